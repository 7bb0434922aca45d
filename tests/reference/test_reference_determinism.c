/* Determinism (1 vs 2 threads bit-identical; tiles x sample batches merged == one render, through
 * .acc files) and light-path filters (direct + indirect == all within 3 sigma; exact splits with the
 * same seed). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "prw_image.h"
#include "ref_scenes.h"

/* A small room with every emitter kind: rect light, point, spot, directional (through nothing:
 * the room is closed, so it only tests the shadow path), an emissive sphere, a glossy metal sphere,
 * a textured-free diffuse box, and a uniform sky outside. */
static prw_scene *room_scene(void)
{
    prw_scene *s = prw_scene_create();
    prw_error e;
    int white = lambert_material(s, "white", 0.7, 0);
    prw_material gm = prw_material_default();
    snprintf(gm.name, sizeof gm.name, "glossy");
    gm.base_color[0] = 0.9f, gm.base_color[1] = 0.6f, gm.base_color[2] = 0.3f;
    gm.metallic = 0.7f;
    gm.roughness = 0.35f;
    int glossy = prw_scene_add_material(s, &gm);
    int lamp = lambert_material(s, "lamp", 0, 40);
    CHECK(prw_scene_add_box(s, "room", prw_v3(-2, 0, -2), prw_v3(2, 2.5, 2), white, true, &e) >= 0);
    CHECK(prw_scene_add_sphere(s, "ball", prw_v3(0.5, 0.5, -0.5), 0.5, 32, 16, glossy, &e) >= 0);
    CHECK(prw_scene_add_sphere(s, "glow", prw_v3(-0.8, 0.3, 0.2), 0.2, 16, 8, lamp, &e) >= 0);
    CHECK(prw_scene_add_box(s, "block", prw_v3(-1.5, 0, -1.5), prw_v3(-0.9, 0.8, -0.9), white, false, &e) >= 0);
    prw_light l;
    memset(&l, 0, sizeof l);
    l.color[0] = l.color[1] = l.color[2] = 1;
    snprintf(l.name, sizeof l.name, "panel");
    l.type = PRW_LIGHT_RECT;
    l.intensity = 300;
    l.width = 0.8, l.height = 0.5;
    add_light_at(s, l, prw_v3(0, 2.45, 0), prw_v3(0, 0, 0), prw_v3(0, 0, 1));
    snprintf(l.name, sizeof l.name, "bulb");
    l.type = PRW_LIGHT_POINT;
    l.intensity = 20;
    l.range = 6;
    add_light_at(s, l, prw_v3(1.2, 1.8, 1.0), prw_v3(0, 0, 0), prw_v3(0, 1, 0));
    snprintf(l.name, sizeof l.name, "spot");
    l.type = PRW_LIGHT_SPOT;
    l.intensity = 60;
    l.range = 0;
    l.inner_cone = 0.3, l.outer_cone = 0.5;
    add_light_at(s, l, prw_v3(-1.5, 2.2, 1.5), prw_v3(0.5, 0.5, -0.5), prw_v3(0, 1, 0));
    snprintf(l.name, sizeof l.name, "sun");
    l.type = PRW_LIGHT_DIRECTIONAL;
    l.intensity = 1000;
    add_light_at(s, l, prw_v3(0, 10, 0), prw_v3(1, 0, 0.5), prw_v3(0, 1, 0));
    s->environment.present = true;
    s->environment.uniform[0] = s->environment.uniform[1] = s->environment.uniform[2] = 100;
    prw_scene_update(s);
    return s;
}

static prw_view room_view(uint32_t w, uint32_t h)
{
    return prw_view_look_at(prw_v3(0.2, 1.3, 1.9), prw_v3(0, 0.6, 0), prw_v3(0, 1, 0), 1.2, 0.05, w, h, 0);
}

static bool render_acc(prw_ref_renderer *r, const prw_view *v, uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1,
                       uint64_t s0, uint64_t s1, uint64_t seed, prw_ref_filter f, int threads, prw_ref_acc *acc)
{
    prw_error e = {{0}};
    prw_ref_desc d = {.x0 = x0, .y0 = y0, .x1 = x1, .y1 = y1, .s0 = s0, .s1 = s1, .seed = seed, .filter = f,
                      .threads = threads};
    bool ok = prw_ref_render(r, v, &d, acc, NULL, &e);
    CHECK_MSG(ok, "%s", e.msg);
    return ok;
}

static bool acc_equal(const prw_ref_acc *a, const prw_ref_acc *b)
{
    if (a->x0 != b->x0 || a->y0 != b->y0 || a->x1 != b->x1 || a->y1 != b->y1) return false;
    size_t n = 3 * (size_t)(a->x1 - a->x0) * (a->y1 - a->y0);
    return memcmp(a->sum, b->sum, n * sizeof *a->sum) == 0 && memcmp(a->sq, b->sq, n * sizeof *a->sq) == 0;
}

static void test_threads(void)
{
    prw_scene *s = room_scene();
    prw_view v = room_view(24, 16);
    prw_error e;
    prw_ref_renderer *r1 = NULL, *r2 = NULL;
    CHECK_OK(prw_ref_create(s, v.eye, 1, &r1, &e), &e);
    CHECK_OK(prw_ref_create(s, v.eye, 2, &r2, &e), &e);
    prw_ref_filter all = {PRW_REF_ALL, 0};
    prw_ref_acc a = {0}, b = {0};
    if (render_acc(r1, &v, 0, 0, 0, 0, 0, 8, 42, all, 1, &a) && render_acc(r2, &v, 0, 0, 0, 0, 0, 8, 42, all, 2, &b))
        CHECK_MSG(acc_equal(&a, &b), "1 and 2 threads differ");
    prw_ref_acc_free(&a);
    prw_ref_acc_free(&b);
    prw_ref_destroy(r1);
    prw_ref_destroy(r2);
    prw_scene_destroy(s);
}

/* Two tiles x two sample batches, written to .acc files, read back and merged == one full render. */
static void test_tiles_merge(void)
{
    prw_scene *s = room_scene();
    prw_view v = room_view(24, 16);
    prw_error e;
    prw_ref_renderer *r = NULL;
    CHECK_OK(prw_ref_create(s, v.eye, 2, &r, &e), &e);
    prw_ref_filter all = {PRW_REF_ALL, 0};
    prw_ref_acc full = {0}, parts[4] = {{0}}, back[4] = {{0}}, merged = {0};
    bool ok = render_acc(r, &v, 0, 0, 0, 0, 0, 8, 7, all, 2, &full);
    const uint32_t tiles[2][4] = {{0, 0, 13, 16}, {13, 0, 24, 16}};
    const uint64_t ranges[2][2] = {{0, 3}, {3, 8}};
    const char *names[4];
    for (int t = 0; t < 2 && ok; t++)
        for (int b = 0; b < 2 && ok; b++) {
            int k = 2 * t + b;
            ok = render_acc(r, &v, tiles[t][0], tiles[t][1], tiles[t][2], tiles[t][3], ranges[b][0], ranges[b][1], 7,
                            all, 1 + b, &parts[k]);
            char name[32];
            snprintf(name, sizeof name, "part%d.acc", k);
            names[k] = prw_test_path(name);
            ok = ok && prw_ref_acc_write(names[k], &parts[k], &e);
            ok = ok && prw_ref_acc_read(names[k], &back[k], &e);
            CHECK_MSG(ok, "%s", e.msg);
        }
    if (ok) {
        /* merge in a scrambled order: integer addition is order-independent */
        const prw_ref_acc *in[4] = {&back[3], &back[0], &back[2], &back[1]};
        const char *nm[4] = {names[3], names[0], names[2], names[1]};
        CHECK_OK(prw_ref_acc_merge(in, nm, 4, &merged, &e), &e);
        CHECK(merged.s0 == 0 && merged.s1 == 8 && merged.seed == 7);
        CHECK_MSG(acc_equal(&full, &merged), "tiles + batches merged differ from the full render");
        /* and the EXR output of both is identical */
        const char *p1 = prw_test_path("full.exr"), *p2 = prw_test_path("merged.exr");
        CHECK_OK(prw_ref_write_exr(p1, &full, NULL, 0, &e), &e);
        CHECK_OK(prw_ref_write_exr(p2, &merged, NULL, 0, &e), &e);
        char spp[32], var_path[1024];
        CHECK_OK(prw_exr_read_attr(p2, "prw:spp", spp, sizeof spp, &e), &e);
        CHECK(strcmp(spp, "8") == 0);
        prw_ref_var_path(p2, var_path, sizeof var_path);
        prw_image img = {0};
        CHECK_OK(prw_exr_read(var_path, NULL, &img, &e), &e);
        CHECK(img.width == 24 && img.height == 16 && img.rgba[3] == 8.0f);
        prw_image_free(&img);
    }
    prw_ref_acc_free(&full);
    prw_ref_acc_free(&merged);
    for (int k = 0; k < 4; k++) prw_ref_acc_free(&parts[k]), prw_ref_acc_free(&back[k]);
    prw_ref_destroy(r);
    prw_scene_destroy(s);
}

static void img_stats(const prw_ref_acc *a, double *mean, double *var_of_mean)
{
    float *m = NULL, *v = NULL;
    prw_error e;
    *mean = *var_of_mean = 0;
    if (!prw_ref_acc_images(a, &m, &v, &e)) return;
    size_t n = (size_t)a->width * a->height;
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++) {
            *mean += m[4 * i + c];
            *var_of_mean += v[4 * i + c];
        }
    *mean /= 3.0 * n;
    *var_of_mean /= 9.0 * n * n; /* channels treated as independent; see below for the bound */
    free(m);
    free(v);
}

static double acc_total(const prw_ref_acc *a)
{
    size_t n = 3 * (size_t)(a->x1 - a->x0) * (a->y1 - a->y0);
    double t = 0;
    for (size_t i = 0; i < n; i++) t += (double)a->sum[i] / PRW_REF_SUM_SCALE;
    return t;
}

static void test_filters(void)
{
    prw_scene *s = room_scene();
    prw_view v = room_view(16, 12);
    prw_error e;
    prw_ref_renderer *r = NULL;
    CHECK_OK(prw_ref_create(s, v.eye, 0, &r, &e), &e);
    const char *names[] = {"all", "direct", "indirect", "emission", "diffuse-last", "glossy-last", "depth:1",
                           "maxdepth:1", "indirect-diffuse-last", "indirect-glossy-last", "environment-direct"};
    enum { NF = (int)PRW_ARRAY_LEN(names) };
    prw_ref_acc acc[NF] = {{0}}, other[3] = {{0}};
    bool ok = true;
    for (int k = 0; k < NF && ok; k++) {
        prw_ref_filter f;
        CHECK_OK(prw_ref_filter_parse(names[k], &f, &e), &e);
        char back[32];
        prw_ref_filter_name(f, back, sizeof back);
        CHECK_MSG(strcmp(back, names[k]) == 0, "%s -> %s", names[k], back);
        ok = render_acc(r, &v, 0, 0, 0, 0, 0, 32, 5, f, 0, &acc[k]);
    }
    /* independent seeds: direct + indirect == all within 3 sigma (image means) */
    for (int k = 0; k < 3 && ok; k++) {
        prw_ref_filter f;
        prw_ref_filter_parse(names[k], &f, &e);
        ok = render_acc(r, &v, 0, 0, 0, 0, 0, 128, 100 + k, f, 0, &other[k]);
    }
    if (ok) {
        double m[3], vm[3];
        for (int k = 0; k < 3; k++) img_stats(&other[k], &m[k], &vm[k]);
        /* channels of one pixel are positively correlated: bound the variance with 3x (all correlated) */
        double sigma = sqrt(3 * (vm[0] + vm[1] + vm[2]));
        double diff = m[1] + m[2] - m[0];
        printf("  seeds 100..102: all %.5g, direct %.5g + indirect %.5g = %.5g, diff %.3g (3 sigma %.3g)\n", m[0], m[1],
               m[2], m[1] + m[2], diff, 3 * sigma);
        CHECK_MSG(fabs(diff) <= 3 * sigma, "direct + indirect - all = %g > 3 sigma = %g", diff, 3 * sigma);
        CHECK(m[1] > 0 && m[2] > 0);
        /* the same seed: the same paths, so the splits hold to rounding */
        double t_all = acc_total(&acc[0]), t_dir = acc_total(&acc[1]), t_ind = acc_total(&acc[2]);
        double t_em = acc_total(&acc[3]), t_dif = acc_total(&acc[4]), t_gl = acc_total(&acc[5]);
        double t_d1 = acc_total(&acc[6]), t_m1 = acc_total(&acc[7]);
        printf("  seed 5: all %.9g  direct+indirect %.9g  emission+diffuse+glossy %.9g (diffuse %.4g, glossy %.4g)\n",
               t_all, t_dir + t_ind, t_em + t_dif + t_gl, t_dif, t_gl);
        CHECK_NEAR(t_dir + t_ind, t_all, 1e-9 * t_all);
        CHECK_NEAR(t_em + t_dif + t_gl, t_all, 1e-9 * t_all);
        CHECK_NEAR(t_em + t_d1, t_dir, 1e-9 * t_all);
        CHECK_NEAR(t_m1, t_dir, 1e-9 * t_all);
        CHECK(t_em > 0 && t_dif > 0 && t_gl > 0);
        /* the GI terms (every emitter kind: rect, point, spot, directional, emissive mesh) */
        double t_idl = acc_total(&acc[8]), t_igl = acc_total(&acc[9]), t_env = acc_total(&acc[10]);
        printf("  seed 5: direct+indirect-diffuse-last+indirect-glossy-last %.9g (%.4g, %.4g)\n", t_dir + t_idl + t_igl,
               t_idl, t_igl);
        CHECK_NEAR(t_dir + t_idl + t_igl, t_all, 1e-9 * t_all);
        CHECK_NEAR(t_idl + t_igl, t_ind, 1e-9 * t_all);
        CHECK(t_idl > 0 && t_igl > 0 && t_idl < t_dif && t_igl < t_gl);
        CHECK(t_env <= 1e-6 * t_all); /* the room is closed: its sky is (all but) never reached */
    }
    for (int k = 0; k < NF; k++) prw_ref_acc_free(&acc[k]);
    for (int k = 0; k < 3; k++) prw_ref_acc_free(&other[k]);
    prw_ref_destroy(r);
    prw_scene_destroy(s);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"threads", test_threads},
        {"tiles_merge", test_tiles_merge},
        {"filters", test_filters},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
