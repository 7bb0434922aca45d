/* shadow_plan — shadow views of the scene's lights (shadow_plan.h). */
#include "shadow_plan.h"

#include <math.h>
#include <string.h>

static prw_dvec3 pick_up(prw_dvec3 dir)
{
    return fabs(dir.y) < 0.99 ? prw_v3(0, 1, 0) : prw_v3(1, 0, 0);
}

static prw_dmat4 persp(prw_dvec3 pos, prw_dvec3 dir, prw_dvec3 up, double half_fov)
{
    double t = tan(half_fov);
    prw_dmat4 v = prw_dm4_look_at(pos, prw_v3_add(pos, dir), up);
    return prw_dm4_mul(prw_dm4_frustum_rev_inf(-t, t, -t, t, 0.02), v);
}

static void plan_lights(const prw_scene *s, const prw_emissive_lights *em, prw_shadow_plan *plan)
{
    uint32_t n = 0;
    for (uint32_t i = 0; i < s->light_count && n < PRW_MAX_LIGHTS; i++, n++) {
        const prw_light *l = &s->lights[i];
        const double *m = s->nodes[l->node].world.m;
        prw_plan_light *o = &plan->lights[n];
        memset(o, 0, sizeof *o);
        o->type = l->type;
        o->pos = o->shadow_pos = prw_v3(m[12], m[13], m[14]);
        o->dir = prw_v3_norm(prw_v3(-m[8], -m[9], -m[10]));
        o->half_u = prw_v3_scale(prw_v3_norm(prw_v3(m[0], m[1], m[2])), 0.5 * l->width);
        o->half_v = prw_v3_scale(prw_v3_norm(prw_v3(m[4], m[5], m[6])), 0.5 * l->height);
        o->shape = PRW_AREA_RECT;
        for (int c = 0; c < 3; c++) o->radiance[c] = (float)(l->color[c] * l->intensity);
        o->range = l->range;
        o->inner_cone = l->inner_cone;
        o->outer_cone = l->outer_cone;
        o->cast_shadows = l->cast_shadows;
        o->emissive = -1;
    }
    uint32_t scene_lights = n;
    for (uint32_t i = 0; em && i < em->count && n < PRW_MAX_LIGHTS; i++, n++) {
        const prw_area_light *a = &em->lights[i];
        prw_plan_light *o = &plan->lights[n];
        memset(o, 0, sizeof *o);
        o->type = PRW_LIGHT_RECT;
        /* in front of the emitting surface, so that surface is not lit by its own light */
        double size = fmax(prw_v3_len(a->half_u), prw_v3_len(a->half_v));
        prw_dvec3 lift = prw_v3_scale(a->normal, 1e-4 * size);
        o->pos = prw_v3_add(a->centre, lift);
        o->shadow_pos = prw_v3_add(a->centroid, lift);
        o->dir = a->normal;
        o->half_u = a->half_u;
        o->half_v = a->half_v;
        o->shape = (int)a->shape;
        for (int c = 0; c < 3; c++) o->radiance[c] = a->radiance[c];
        o->cast_shadows = true;
        o->emissive = (int)i;
    }
    plan->light_count = n;
    plan->emissive_count = n - scene_lights;
}

void prw_shadow_plan_make(const prw_scene *s, prw_shadow_plan *plan) { prw_shadow_plan_make_with(s, NULL, plan); }

void prw_shadow_plan_make_with(const prw_scene *s, const prw_emissive_lights *em, prw_shadow_plan *plan)
{
    plan_lights(s, em, plan);
    prw_shadow_view *out = plan->views;
    int *light_first = plan->light_first;
    uint32_t n = 0;
    for (int i = 0; i < PRW_MAX_LIGHTS; i++) light_first[i] = -1;
    prw_dvec3 bmin = s->has_bounds ? s->bounds_min : prw_v3(-1, -1, -1);
    prw_dvec3 bmax = s->has_bounds ? s->bounds_max : prw_v3(1, 1, 1);
    prw_dvec3 centre = prw_v3_scale(prw_v3_add(bmin, bmax), 0.5);
    double radius = 0.5 * prw_v3_len(prw_v3_sub(bmax, bmin)) + 1e-3;
    for (uint32_t i = 0; i < plan->light_count; i++) {
        const prw_plan_light *l = &plan->lights[i];
        light_first[i] = -1;
        uint32_t need = l->type == PRW_LIGHT_POINT ? 6 : 1;
        if (!l->cast_shadows || n + need > PRW_MAX_SHADOW_VIEWS) continue;
        prw_dvec3 pos = l->shadow_pos;
        prw_dvec3 dir = l->dir;
        light_first[i] = (int)n;
        if (l->type == PRW_LIGHT_POINT) {
            static const double axes[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
            for (int f = 0; f < 6; f++) {
                prw_dvec3 d = prw_v3(axes[f][0], axes[f][1], axes[f][2]);
                out[n].light = (int)i;
                out[n].view_proj = persp(pos, d, pick_up(d), 0.25 * PRW_PI);
                out[n].texel_per_unit = 2.0;
                n++;
            }
        } else if (l->type == PRW_LIGHT_DIRECTIONAL) {
            prw_dvec3 eye = prw_v3_sub(centre, prw_v3_scale(dir, 2.0 * radius));
            prw_dmat4 v = prw_dm4_look_at(eye, centre, pick_up(dir));
            out[n].light = (int)i;
            out[n].view_proj = prw_dm4_mul(prw_dm4_ortho_rev(-radius, radius, -radius, radius, 0.0, 4.0 * radius), v);
            out[n].texel_per_unit = 2.0 * radius;
            n++;
        } else {
            /* spot: its outer cone; rect: 150 degrees of its hemisphere (grazing directions unshadowed) */
            double half = l->type == PRW_LIGHT_SPOT ? fmin(l->outer_cone + 0.05, 1.45) : 75.0 * PRW_PI / 180.0;
            out[n].light = (int)i;
            out[n].view_proj = persp(pos, dir, pick_up(dir), half);
            out[n].texel_per_unit = 2.0 * tan(half);
            n++;
        }
    }
    plan->count = n;
    uint32_t nl = plan->light_count, k = 0;
    for (int c = 0; c < PRW_LIGHT_CLASSES; c++) {
        plan->class_count[c] = 0;
        for (uint32_t i = 0; i < nl; i++) {
            bool rect = plan->lights[i].type == PRW_LIGHT_RECT, shadowed = light_first[i] >= 0;
            int cls = rect ? (shadowed ? PRW_LIGHT_CLASS_RECT_SHADOWED : PRW_LIGHT_CLASS_RECT)
                           : !shadowed ? PRW_LIGHT_CLASS_PUNCTUAL
                           : plan->lights[i].type == PRW_LIGHT_POINT ? PRW_LIGHT_CLASS_POINT_SHADOWED
                                                                 : PRW_LIGHT_CLASS_PUNCTUAL_SHADOWED;
            if (cls != c) continue;
            plan->slot_light[k++] = i;
            plan->class_count[c]++;
        }
    }
    plan->slot_count = k;
}

