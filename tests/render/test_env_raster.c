/* The rasterizer's environment term (issue 16; engine/render/prw_env_gpu.h, shaders/gi_env.glsl) against
 * the path tracer's environment-direct paths, validation layer on, 4x MSAA.
 *
 *  uniform_spheres: a rough dielectric and a gold sphere under a uniform environment, nothing else
 *    (no light maps: visibility 1, which is exact here).  The raster image's mean radiance per channel
 *    over the whole frame is within 2 % of the reference's (environment-direct; the background is 0 in
 *    both).  A control with the environment term scaled by 0.97 must fail the same bound's half.
 *  gi_room_sky: gi-room-sky.json (open window, non-uniform EXR sky), camera main, 128x72, a reduced
 *    bake made here (no cache) for the visibility, the environment precomputation at envmap_size 64.
 *    Over the pixels where the filtered reference exceeds 1 % of the full reference, at the term's own
 *    metric exposure: relMSE and LDR-FLIP beyond noise (term_error.h; as test_gi_raster), printed
 *    against the goal 0.05, which the term does NOT reach: a few pixels of the sharp reflectors
 *    (the mirror, the glossy floor and spheres) reflect the sky or the sun where the open cone lets it
 *    through and the window does not (the cone is a disc, the window a rectangle, and the blue sphere
 *    hides part of it from the floor), relMSE 2.74 (7.33 before the cone's occupancy, gi_env.glsl; FLIP
 *    at this exposure, EV100 about -2.6, saturates and reads below the noise for every image, so it
 *    checks nothing; the reference's own relMSE noise, B vs A, is 1.50 at 256 spp).
 *    Asserted: relMSE beyond noise <= BOUND_RELMSE, and the median over the mask of the per-pixel
 *    luminance ratio raster / A within BOUND_MEDIAN of 1 (robust to those pixels and to the reference
 *    noise).  Controls: the visibility forced to 1 (no light maps) must fail the relMSE bound, the term
 *    x 0.8 the median one.
 *  black_environment: a black environment, spheres of roughness 0 and 1 (metal and dielectric), and the
 *    sky with the same spheres: every pixel finite; with the black one the environment term is 0.
 *
 * Environment: PRW_ENVR_SPP (reference samples per pixel of gi_room_sky, default 256), PRW_ENVR_OUT=DIR
 * writes raster / reference images (EXR + PNG at the metric exposure) there. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "lightmaps.h"
#include "prw_env_bake.h"
#include "prw_gi.h"
#include "prw_image.h"
#include "prw_metrics.h"
#include "prw_reference.h"
#include "prw_render.h"
#include "prw_test.h"
#include "prw_test_gpu.h"
#include "term_error.h"

#define W 128u
#define H 72u
#define GOAL 0.05        /* the goal for relMSE and LDR-FLIP beyond noise (printed, not reached) */
#define BOUND_RELMSE 4.0 /* what the term reaches (2.74 at 256 spp, 2026-12-06; 7.33 without the occupancy) */
#define BOUND_MEDIAN 0.08 /* |median of the per-pixel luminance ratio raster / A - 1| (0.052 reached) */

static unsigned long env_u(const char *name, unsigned long def)
{
    const char *v = getenv(name);
    return v && *v ? strtoul(v, NULL, 10) : def;
}

static bool render_raster(const prw_scene *s, const prw_view *v, const prw_lightmaps *lm, const prw_env_data *env,
                          uint32_t terms, prw_image *hdr, prw_error *e)
{
    prw_render_desc rd = {.width = W, .height = H, .quality = prw_quality_default(), .lightmaps = lm,
                          .environment = env, .terms = terms};
    rd.quality.msaa = 4;
    return prw_test_render(s, &rd, v, 1, hdr, NULL, e);
}

static bool render_ref(prw_ref_renderer *ref, const prw_view *v, uint64_t spp, uint64_t seed, prw_ref_filter_kind k,
                       prw_image *out, prw_error *e)
{
    prw_ref_desc d = {.s0 = 0, .s1 = spp, .seed = seed, .filter = {.kind = k}};
    prw_ref_acc acc = {0};
    prw_ref_stats st;
    float *mean = NULL, *var = NULL;
    bool ok = prw_ref_render(ref, v, &d, &acc, &st, e) && prw_ref_acc_images(&acc, &mean, &var, e) &&
              prw_image_alloc(out, v->width, v->height, e);
    if (ok) {
        memcpy(out->rgba, mean, (size_t)v->width * v->height * 4 * sizeof(float));
        printf("reference %s seed %llu: %llu spp in %.1f s\n", k == PRW_REF_ALL ? "all" : "environment-direct",
               (unsigned long long)seed, (unsigned long long)st.spp, st.seconds);
    }
    free(mean);
    free(var);
    prw_ref_acc_free(&acc);
    return ok;
}

static double luma(const float *p) { return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]; }
static double median_ratio(const prw_image *test, const prw_image *ref, const uint8_t *mask);

static void write_if(const char *name, const prw_image *im, double ev100)
{
    const char *dir = getenv("PRW_ENVR_OUT");
    if (!dir || !*dir) return;
    char path[4096], ev[64];
    snprintf(path, sizeof path, "%s/%s.exr", dir, name);
    snprintf(ev, sizeof ev, "%.17g", ev100);
    prw_kv kv[] = {{"prw:ev100", ev}};
    prw_error e;
    if (!prw_exr_write(path, im, kv, 1, &e)) fprintf(stderr, "%s\n", e.msg);
    prw_image tm = {0};
    if (!prw_metric_tonemap(im, ev100, &tm, &e)) return;
    uint8_t *px = prw_malloc((size_t)tm.width * tm.height * 3);
    for (size_t i = 0; i < (size_t)tm.width * tm.height; i++)
        for (int c = 0; c < 3; c++) px[i * 3 + c] = (uint8_t)lrintf(255.0f * fminf(fmaxf(tm.rgba[i * 4 + c], 0.0f), 1.0f));
    snprintf(path, sizeof path, "%s/%s.png", dir, name);
    if (prw_png_write8(path, tm.width, tm.height, 3, px, &e)) printf("wrote %s\n", path);
    free(px);
    prw_image_free(&tm);
}

/* A manifest in a temporary file (removed by the caller), loaded; NULL (e set) on failure. */
static prw_scene *load_text(const char *json, char *path, size_t cap, prw_error *e)
{
    snprintf(path, cap, "/tmp/prw_test_env_%ld.json", (long)getpid());
    FILE *f = fopen(path, "wb");
    if (!f) return prw_fail(e, "%s: cannot write", path), NULL;
    fputs(json, f);
    fclose(f);
    prw_scene *s = prw_scene_create();
    if (!prw_scene_load_manifest(s, path, e)) {
        prw_scene_destroy(s);
        return NULL;
    }
    prw_scene_update(s);
    return s;
}

/* printf arguments: the environment's radiance, the clay's and the gold's roughness, the spheres (JSON) */
static const char *k_spheres =
    "{\"prw_manifest\": 1,\n"
    " \"environment\": {\"uniform_cd_m2\": [%s]},\n"
    " \"materials\": [\n"
    "  {\"name\": \"clay\", \"base_color\": [0.6, 0.45, 0.3], \"metallic\": 0, \"roughness\": %s},\n"
    "  {\"name\": \"gold\", \"base_color\": [1.0, 0.78, 0.34], \"metallic\": 1, \"roughness\": %s}],\n"
    " \"meshes\": [%s],\n"
    " \"cameras\": [{\"name\": \"main\", \"position\": [0, 0.4, 3], \"target\": [0, 0, 0], \"up\": [0, 1, 0], "
    "\"yfov_deg\": 40, \"znear\": 0.05, \"ev100\": 7}]}\n";
#define SPHERE(NAME, X, MAT)                                                                                    \
    "{\"name\": \"" NAME "\", \"sphere\": {\"centre\": [" X ", 0, 0], \"radius\": 0.5, \"slices\": 96, \"stacks\": 48}, " \
    "\"material\": \"" MAT "\"}"

static void mean_rgb(const prw_image *im, double out[3])
{
    out[0] = out[1] = out[2] = 0;
    size_t n = (size_t)im->width * im->height;
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++) out[c] += im->rgba[4 * i + c];
    for (int c = 0; c < 3; c++) out[c] /= (double)n;
}

/* One sphere alone (nothing occludes it: visibility 1 is exact) under a uniform environment. */
static void uniform_sphere(const char *sphere, double *worst)
{
    prw_error e = {{0}};
    char json[4096], path[256];
    snprintf(json, sizeof json, k_spheres, "150, 140, 120", "0.5", "0.3", sphere);
    prw_scene *s = load_text(json, path, sizeof path, &e);
    CHECK_OK(s != NULL, &e);
    prw_view v;
    CHECK_OK(prw_ref_view_for_camera(s, "main", W, H, &v, &e), &e);
    prw_env_data env;
    bool hit = false;
    CHECK_OK(prw_env_bake(&s->environment, 64, &env, &hit, NULL, 0, &e), &e);
    prw_image raster = {0}, ref = {0};
    CHECK_OK(render_raster(s, &v, NULL, &env, PRW_TERM_ENVIRONMENT, &raster, &e), &e);
    uint64_t spp = prw_test_light() ? 16 : 64;
    prw_ref_renderer *rr = NULL;
    CHECK_OK(prw_ref_create(s, v.eye, 0, &rr, &e), &e);
    bool ok = render_ref(rr, &v, spp, 1, PRW_REF_ENVIRONMENT_DIRECT, &ref, &e);
    prw_ref_destroy(rr);
    CHECK_OK(ok, &e);
    double mr[3], mt[3];
    mean_rgb(&raster, mt);
    mean_rgb(&ref, mr);
    for (int c = 0; c < 3; c++) {
        printf("  channel %d: raster mean %.4f, reference mean %.4f, ratio %.4f\n", c, mt[c], mr[c], mt[c] / mr[c]);
        *worst = fmax(*worst, fabs(mt[c] / mr[c] - 1));
        /* the control: the term 3 % too dark must miss half the bound */
        CHECK_MSG(fabs(0.97 * mt[c] / mr[c] - 1) > 0.01, "control (x 0.97) within 1 %%: %.4f", 0.97 * mt[c] / mr[c]);
    }
    write_if(strstr(sphere, "gold") ? "uniform_gold_raster" : "uniform_clay_raster", &raster, 7);
    write_if(strstr(sphere, "gold") ? "uniform_gold_ref" : "uniform_clay_ref", &ref, 7);
    prw_image_free(&raster);
    prw_image_free(&ref);
    prw_env_data_free(&env);
    prw_scene_destroy(s);
    remove(path);
}

static void test_uniform_spheres(void)
{
    double worst = 0;
    printf("rough dielectric (roughness 0.5):\n");
    uniform_sphere(SPHERE("a", "0", "clay"), &worst);
    printf("gold (roughness 0.3):\n");
    uniform_sphere(SPHERE("b", "0", "gold"), &worst);
    printf("uniform environment, one sphere at a time, %ux%u: worst channel %.4f (bound 0.02)\n", W, H, worst);
    CHECK_MSG(worst <= 0.02, "mean radiance off by %.4f", worst);
}

static void test_gi_room_sky(void)
{
    prw_error e = {{0}};
    prw_scene *s = prw_scene_create();
    CHECK_OK(prw_scene_load_manifest(s, PRW_SOURCE_DIR "/assets/scenes/gi-room-sky.json", &e), &e);
    prw_scene_update(s);
    prw_view v;
    CHECK_OK(prw_ref_view_for_camera(s, "main", W, H, &v, &e), &e);
    bool light = prw_test_light();
    prw_gi_options o = {.radiosity_size = light ? 32 : 96, .samples = light ? 16 : 64, .seed = 7,
                        .filter_radius = PRW_GI_DEFAULT_FILTER_RADIUS};
    prw_gi_bake *b = NULL;
    prw_gi_result gr;
    CHECK_OK(prw_gi_run(s, &o, true, NULL, NULL, &b, &gr, &e), &e);
    printf("bake: radiosity_size %u, %u samples, texel %.4f m, %llu texels + %llu vertices, %.1f s\n", o.radiosity_size,
           o.samples, b->texel_size, (unsigned long long)b->sampled_texels, (unsigned long long)b->sampled_vertices,
           gr.seconds_total);
    prw_app_lightmaps *lms = NULL;
    CHECK_OK(prw_app_lightmaps_from_bake(s, b, &lms, &e), &e);
    prw_env_data env;
    bool hit = false;
    CHECK_OK(prw_env_bake(&s->environment, 64, &env, &hit, NULL, 0, &e), &e);

    prw_image raster = {0}, unoccluded = {0}, ra = {0}, rb = {0}, rall = {0};
    CHECK_OK(render_raster(s, &v, prw_app_lightmaps_get(lms), &env, PRW_TERM_ENVIRONMENT, &raster, &e), &e);
    CHECK_OK(render_raster(s, &v, NULL, &env, PRW_TERM_ENVIRONMENT, &unoccluded, &e), &e);
    uint64_t spp = env_u("PRW_ENVR_SPP", light ? 16 : 256);
    prw_ref_renderer *ref = NULL;
    CHECK_OK(prw_ref_create(s, v.eye, 0, &ref, &e), &e);
    bool ok = render_ref(ref, &v, spp, 1, PRW_REF_ENVIRONMENT_DIRECT, &ra, &e) &&
              render_ref(ref, &v, spp, 2, PRW_REF_ENVIRONMENT_DIRECT, &rb, &e) &&
              render_ref(ref, &v, spp / 4 ? spp / 4 : 1, 3, PRW_REF_ALL, &rall, &e); /* the mask only */
    prw_ref_destroy(ref);
    CHECK_OK(ok, &e);

    uint8_t *mask = prw_calloc((size_t)W * H, 1);
    size_t nm = 0;
    for (size_t i = 0; i < (size_t)W * H; i++) {
        mask[i] = luma(ra.rgba + 4 * i) > 0.01 * luma(rall.rgba + 4 * i);
        nm += mask[i];
        for (int c = 0; c < 3; c++) CHECK(isfinite(raster.rgba[4 * i + c]) && raster.rgba[4 * i + c] >= 0);
    }
    double ev = prw_compare_derive_ev100(&ra, NULL);
    term_err err, noise, vis1, dim;
    double med = median_ratio(&raster, &ra, mask), med_b = median_ratio(&rb, &ra, mask);
    masked_error(&raster, &ra, mask, ev, &err);
    masked_error(&rb, &ra, mask, ev, &noise);
    masked_error(&unoccluded, &ra, mask, ev, &vis1);
    prw_image scaled = {0};
    CHECK_OK(prw_image_alloc(&scaled, W, H, &e), &e);
    for (size_t i = 0; i < (size_t)W * H * 4; i++) scaled.rgba[i] = raster.rgba[i] * ((i & 3) == 3 ? 1.0f : 0.8f);
    masked_error(&scaled, &ra, mask, ev, &dim);
    double fb = err.flip - noise.flip, rb_ = err.relmse - noise.relmse / 2, med_dim = 0.8 * med;
    printf("gi-room-sky, camera main, %ux%u, 4x MSAA, term environment, reference %llu spp, metric EV100 %.4f (the "
           "term's own), %zu of %u pixels where the term > 1 %% of the full reference:\n",
           W, H, (unsigned long long)spp, ev, nm, W * H);
    printf("  LDR-FLIP  raster vs A %.4f  noise (B vs A) %.4f  beyond noise %.4f (goal %.2f)\n", err.flip, noise.flip,
           fb, GOAL);
    printf("  relMSE    raster vs A %.4f  noise (B vs A) %.4f  beyond noise %.4f (goal %.2f, bound %.1f)\n", err.relmse,
           noise.relmse, rb_, GOAL, BOUND_RELMSE);
    printf("  median luminance ratio over the mask: raster / A %.4f, B / A %.4f (bound |x - 1| <= %.2f)\n", med, med_b,
           BOUND_MEDIAN);
    printf("  control visibility 1: LDR-FLIP beyond noise %.4f, relMSE beyond noise %.4f\n", vis1.flip - noise.flip,
           vis1.relmse - noise.relmse / 2);
    printf("  control term x 0.8:   LDR-FLIP beyond noise %.4f, relMSE beyond noise %.4f, median ratio %.4f\n",
           dim.flip - noise.flip, dim.relmse - noise.relmse / 2, med_dim);
    write_if("room_raster", &raster, ev);
    write_if("room_unoccluded", &unoccluded, ev);
    write_if("room_ref_a", &ra, ev);
    write_if("room_ref_b", &rb, ev);
    write_if("room_ref_all", &rall, ev);
    if (!light) {
        CHECK(nm > (size_t)W * H / 4);
        CHECK_MSG(rb_ <= BOUND_RELMSE, "relMSE beyond noise %.4f > %.1f", rb_, BOUND_RELMSE);
        CHECK_MSG(fabs(med - 1) <= BOUND_MEDIAN, "median ratio %.4f", med);
        CHECK_MSG(vis1.relmse - noise.relmse / 2 > BOUND_RELMSE, "the control (visibility 1) passes");
        CHECK_MSG(fabs(med_dim - 1) > BOUND_MEDIAN, "the control (x 0.8) passes: median ratio %.4f", med_dim);
    } else {
        printf("  light mode: the bounds are not checked at %llu spp\n", (unsigned long long)spp);
        CHECK_MSG(vis1.relmse > err.relmse, "the control (visibility 1) is not worse: %.4f", vis1.relmse);
    }
    free(mask);
    prw_image_free(&scaled);
    prw_image_free(&raster);
    prw_image_free(&unoccluded);
    prw_image_free(&ra);
    prw_image_free(&rb);
    prw_image_free(&rall);
    prw_env_data_free(&env);
    prw_app_lightmaps_destroy(lms);
    prw_scene_destroy(s);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* The median over the mask of Y(test) / Y(ref) (pixels with Y(ref) > 0). */
static double median_ratio(const prw_image *test, const prw_image *ref, const uint8_t *mask)
{
    size_t n = (size_t)test->width * test->height, m = 0;
    double *r = prw_malloc((n + 1) * sizeof *r);
    for (size_t i = 0; i < n; i++)
        if (mask[i] && luma(ref->rgba + 4 * i) > 0) r[m++] = luma(test->rgba + 4 * i) / luma(ref->rgba + 4 * i);
    qsort(r, m, sizeof *r, cmp_double);
    double med = m ? r[m / 2] : 0;
    free(r);
    return med;
}

static void check_finite(const prw_image *im, const char *what)
{
    size_t n = (size_t)im->width * im->height * 4;
    for (size_t i = 0; i < n; i++) CHECK_MSG(isfinite(im->rgba[i]), "%s: value %zu is %g", what, i, im->rgba[i]);
}

static void test_black_environment(void)
{
    prw_error e = {{0}};
    const char *rough[2][2] = {{"0", "1"}, {"1", "0"}};
    for (int k = 0; k < 2; k++) {
        char json[4096], path[256];
        snprintf(json, sizeof json, k_spheres, "0, 0, 0", rough[k][0], rough[k][1],
                 SPHERE("a", "-0.55", "clay") ", " SPHERE("b", "0.55", "gold"));
        prw_scene *s = load_text(json, path, sizeof path, &e);
        CHECK_OK(s != NULL, &e);
        prw_view v;
        CHECK_OK(prw_ref_view_for_camera(s, "main", W, H, &v, &e), &e);
        prw_env_data env;
        bool hit = false;
        CHECK_OK(prw_env_bake(&s->environment, 32, &env, &hit, NULL, 0, &e), &e);
        prw_image im = {0}, all = {0};
        CHECK_OK(render_raster(s, &v, NULL, &env, PRW_TERM_ENVIRONMENT, &im, &e), &e);
        CHECK_OK(render_raster(s, &v, NULL, &env, 0, &all, &e), &e);
        check_finite(&im, "black environment, term");
        check_finite(&all, "black environment, all terms");
        for (size_t i = 0; i < (size_t)W * H; i++)
            for (int c = 0; c < 3; c++) CHECK_MSG(im.rgba[4 * i + c] == 0.0f, "black environment lights pixel %zu", i);
        prw_image_free(&im);
        prw_image_free(&all);
        prw_env_data_free(&env);
        /* the same spheres under the sky of gi-room-sky: finite everywhere */
        prw_scene *room = prw_scene_create();
        CHECK_OK(prw_scene_load_manifest(room, PRW_SOURCE_DIR "/assets/scenes/gi-room-sky.json", &e), &e);
        CHECK_OK(prw_env_bake(&room->environment, 32, &env, &hit, NULL, 0, &e), &e);
        prw_scene_destroy(room);
        CHECK_OK(render_raster(s, &v, NULL, &env, 0, &all, &e), &e);
        check_finite(&all, "sky, all terms");
        double m[3];
        mean_rgb(&all, m);
        CHECK(m[0] > 0 && m[1] > 0 && m[2] > 0);
        printf("roughness clay %s / gold %s: black environment term 0 everywhere, sky finite (mean %.3g)\n", rough[k][0],
               rough[k][1], luma((float[3]){(float)m[0], (float)m[1], (float)m[2]}));
        prw_image_free(&all);
        prw_env_data_free(&env);
        prw_scene_destroy(s);
        remove(path);
    }
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {{"uniform_spheres", test_uniform_spheres},
                                          {"gi_room_sky", test_gi_room_sky},
                                          {"black_environment", test_black_environment}};
    int rc = prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
    return prw_test_gpu_finish() ? 1 : rc; /* one gpu for all cases: pipelines compiled once */
}
