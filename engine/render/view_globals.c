/* view_globals — the per-view uniform block (view_globals.h). */
#include "view_globals.h"

#include <math.h>
#include <string.h>

static prw_dmat4 translation(prw_dvec3 o)
{
    prw_dmat4 t = prw_dm4_identity();
    t.m[12] = o.x;
    t.m[13] = o.y;
    t.m[14] = o.z;
    return t;
}

prw_mat4 prw_view_globals_view_proj(const prw_view *v, prw_dvec3 origin)
{
    return prw_m4_from_d(prw_dm4_mul(prw_view_proj(v), prw_dm4_mul(v->view, translation(origin))));
}

void prw_view_globals_fill(const prw_scene *s, const prw_shadow_plan *plan, uint32_t shadow_size,
                           const prw_view *v, prw_dvec3 o, prw_gpu_globals *g)
{
    (void)s; /* the lights come from the plan */
    prw_dmat4 to_origin = translation(o);
    memset(g, 0, sizeof *g);
    g->view_proj = prw_view_globals_view_proj(v, o);
    g->eye_rel[0] = (float)(v->eye.x - o.x);
    g->eye_rel[1] = (float)(v->eye.y - o.y);
    g->eye_rel[2] = (float)(v->eye.z - o.z);
    g->origin[0] = (float)o.x, g->origin[1] = (float)o.y, g->origin[2] = (float)o.z;
    uint32_t nl = plan->slot_count;
    g->params[0] = (float)nl;
    g->params[1] = (float)shadow_size;
    for (uint32_t k = 0; k < nl; k++) {
        uint32_t i = plan->slot_light[k]; /* slots grouped by shading class (shadow_plan.h) */
        const prw_plan_light *l = &plan->lights[i];
        prw_gpu_light *gl = &g->lights[k];
        gl->pos_type[0] = (float)(l->pos.x - o.x);
        gl->pos_type[1] = (float)(l->pos.y - o.y);
        gl->pos_type[2] = (float)(l->pos.z - o.z);
        gl->pos_type[3] = (float)l->type;
        gl->dir_range[0] = (float)l->dir.x;
        gl->dir_range[1] = (float)l->dir.y;
        gl->dir_range[2] = (float)l->dir.z;
        gl->dir_range[3] = (float)l->range;
        for (int c = 0; c < 3; c++) gl->radiance[c] = l->radiance[c];
        gl->cone_shadow[0] = (float)cos(l->inner_cone);
        gl->cone_shadow[1] = (float)cos(l->outer_cone);
        int first = plan->light_first[i];
        gl->cone_shadow[2] = (float)first;
        gl->cone_shadow[3] = first < 0 ? 0.0f : (l->type == PRW_LIGHT_POINT ? 6.0f : 1.0f);
        gl->axis_u[0] = (float)l->half_u.x, gl->axis_u[1] = (float)l->half_u.y, gl->axis_u[2] = (float)l->half_u.z;
        gl->axis_v[0] = (float)l->half_v.x, gl->axis_v[1] = (float)l->half_v.y, gl->axis_v[2] = (float)l->half_v.z;
        gl->axis_u[3] = (float)l->shape; /* lights.glsl rect_corners: rect, parallelogram or triangle */
        if (first >= 0) gl->shadow[0] = (float)(plan->views[first].texel_per_unit / shadow_size);
    }
    for (uint32_t k = 0; k < plan->count; k++)
        g->shadow_mats[k] = prw_m4_from_d(prw_dm4_mul(plan->views[k].view_proj, to_origin));
}
