/* gi-room (assets/scenes/gi-room.json, -sky.json), the yardstick of issue 16, and the light-path
 * filters of its GI terms:
 *  - the manifest is the room of the demo as of 46f70f0 (a frozen copy of that builder below, so the
 *    demo may grow without moving this check) plus the mirror and the floor's roughness 0.2;
 *  - the committed sky map is the formula of gi_sky.h;
 *  - per-sample sums of the filters with one seed (to fixed-point rounding), per pixel:
 *    direct + indirect-diffuse-last + indirect-glossy-last = all, indirect-diffuse-last +
 *    indirect-glossy-last = indirect, environment-direct = depth:1 - depth:1 without the environment;
 *  - the filtered terms with independent seeds sum to the unfiltered reference within 3 sigma. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "gi_sky.h"
#include "prw_image.h"
#include "ref_scenes.h"

#define GI_ROOM PRW_SOURCE_DIR "/assets/scenes/gi-room.json"
#define GI_ROOM_SKY PRW_SOURCE_DIR "/assets/scenes/gi-room-sky.json"
#define GI_SKY_EXR PRW_SOURCE_DIR "/assets/scenes/gi-room-sky.exr"

/* ---- the demo room as assets/prw_demo.c built it at commit 46f70f0 (frozen copy) ---- */

static int demo_material(prw_scene *s, const char *name, float r, float g, float b, float metallic, float roughness)
{
    prw_material m = prw_material_default();
    snprintf(m.name, sizeof m.name, "%s", name);
    m.base_color[0] = r;
    m.base_color[1] = g;
    m.base_color[2] = b;
    m.base_color[3] = 1.0f;
    m.metallic = metallic;
    m.roughness = roughness;
    return prw_scene_add_material(s, &m);
}

static bool demo_46f70f0(prw_scene *s, prw_error *e)
{
    int wall = demo_material(s, "white plaster", 0.70f, 0.70f, 0.68f, 0.0f, 0.9f);
    int floor_m = demo_material(s, "oak floor", 0.45f, 0.30f, 0.18f, 0.0f, 0.55f);
    int red = demo_material(s, "red matte", 0.60f, 0.08f, 0.06f, 0.0f, 0.85f);
    int gold = demo_material(s, "gold", 1.00f, 0.78f, 0.34f, 1.0f, 0.30f);
    int blue = demo_material(s, "blue plastic", 0.08f, 0.18f, 0.60f, 0.0f, 0.25f);
    int grey = demo_material(s, "grey concrete", 0.35f, 0.35f, 0.35f, 0.0f, 0.95f);
    if (prw_scene_add_box(s, "room walls", prw_v3(-3, 0, -2.5), prw_v3(3, 3, 2.5), wall, true, e) < 0) return false;
    if (prw_scene_add_quad(s, "floor", prw_v3(0, 0.001, 0), prw_v3(0, 0, 2.5), prw_v3(3, 0, 0), floor_m, e) < 0)
        return false;
    if (prw_scene_add_box(s, "red box", prw_v3(-0.2, 0, -1.6), prw_v3(0.6, 0.8, -0.8), red, false, e) < 0) return false;
    if (prw_scene_add_sphere(s, "gold sphere", prw_v3(0.2, 1.1, -1.2), 0.3, 48, 24, gold, e) < 0) return false;
    if (prw_scene_add_sphere(s, "blue sphere", prw_v3(1.2, 0.35, 0.6), 0.35, 48, 24, blue, e) < 0) return false;
    if (prw_scene_add_box(s, "column", prw_v3(-2.2, 0, -2.2), prw_v3(-1.7, 3, -1.7), grey, false, e) < 0) return false;

    prw_light window = {0};
    snprintf(window.name, sizeof window.name, "window");
    window.type = PRW_LIGHT_RECT;
    window.color[0] = window.color[1] = window.color[2] = 1.0f;
    window.intensity = 2000.0;
    window.width = 1.6;
    window.height = 1.2;
    window.cast_shadows = true;
    prw_node wn = prw_node_look_at("window light", prw_v3(2.99, 1.6, 0), prw_v3(0, 1.6, 0), prw_v3(0, 1, 0));
    window.node = prw_scene_add_node(s, &wn);
    s->nodes[window.node].light = prw_scene_add_light(s, &window);

    prw_light spot = {0};
    snprintf(spot.name, sizeof spot.name, "ceiling spot");
    spot.type = PRW_LIGHT_SPOT;
    spot.color[0] = 1.0f;
    spot.color[1] = 0.85f;
    spot.color[2] = 0.65f;
    spot.intensity = 1500.0;
    spot.inner_cone = 0.35;
    spot.outer_cone = 0.6;
    spot.cast_shadows = true;
    prw_node sn = prw_node_look_at("spot light", prw_v3(-0.5, 2.9, -0.8), prw_v3(0.0, 0.0, -1.0), prw_v3(0, 0, -1));
    spot.node = prw_scene_add_node(s, &sn);
    s->nodes[spot.node].light = prw_scene_add_light(s, &spot);

    prw_camera cam = {0};
    snprintf(cam.name, sizeof cam.name, "main");
    cam.yfov = 60.0 * PRW_PI / 180.0;
    cam.znear = 0.05;
    cam.ev100 = 7.0;
    prw_node cn = prw_node_look_at("camera main", prw_v3(-2.6, 1.5, 2.2), prw_v3(0.6, 0.9, -0.8), prw_v3(0, 1, 0));
    cam.node = prw_scene_add_node(s, &cn);
    s->nodes[cam.node].camera = prw_scene_add_camera(s, &cam);

    snprintf(cam.name, sizeof cam.name, "window");
    prw_node cw = prw_node_look_at("camera window", prw_v3(-2.5, 1.4, -1.0), prw_v3(3.0, 1.4, 0.5), prw_v3(0, 1, 0));
    cam.node = prw_scene_add_node(s, &cw);
    s->nodes[cam.node].camera = prw_scene_add_camera(s, &cam);
    prw_scene_update(s);
    return true;
}

/* ---- scene comparison ---- */

static bool material_same(const prw_material *a, const prw_material *b)
{
    bool same = strcmp(a->name, b->name) == 0 && a->kind == b->kind && a->metallic == b->metallic &&
                a->roughness == b->roughness && a->specular == b->specular && a->double_sided == b->double_sided &&
                a->base_color_tex == b->base_color_tex && a->metal_rough_tex == b->metal_rough_tex &&
                a->normal_tex == b->normal_tex && a->emissive_tex == b->emissive_tex &&
                a->alpha_mode == b->alpha_mode && a->clearcoat == b->clearcoat;
    for (int c = 0; c < 4; c++) same = same && a->base_color[c] == b->base_color[c];
    for (int c = 0; c < 3; c++) same = same && a->emission[c] == b->emission[c];
    return same;
}

/* The node drawing mesh index m (-1: none). */
static int node_of_mesh(const prw_scene *s, uint32_t m)
{
    for (uint32_t n = 0; n < s->node_count; n++) {
        int g = s->nodes[n].mesh_group;
        if (g >= 0 && m >= s->groups[g].first && m < s->groups[g].first + s->groups[g].count) return (int)n;
    }
    return -1;
}

static int mesh_named(const prw_scene *s, const char *name)
{
    for (uint32_t m = 0; m < s->mesh_count; m++)
        if (strcmp(s->meshes[m].name, name) == 0) return (int)m;
    return -1;
}

/* World-space vertices and normals, indices and material of mesh `name` agree (1e-9 m). */
static void check_mesh(const prw_scene *a, const prw_scene *b, const char *name)
{
    int ma = mesh_named(a, name), mb = mesh_named(b, name);
    CHECK_MSG(ma >= 0 && mb >= 0, "mesh '%s' missing (%d, %d)", name, ma, mb);
    if (ma < 0 || mb < 0) return;
    const prw_mesh *x = &a->meshes[ma], *y = &b->meshes[mb];
    int na = node_of_mesh(a, (uint32_t)ma), nb = node_of_mesh(b, (uint32_t)mb);
    CHECK(na >= 0 && nb >= 0);
    CHECK_MSG(x->vertex_count == y->vertex_count && x->index_count == y->index_count, "mesh '%s': counts differ", name);
    CHECK_MSG(material_same(&a->materials[x->material], &b->materials[y->material]), "mesh '%s': material differs", name);
    if (na < 0 || nb < 0 || x->vertex_count != y->vertex_count || x->index_count != y->index_count) return;
    CHECK_MSG(memcmp(x->indices, y->indices, x->index_count * sizeof *x->indices) == 0, "mesh '%s': indices", name);
    double worst = 0, worst_n = 0;
    for (uint32_t v = 0; v < x->vertex_count; v++) {
        const float *p = x->positions + 3 * v, *q = y->positions + 3 * v;
        prw_dvec3 pa = prw_dm4_point(a->nodes[na].world, prw_v3(p[0], p[1], p[2]));
        prw_dvec3 pb = prw_dm4_point(b->nodes[nb].world, prw_v3(q[0], q[1], q[2]));
        worst = fmax(worst, prw_v3_len(prw_v3_sub(pa, pb)));
        p = x->normals + 3 * v, q = y->normals + 3 * v;
        prw_dvec3 ua = prw_dm4_dir(a->nodes[na].world, prw_v3(p[0], p[1], p[2]));
        prw_dvec3 ub = prw_dm4_dir(b->nodes[nb].world, prw_v3(q[0], q[1], q[2]));
        worst_n = fmax(worst_n, prw_v3_len(prw_v3_sub(ua, ub)));
    }
    CHECK_MSG(worst <= 1e-9 && worst_n <= 1e-9, "mesh '%s': vertices differ by %g m, normals by %g", name, worst,
              worst_n);
}

static prw_dvec3 column(prw_dmat4 m, int c) { return prw_v3(m.m[4 * c], m.m[4 * c + 1], m.m[4 * c + 2]); }

static double vdist(prw_dvec3 a, prw_dvec3 b) { return prw_v3_len(prw_v3_sub(a, b)); }

static void check_lights_cameras(const prw_scene *a, const prw_scene *b)
{
    CHECK(a->light_count == b->light_count && a->camera_count == b->camera_count);
    for (uint32_t i = 0; i < a->light_count && i < b->light_count; i++) {
        const prw_light *x = &a->lights[i], *y = &b->lights[i];
        prw_dmat4 wa = a->nodes[x->node].world, wb = b->nodes[y->node].world;
        bool same = strcmp(x->name, y->name) == 0 && x->type == y->type && x->intensity == y->intensity &&
                    x->range == y->range && x->width == y->width && x->height == y->height &&
                    x->cast_shadows == y->cast_shadows && fabs(x->inner_cone - y->inner_cone) <= 1e-12 &&
                    fabs(x->outer_cone - y->outer_cone) <= 1e-12;
        for (int c = 0; c < 3; c++) same = same && x->color[c] == y->color[c];
        /* position and emission axis -Z; a rect light's x / y axes too (a spot's roll does not matter) */
        double err = fmax(vdist(column(wa, 3), column(wb, 3)), vdist(column(wa, 2), column(wb, 2)));
        if (x->type == PRW_LIGHT_RECT) err = fmax(err, fmax(vdist(column(wa, 0), column(wb, 0)), vdist(column(wa, 1), column(wb, 1))));
        CHECK_MSG(same && err <= 1e-9, "light %u ('%s'): differs (placement %g)", i, x->name, err);
    }
    for (uint32_t i = 0; i < a->camera_count && i < b->camera_count; i++) {
        const prw_camera *x = &a->cameras[i], *y = &b->cameras[i];
        prw_dmat4 wa = a->nodes[x->node].world, wb = b->nodes[y->node].world;
        double err = 0;
        for (int k = 0; k < 16; k++) err = fmax(err, fabs(wa.m[k] - wb.m[k]));
        CHECK_MSG(strcmp(x->name, y->name) == 0 && x->yfov == y->yfov && x->znear == y->znear && x->aspect == y->aspect &&
                      x->ev100 == y->ev100 && err <= 1e-9,
                  "camera %u ('%s') differs (placement %g)", i, x->name, err);
    }
}

static void test_manifest_matches_demo(void)
{
    prw_scene *m = prw_scene_create(), *d = prw_scene_create();
    prw_error e = {{0}};
    CHECK_OK(prw_scene_load_manifest(m, GI_ROOM, &e), &e);
    CHECK_OK(demo_46f70f0(d, &e), &e);
    /* the two additions of issue 16: a mirror on the back wall and a floor of roughness 0.2 */
    int mirror = mesh_named(m, "mirror"), floor_m = mesh_named(m, "floor");
    CHECK(mirror >= 0 && floor_m >= 0);
    if (mirror >= 0 && floor_m >= 0) {
        prw_material *fm = &m->materials[m->meshes[floor_m].material];
        const prw_material *mm = &m->materials[m->meshes[mirror].material];
        CHECK(mm->metallic == 1 && mm->roughness == 0);
        CHECK(fm->roughness == 0.2f);
        fm->roughness = 0.55f; /* undone, the rest must be the demo's */
    }
    CHECK_MSG(m->mesh_count == d->mesh_count + 1, "meshes: %u, demo %u + mirror", m->mesh_count, d->mesh_count);
    for (uint32_t i = 0; i < d->mesh_count; i++) check_mesh(m, d, d->meshes[i].name);
    check_lights_cameras(m, d);
    CHECK(!m->environment.present);
    prw_scene_destroy(m);
    prw_scene_destroy(d);
}

/* Whether world point p (on the plane x = 3) is covered by a triangle of s lying in that plane. */
static bool wall_covers(const prw_scene *s, prw_dvec3 p)
{
    for (uint32_t m = 0; m < s->mesh_count; m++) {
        int n = node_of_mesh(s, m);
        const prw_mesh *me = &s->meshes[m];
        for (uint32_t t = 0; n >= 0 && t < me->index_count / 3; t++) {
            prw_dvec3 v[3];
            for (int k = 0; k < 3; k++) {
                const float *q = me->positions + 3 * me->indices[3 * t + k];
                v[k] = prw_dm4_point(s->nodes[n].world, prw_v3(q[0], q[1], q[2]));
            }
            if (fabs(v[0].x - 3) > 1e-9 || fabs(v[1].x - 3) > 1e-9 || fabs(v[2].x - 3) > 1e-9) continue;
            /* 2-D (z, y) point in triangle, either winding */
            double d[3];
            for (int k = 0; k < 3; k++) {
                prw_dvec3 a = v[k], b = v[(k + 1) % 3];
                d[k] = (b.z - a.z) * (p.y - a.y) - (b.y - a.y) * (p.z - a.z);
            }
            if ((d[0] >= 0 && d[1] >= 0 && d[2] >= 0) || (d[0] <= 0 && d[1] <= 0 && d[2] <= 0)) return true;
        }
    }
    return false;
}

/* gi-room-sky is gi-room with the window light replaced by an opening of the same rectangle in the
 * wall: the same objects (all but the wall box), spot and cameras; the wall x = 3 covered exactly
 * outside the window light's rectangle (sampled on a 5 cm grid, off the edges). */
static void test_sky_variant_matches(void)
{
    prw_scene *room = prw_scene_create(), *sky = prw_scene_create();
    prw_error e = {{0}};
    CHECK_OK(prw_scene_load_manifest(room, GI_ROOM, &e), &e);
    CHECK_OK(prw_scene_load_manifest(sky, GI_ROOM_SKY, &e), &e);
    for (uint32_t i = 0; i < room->mesh_count; i++)
        if (strcmp(room->meshes[i].name, "room walls") != 0) check_mesh(sky, room, room->meshes[i].name);
    CHECK(room->light_count == 2 && sky->light_count == 1 && room->lights[0].type == PRW_LIGHT_RECT);
    if (room->light_count == 2 && sky->light_count == 1) {
        /* compare the spot and cameras through a copy of the room without its window light */
        prw_scene tmp = *room;
        tmp.lights = room->lights + 1;
        tmp.light_count = 1;
        check_lights_cameras(sky, &tmp);
        const prw_light *w = &room->lights[0];
        prw_dmat4 wm = room->nodes[w->node].world;
        prw_dvec3 c = column(wm, 3), ax = column(wm, 0), ay = column(wm, 1);
        int wrong = 0, n = 0;
        for (double y = 0.025; y < 3; y += 0.05)
            for (double z = -2.475; z < 2.5; z += 0.05, n++) {
                prw_dvec3 rel = prw_v3(3 - c.x, y - c.y, z - c.z);
                double a = prw_v3_dot(rel, ax) / (w->width / 2), b = prw_v3_dot(rel, ay) / (w->height / 2);
                bool in_window = fabs(a) < 1 && fabs(b) < 1;
                if (wall_covers(sky, prw_v3(3, y, z)) == in_window) wrong++;
            }
        CHECK_MSG(wrong == 0, "gi-room-sky: %d of %d points of the wall x = 3 disagree with the window light", wrong, n);
    }
    prw_scene_destroy(room);
    prw_scene_destroy(sky);
}

/* The committed map is the formula (to float rounding of the libm in use). */
static void test_sky_map(void)
{
    prw_image file = {0}, gen = {0};
    prw_error e = {{0}};
    CHECK_OK(prw_exr_read(GI_SKY_EXR, NULL, &file, &e), &e);
    CHECK_OK(gi_sky_image(&gen, &e), &e);
    if (file.rgba && gen.rgba) {
        CHECK(file.width == gen.width && file.height == gen.height);
        double worst = 0;
        for (size_t i = 0; file.width == gen.width && file.height == gen.height && i < 4 * (size_t)gen.width * gen.height;
             i++)
            worst = fmax(worst, fabs(file.rgba[i] - gen.rgba[i]) / fmax(fabs(gen.rgba[i]), 1.0));
        CHECK_MSG(worst <= 1e-5, "gi-room-sky.exr differs from gi_sky.h by %g (regenerate: gi_sky %s)", worst,
                  "assets/scenes/gi-room-sky.exr");
    }
    /* the scene reads it */
    prw_scene *s = prw_scene_create();
    CHECK_OK(prw_scene_load_manifest(s, GI_ROOM_SKY, &e), &e);
    CHECK(s->environment.present && s->environment.file[0]);
    prw_scene_destroy(s);
    prw_image_free(&file);
    prw_image_free(&gen);
}

/* ---- filters ---- */

static prw_ref_filter filter(const char *name)
{
    prw_ref_filter f = {PRW_REF_ALL, 0};
    prw_error e = {{0}};
    bool ok = prw_ref_filter_parse(name, &f, &e);
    CHECK_MSG(ok, "%s", e.msg);
    char back[64];
    prw_ref_filter_name(f, back, sizeof back);
    CHECK_MSG(strcmp(back, name) == 0, "%s -> %s", name, back);
    return f;
}

static bool render(prw_ref_renderer *r, const prw_view *v, uint64_t spp, uint64_t seed, const char *f,
                   prw_ref_acc *acc)
{
    prw_error e = {{0}};
    prw_ref_desc d = {.s0 = 0, .s1 = spp, .seed = seed, .filter = filter(f)};
    bool ok = prw_ref_render(r, v, &d, acc, NULL, &e);
    CHECK_MSG(ok, "%s: %s", f, e.msg);
    return ok;
}

/* sum over terms (signs +-1) minus ref, per pixel and channel, in fixed-point units: the worst excess
 * over the rounding allowance (4 units per sample per term, plus 1e-12 relative; <= 0: the identity
 * holds), the worst difference itself (*worst_diff) and the image totals. */
static double identity_excess(const prw_ref_acc *ref, const prw_ref_acc *const *terms, const int *sign, int n,
                              double *tot_ref, double *tot_terms, double *worst_diff)
{
    size_t count = 3 * (size_t)ref->width * ref->height;
    double worst = -INFINITY, allow = 4.0 * (double)(ref->s1 - ref->s0) * (n + 1);
    *tot_ref = *tot_terms = *worst_diff = 0;
    for (size_t i = 0; i < count; i++) {
        prw_ref_fixed sum = 0;
        for (int k = 0; k < n; k++) sum += sign[k] * terms[k]->sum[i];
        double diff = fabs((double)(sum - ref->sum[i]));
        *worst_diff = fmax(*worst_diff, diff);
        worst = fmax(worst, diff - allow - 1e-12 * fabs((double)ref->sum[i]));
        *tot_ref += (double)ref->sum[i] / PRW_REF_SUM_SCALE;
        *tot_terms += (double)sum / PRW_REF_SUM_SCALE;
    }
    return worst;
}

static double acc_total(const prw_ref_acc *a)
{
    double t = 0;
    for (size_t i = 0; i < 3 * (size_t)a->width * a->height; i++) t += (double)a->sum[i] / PRW_REF_SUM_SCALE;
    return t;
}

/* One seed, per pixel: the sums of prw_reference.h, on gi-room-sky (environment map, spot, mirror,
 * glossy floor) and environment-direct on gi-room (no environment: zero). */
static void test_filters_exact(void)
{
    prw_scene *s = prw_scene_create(), *nosky = prw_scene_create(), *room = prw_scene_create();
    prw_error e = {{0}};
    CHECK_OK(prw_scene_load_manifest(s, GI_ROOM_SKY, &e), &e);
    CHECK_OK(prw_scene_load_manifest(nosky, GI_ROOM_SKY, &e), &e);
    CHECK_OK(prw_scene_load_manifest(room, GI_ROOM, &e), &e);
    nosky->environment.present = false;
    prw_view v;
    CHECK_OK(prw_ref_view_for_camera(s, "main", 32, 18, &v, &e), &e);
    prw_ref_renderer *r = NULL, *rn = NULL, *rr = NULL;
    CHECK_OK(prw_ref_create(s, v.eye, 0, &r, &e), &e);
    CHECK_OK(prw_ref_create(nosky, v.eye, 0, &rn, &e), &e);
    CHECK_OK(prw_ref_create(room, v.eye, 0, &rr, &e), &e);
    const uint64_t spp = (uint64_t)prw_test_scale(8, 4), seed = 3;
    enum { ALL, DIR, IND, IDL, IGL, D1, ENV, D1N, ENVR, N };
    prw_ref_acc a[N];
    memset(a, 0, sizeof a);
    bool ok = r && rn && rr && render(r, &v, spp, seed, "all", &a[ALL]) && render(r, &v, spp, seed, "direct", &a[DIR]) &&
              render(r, &v, spp, seed, "indirect", &a[IND]) &&
              render(r, &v, spp, seed, "indirect-diffuse-last", &a[IDL]) &&
              render(r, &v, spp, seed, "indirect-glossy-last", &a[IGL]) &&
              render(r, &v, spp, seed, "depth:1", &a[D1]) && render(r, &v, spp, seed, "environment-direct", &a[ENV]) &&
              render(rn, &v, spp, seed, "depth:1", &a[D1N]) && render(rr, &v, spp, seed, "environment-direct", &a[ENVR]);
    if (ok) {
        double tr, tt, wd;
        const prw_ref_acc *t1[] = {&a[DIR], &a[IDL], &a[IGL]};
        const int plus3[] = {1, 1, 1}, pm[] = {1, -1};
        double x = identity_excess(&a[ALL], t1, plus3, 3, &tr, &tt, &wd);
        printf("  direct + indirect-diffuse-last + indirect-glossy-last = %.9g, all %.9g (worst pixel: %.3g units of "
               "2^-32 cd/m^2)\n", tt, tr, wd);
        CHECK_MSG(x <= 0, "direct + indirect-diffuse-last + indirect-glossy-last != all: %g fixed-point units", x);
        const prw_ref_acc *t2[] = {&a[IDL], &a[IGL]};
        x = identity_excess(&a[IND], t2, plus3, 2, &tr, &tt, &wd);
        printf("  indirect-diffuse-last + indirect-glossy-last = %.9g, indirect %.9g (worst pixel: %.3g units)\n", tt,
               tr, wd);
        CHECK_MSG(x <= 0, "indirect-diffuse-last + indirect-glossy-last != indirect: %g units", x);
        const prw_ref_acc *t3[] = {&a[D1], &a[D1N]};
        x = identity_excess(&a[ENV], t3, pm, 2, &tr, &tt, &wd);
        printf("  environment-direct %.9g, depth:1 - depth:1 without the sky %.9g (worst pixel: %.3g units)\n", tr,
               tt, wd);
        CHECK_MSG(x <= 0, "environment-direct != depth:1 - depth:1 without the environment: %g units", x);
        double tdl = acc_total(&a[IDL]), tgl = acc_total(&a[IGL]), tenv = acc_total(&a[ENV]);
        printf("  indirect-diffuse-last %.6g, indirect-glossy-last %.6g, environment-direct %.6g, all %.6g\n", tdl, tgl,
               tenv, acc_total(&a[ALL]));
        CHECK(tdl > 0 && tgl > 0 && tenv > 0); /* each term carries light on this scene */
        bool zero = true;
        for (size_t i = 0; i < 3 * (size_t)a[ENVR].width * a[ENVR].height; i++) zero = zero && a[ENVR].sum[i] == 0;
        CHECK_MSG(zero, "environment-direct of a scene without an environment is not 0");
    }
    for (int k = 0; k < N; k++) prw_ref_acc_free(&a[k]);
    prw_ref_destroy(r);
    prw_ref_destroy(rn);
    prw_ref_destroy(rr);
    prw_scene_destroy(s);
    prw_scene_destroy(nosky);
    prw_scene_destroy(room);
}

/* Independent seeds: direct + indirect-diffuse-last + indirect-glossy-last against all, image means
 * per channel within 3 sigma (pixels are independent; sigma from the per-pixel variances), and at
 * most 1 % of the pixel values beyond their own 3 sigma (a Gaussian: 0.27 %). */
static void terms_sum(const char *path, uint64_t spp)
{
    prw_scene *s = prw_scene_create();
    prw_error e = {{0}};
    CHECK_OK(prw_scene_load_manifest(s, path, &e), &e);
    prw_view v;
    CHECK_OK(prw_ref_view_for_camera(s, "main", 32, 18, &v, &e), &e);
    prw_ref_renderer *r = NULL;
    CHECK_OK(prw_ref_create(s, v.eye, 0, &r, &e), &e);
    static const char *const names[] = {"all", "direct", "indirect-diffuse-last", "indirect-glossy-last"};
    double mean[4][3] = {{0}}, var[4][3] = {{0}};
    float *pm[4] = {NULL}, *pv[4] = {NULL};
    size_t n = (size_t)v.width * v.height;
    bool ok = r != NULL;
    for (int k = 0; k < 4 && ok; k++) {
        prw_ref_acc a = {0};
        ok = render(r, &v, spp, 1000 + (uint64_t)k, names[k], &a) && prw_ref_acc_images(&a, &pm[k], &pv[k], &e);
        for (size_t i = 0; ok && i < n; i++)
            for (int c = 0; c < 3; c++) {
                mean[k][c] += pm[k][4 * i + c] / (double)n;
                var[k][c] += pv[k][4 * i + c] / ((double)n * n);
            }
        prw_ref_acc_free(&a);
    }
    /* per pixel: how many channel values lie beyond 3 sigma (a Gaussian: 0.27 %) */
    int beyond = 0;
    for (size_t i = 0; ok && i < n; i++)
        for (int c = 0; c < 3; c++) {
            size_t j = 4 * i + c;
            double d = pm[1][j] + pm[2][j] + pm[3][j] - pm[0][j], sg = sqrt(pv[0][j] + pv[1][j] + pv[2][j] + pv[3][j]);
            if (fabs(d) > 3 * sg) beyond++;
        }
    printf("  %s: per pixel and channel beyond 3 sigma: %d of %zu\n", strrchr(path, '/') + 1, beyond, 3 * n);
    CHECK_MSG(beyond <= (int)(3 * n / 100), "%s: %d of %zu pixel values beyond 3 sigma (more than 1 %%)", path, beyond,
              3 * n);
    for (int k = 0; k < 4; k++) free(pm[k]), free(pv[k]);
    for (int c = 0; c < 3 && ok; c++) {
        double sum = mean[1][c] + mean[2][c] + mean[3][c], sigma = sqrt(var[0][c] + var[1][c] + var[2][c] + var[3][c]);
        printf("  %s ch%d: all %.5g, direct %.5g + ind-diffuse %.5g + ind-glossy %.5g = %.5g, diff %.3g sigma "
               "(sigma %.3g)\n", strrchr(path, '/') + 1, c, mean[0][c], mean[1][c], mean[2][c], mean[3][c], sum,
               (sum - mean[0][c]) / sigma, sigma);
        CHECK_MSG(fabs(sum - mean[0][c]) <= 3 * sigma, "%s channel %d: terms %g vs all %g: more than 3 sigma (%g)", path,
                  c, sum, mean[0][c], sigma);
        CHECK(mean[2][c] > 0 && mean[3][c] > 0);
    }
    prw_ref_destroy(r);
    prw_scene_destroy(s);
}

static void test_terms_sum(void)
{
    terms_sum(GI_ROOM, (uint64_t)prw_test_scale(256, 8));
    terms_sum(GI_ROOM_SKY, (uint64_t)prw_test_scale(256, 8));
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"manifest_matches_demo", test_manifest_matches_demo},
        {"sky_variant_matches", test_sky_variant_matches},
        {"sky_map", test_sky_map},
        {"filters_exact", test_filters_exact},
        {"terms_sum", test_terms_sum},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
