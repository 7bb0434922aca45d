/* Rendering tests (lavapipe, validation layer on; any unsuppressed message fails the test).
 * One process for the group so lavapipe's pipelines compile once.
 * Golden: tests/data/golden/demo_main_128.png; regenerate with
 *   PRW_UPDATE_GOLDEN=1 build/tests/render/test_render golden
 * (then look at the PNG before committing it). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_demo.h"
#include "prw_image.h"
#include "prw_render.h"
#include "prw_test.h"

#ifndef PRW_GOLDEN_DIR
#error "PRW_GOLDEN_DIR must be defined"
#endif

static prw_gpu *g_gpu;

static bool gpu_up(void)
{
    if (g_gpu) return true;
    prw_error e;
    prw_gpu_desc d = {.device_index = -1, .validation = true};
    if (!prw_gpu_create(&d, &g_gpu, &e)) {
        fprintf(stderr, "gpu: %s\n", e.msg);
        return false;
    }
    return true;
}

/* Renders scene camera `cam` at w x h; returns HDR and LDR (caller frees). */
static uint32_t g_supersample = 1;

static bool render_scene(const prw_scene *s, const char *cam, uint32_t w, uint32_t h, uint32_t msaa, prw_image *hdr,
                         uint8_t **ldr, prw_frame_stats *st)
{
    prw_error e;
    prw_renderer *r = NULL;
    prw_view v;
    int ci = prw_scene_find_camera(s, cam);
    prw_render_desc rd = {.width = w, .height = h, .quality = prw_quality_default()};
    rd.quality.msaa = msaa;
    rd.quality.shadow_size = 512;
    rd.quality.supersample = g_supersample;
    bool ok = ci >= 0 && prw_view_from_camera(s, ci, w, h, &v, &e) && prw_renderer_create(g_gpu, s, &rd, &r, &e) &&
              prw_renderer_render(r, &v, 1, st, &e) && prw_renderer_read_hdr(r, 0, hdr, &e);
    if (ok && ldr) {
        *ldr = prw_malloc((size_t)w * h * 4);
        ok = prw_renderer_read_ldr(r, 0, *ldr, &e);
    }
    if (!ok) fprintf(stderr, "render: %s\n", ci < 0 ? "no camera" : e.msg);
    prw_renderer_destroy(r);
    return ok;
}

/* Filament-style image comparison: a pixel fails when any channel differs by more than tol/255;
 * returns the fraction of failing pixels. */
static double fail_fraction(const uint8_t *a, const uint8_t *b, int n, int tol, int *worst)
{
    int fails = 0;
    *worst = 0;
    for (int i = 0; i < n; i++) {
        int bad = 0;
        for (int c = 0; c < 3; c++) {
            int d = abs((int)a[4 * i + c] - (int)b[4 * i + c]);
            if (d > *worst) *worst = d;
            if (d > tol) bad = 1;
        }
        fails += bad;
    }
    return (double)fails / n;
}

static bool all_finite(const prw_image *im)
{
    for (size_t i = 0; i < (size_t)im->width * im->height * 4; i++)
        if (!isfinite(im->rgba[i])) return false;
    return true;
}

static void test_golden(void)
{
    if (!gpu_up()) return prw_test_failures++, (void)0;
    prw_error e;
    prw_scene *s = prw_scene_create();
    CHECK_OK(prw_demo_build(s, prw_v3(0, 0, 0), &e), &e);
    prw_image hdr = {0};
    uint8_t *ldr = NULL;
    prw_frame_stats st;
    CHECK(render_scene(s, "main", 128, 128, 4, &hdr, &ldr, &st));
    if (!ldr) return prw_scene_destroy(s);
    CHECK(all_finite(&hdr));
    char path[1024];
    snprintf(path, sizeof path, "%s/demo_main_128.png", PRW_GOLDEN_DIR);
    if (getenv("PRW_UPDATE_GOLDEN")) {
        CHECK_OK(prw_png_write8(path, 128, 128, 4, ldr, &e), &e);
        printf("updated golden %s\n", path);
    } else {
        int w, h, worst;
        uint8_t *gold = NULL;
        if (!prw_png_read8(path, &w, &h, &gold, &e)) {
            CHECK_MSG(false, "%s", e.msg);
        } else {
            CHECK(w == 128 && h == 128);
            double frac = fail_fraction(ldr, gold, 128 * 128, 5, &worst);
            printf("golden: %.4f %% pixels beyond 5/255 (worst %d/255)\n", 100.0 * frac, worst);
            CHECK_MSG(frac <= 0.001, "%.3f %% of pixels differ by > 5/255", 100.0 * frac);
            free(gold);
        }
        /* a non-black image: the mean displayed value is well above black */
        double mean = 0;
        for (int i = 0; i < 128 * 128; i++) mean += ldr[4 * i + 1];
        CHECK(mean / (128 * 128) > 20.0);
    }
    free(ldr);
    prw_image_free(&hdr);
    prw_scene_destroy(s);
}

/* The same scene 1e5 m from the origin renders like the one at the origin (camera-relative floats). */
static void test_far_from_origin(void)
{
    if (!gpu_up()) return prw_test_failures++, (void)0;
    prw_error e;
    prw_scene *a = prw_scene_create(), *b = prw_scene_create();
    CHECK_OK(prw_demo_build(a, prw_v3(0, 0, 0), &e), &e);
    CHECK_OK(prw_demo_build(b, prw_v3(1e5, 0, -1e5), &e), &e);
    prw_image ha = {0}, hb = {0};
    uint8_t *la = NULL, *lb = NULL;
    prw_frame_stats st;
    CHECK(render_scene(a, "main", 128, 128, 4, &ha, &la, &st));
    CHECK(render_scene(b, "main", 128, 128, 4, &hb, &lb, &st));
    if (la && lb) {
        int worst;
        double frac = fail_fraction(la, lb, 128 * 128, 5, &worst);
        printf("far-from-origin: %.4f %% pixels beyond 5/255 (worst %d/255)\n", 100.0 * frac, worst);
        CHECK(frac <= 0.001);
        /* and in linear HDR: relative mean absolute difference */
        double num = 0, den = 0;
        for (int i = 0; i < 128 * 128 * 4; i++) {
            if (i % 4 == 3) continue;
            num += fabs(ha.rgba[i] - hb.rgba[i]);
            den += fabs(ha.rgba[i]);
        }
        printf("far-from-origin: HDR relative mean abs difference %.2e\n", num / den);
        CHECK(num / den < 2e-3);
    }
    free(la);
    free(lb);
    prw_image_free(&ha);
    prw_image_free(&hb);
    prw_scene_destroy(a);
    prw_scene_destroy(b);
}

/* Closed form: a Lambertian plane (rho, specular 0: no specular layer, so the material model's
 * diffuse-specular coupling vanishes and f = rho/pi exactly; roughness 1) under a point light of
 * I cd at height d, seen straight down at the foot point: L = f * I / d^2 cd/m^2 (written out here
 * by hand, not through the material header; the specular lobes are pinned by tests/materials).
 * No shadows, nothing else in the scene. */
static void test_point_light_closed_form(void)
{
    if (!gpu_up()) return prw_test_failures++, (void)0;
    prw_error e;
    prw_scene *s = prw_scene_create();
    prw_material m = prw_material_default();
    m.base_color[0] = m.base_color[1] = m.base_color[2] = 0.5f;
    m.roughness = 1.0f;
    m.specular = 0.0f;
    int mi = prw_scene_add_material(s, &m);
    /* plane y = 0, front face up: cross(u, v) = +Y */
    CHECK(prw_scene_add_quad(s, "plane", prw_v3(0, 0, 0), prw_v3(0, 0, 10), prw_v3(10, 0, 0), mi, &e) >= 0);
    prw_light l = {0};
    l.type = PRW_LIGHT_POINT;
    l.color[0] = l.color[1] = l.color[2] = 1.0f;
    l.intensity = 100.0;
    prw_node ln = prw_node_default();
    ln.translation = prw_v3(0, 2, 0);
    l.node = prw_scene_add_node(s, &ln);
    s->nodes[l.node].light = prw_scene_add_light(s, &l);
    prw_camera c = {0};
    snprintf(c.name, sizeof c.name, "top");
    c.yfov = 0.5;
    c.znear = 0.05;
    c.ev100 = 0;
    prw_node cn = prw_node_look_at("cam", prw_v3(0, 1, 0), prw_v3(0, 0, 0), prw_v3(0, 0, -1));
    c.node = prw_scene_add_node(s, &cn);
    s->nodes[c.node].camera = prw_scene_add_camera(s, &c);
    prw_scene_update(s);
    prw_image hdr = {0};
    prw_frame_stats st;
    CHECK(render_scene(s, "top", 64, 64, 4, &hdr, NULL, &st));
    if (hdr.rgba) {
        /* the four pixels around the image centre straddle the foot point */
        double sum = 0;
        for (int y = 31; y <= 32; y++)
            for (int x = 31; x <= 32; x++) sum += hdr.rgba[4 * (y * 64 + x) + 1];
        double f = 0.5 / PRW_PI;
        double got = sum / 4, expect = f * 100.0 / 4.0;
        printf("point light over Lambert plane: %.5f cd/m^2, closed form %.5f\n", got, expect);
        /* the pixels sit ~0.003 rad off the foot point: cos^3 falloff < 1e-4; RGBA16F: 1e-3 */
        CHECK_NEAR(got, expect, 0.003 * expect);
        /* shadow pass skipped (no shadow-casting light) and listed as such */
        for (uint32_t i = 0; i < st.pass_count; i++) {
            bool expect_skip = strcmp(st.passes[i].name, "shadow") == 0 || strcmp(st.passes[i].name, "downsample") == 0 ||
                               strcmp(st.passes[i].name, "tm_stats") == 0;
            CHECK_MSG(st.passes[i].skipped == expect_skip, "pass %s skipped=%d", st.passes[i].name, st.passes[i].skipped);
        }
        CHECK(st.pass_count == 5);
    }
    prw_image_free(&hdr);
    /* The plane mirrored by its node (scale x = -1, winding flipped) must look the same: front faces
     * and normals follow the determinant's sign. */
    for (uint32_t i = 0; i < s->node_count; i++)
        if (s->nodes[i].mesh_group >= 0) s->nodes[i].scale.x = -1.0;
    prw_scene_update(s);
    CHECK(render_scene(s, "top", 64, 64, 4, &hdr, NULL, &st));
    if (hdr.rgba) {
        double sum = 0;
        for (int y = 31; y <= 32; y++)
            for (int x = 31; x <= 32; x++) sum += hdr.rgba[4 * (y * 64 + x) + 1];
        double f = 0.5 / PRW_PI;
        printf("mirrored plane: %.5f cd/m^2\n", sum / 4);
        CHECK_NEAR(sum / 4, f * 100.0 / 4.0, 0.003 * f * 100.0 / 4.0);
    }
    prw_image_free(&hdr);
    prw_scene_destroy(s);
}

/* N x N supersampling equals rendering N times larger and box-filtering by N x N (in linear HDR). */
static void test_supersampling(void)
{
    if (!gpu_up()) return prw_test_failures++, (void)0;
    prw_error e;
    prw_scene *s = prw_scene_create();
    CHECK_OK(prw_demo_build(s, prw_v3(0, 0, 0), &e), &e);
    prw_image small = {0}, big = {0};
    prw_frame_stats st;
    g_supersample = 2;
    CHECK(render_scene(s, "main", 64, 48, 1, &small, NULL, &st));
    g_supersample = 1;
    bool ran = false;
    for (uint32_t i = 0; i < st.pass_count; i++)
        if (strcmp(st.passes[i].name, "downsample") == 0) ran = !st.passes[i].skipped;
    CHECK(ran);
    CHECK(render_scene(s, "main", 128, 96, 1, &big, NULL, &st));
    if (small.rgba && big.rgba) {
        double worst = 0;
        for (int y = 0; y < 48; y++)
            for (int x = 0; x < 64; x++)
                for (int c = 0; c < 3; c++) {
                    double m = 0;
                    for (int k = 0; k < 4; k++) m += big.rgba[4 * ((2 * y + k / 2) * 128 + 2 * x + k % 2) + c];
                    m *= 0.25;
                    double d = fabs(m - small.rgba[4 * (y * 64 + x) + c]) / (fabs(m) + 1e-3);
                    if (d > worst) worst = d;
                }
        printf("supersampling: worst relative difference to the CPU box filter %.2e\n", worst);
        CHECK(worst < 2e-3); /* RGBA16F rounding of the stored samples and the mean */
    }
    prw_image_free(&small);
    prw_image_free(&big);
    prw_scene_destroy(s);
}

static const prw_test_case cases[] = {
    {"supersampling", test_supersampling},
    {"golden", test_golden},
    {"far_from_origin", test_far_from_origin},
    {"point_light_closed_form", test_point_light_closed_form},
};

int main(int argc, char **argv)
{
    prw_threads_set(2);
    int rc = prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
    if (g_gpu) {
        prw_gpu_destroy(g_gpu);
        uint32_t n = prw_gpu_validation_total(); /* includes leak reports made at destroy */
        if (n) {
            fprintf(stderr, "%u validation messages\n", n);
            rc = 1;
        }
    }
    return rc;
}
