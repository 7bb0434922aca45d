/* The stereo_reuse=reproject knob (issue 5, engine/render/pass_reproject.c) on lavapipe with the
 * validation layer, 128x128 per eye:
 *  - knob_off_unchanged: with the knob off, each eye of a two-view frame is bit-identical to a mono
 *    render from that eye (the base pass is today's); with it on, the left eye still is, and a
 *    one-view renderer with the knob on renders exactly as one with it off;
 *  - reuse_nothing_is_full: with a negative tolerance (nothing reused) the right eye goes through the
 *    depth pre-pass + stencil path and must equal the fully shaded right eye bit for bit with msaa 1 --
 *    so the pre-pass / GREATER_OR_EQUAL / stencil machinery loses and duplicates nothing; with msaa 4
 *    (right eye 2x2-supersampled, see pass_reproject.c) LDR-FLIP against the 4x MSAA eye <= 0.02;
 *  - disocclusion_strip (closed form): an emissive plane at z1 = 2 m covering x < 0 in front of an
 *    emissive background at z2 = 6 m, parallel eyes at x = -+b/2 (b = 0.3 m): the holes of the right
 *    eye are (a) the strip the left eye cannot see behind the plane's edge, b f (1/z1 - 1/z2) pixels
 *    wide, starting at the edge, and (b) the right border strip outside the left image, b f / z2
 *    pixels; each within 1 px in every checked row (msaa 1; with msaa 4 within 1.5 px: edge texels
 *    are shaded again).  Reused pixels equal the full render exactly (emission is view-independent).
 *    Control: with the depth agreement switched off (tolerance 1e6) the strip is not found;
 *  - demo_flip: the demo scene from camera 0, desktop eyes (IPD 0.063 m, screen 0.7 m), msaa 4:
 *    LDR-FLIP (project metric) of the reprojected right eye vs the fully shaded one is printed and must
 *    be <= 0.05, the shaded share is printed and must lie in (0, 0.5), no NaN/Inf anywhere; control:
 *    the left eye taken as the right eye must be more than twice as far (FLIP) from the full right eye.
 *  - multiview_refused: the knob with the multiview backend fails with a clear message. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_demo.h"
#include "prw_metrics.h"
#include "prw_render.h"
#include "prw_stereo.h"
#include "prw_test.h"

static prw_gpu *g_gpu;

static bool up(void)
{
    if (g_gpu) return true;
    prw_error e;
    prw_gpu_desc d = {.device_index = -1, .validation = true};
    if (!prw_gpu_create(&d, &g_gpu, &e)) {
        fprintf(stderr, "setup: %s\n", e.msg);
        prw_test_failures++;
        return false;
    }
    return true;
}

/* Renders views[0..n) with desc d; copies the HDR images of the first n views into out. */
static bool render(const prw_scene *s, prw_render_desc d, const prw_view *views, uint32_t n, prw_image *out)
{
    prw_error e = {{0}};
    prw_renderer *r = NULL;
    d.max_views = d.max_views ? d.max_views : n;
    bool ok = prw_renderer_create(g_gpu, s, &d, &r, &e) && prw_renderer_render(r, views, n, NULL, &e);
    for (uint32_t v = 0; ok && v < n; v++) ok = prw_renderer_read_hdr(r, v, &out[v], &e);
    prw_renderer_destroy(r);
    if (!ok) {
        fprintf(stderr, "render: %s\n", e.msg);
        prw_test_failures++;
    }
    return ok;
}

static bool same(const prw_image *a, const prw_image *b)
{
    return a->rgba && b->rgba && a->width == b->width && a->height == b->height &&
           memcmp(a->rgba, b->rgba, (size_t)a->width * a->height * 4 * sizeof(float)) == 0;
}

static size_t count_diff_rgb(const prw_image *a, const prw_image *b)
{
    size_t n = 0;
    for (size_t i = 0; i < (size_t)a->width * a->height; i++)
        for (int c = 0; c < 3; c++)
            if (a->rgba[i * 4 + c] != b->rgba[i * 4 + c]) {
                n++;
                break;
            }
    return n;
}

static bool all_finite(const prw_image *a)
{
    for (size_t i = 0; i < (size_t)a->width * a->height * 4; i++)
        if (!isfinite(a->rgba[i])) return false;
    return true;
}

static void free_images(prw_image *im, int n)
{
    for (int i = 0; i < n; i++) prw_image_free(&im[i]);
}

/* The debug switches of a desc, in storage that lives as long as the test (renderers copy it at create). */
static prw_render_debug *dbg_of(prw_render_desc *d)
{
    static prw_render_debug pool[16];
    static unsigned n;
    prw_render_debug *p = &pool[n++ % 16];
    *p = d->debug ? *d->debug : (prw_render_debug){0};
    d->debug = p;
    return p;
}

static prw_render_desc base_desc(uint32_t w, uint32_t h, uint32_t msaa)
{
    prw_render_desc d = {.width = w, .height = h, .quality = prw_quality_default()};
    d.quality.msaa = msaa;
    d.quality.shadow_size = 512;
    return d;
}

static prw_scene *g_demo;

static bool demo_eyes(prw_view eyes[2])
{
    prw_error e = {{0}};
    if (!g_demo) {
        g_demo = prw_scene_create();
        if (!prw_demo_build(g_demo, prw_v3(0, 0, 0), &e)) {
            fprintf(stderr, "demo: %s\n", e.msg);
            prw_test_failures++;
            return false;
        }
    }
    prw_view centre;
    if (!prw_view_from_camera(g_demo, 0, 128, 128, &centre, &e) || !prw_stereo_desktop(&centre, 0.063, 0.7, eyes, &e)) {
        fprintf(stderr, "views: %s\n", e.msg);
        prw_test_failures++;
        return false;
    }
    return true;
}

static void test_knob_off_unchanged(void)
{
    if (!up()) return;
    prw_view eyes[2];
    if (!demo_eyes(eyes)) return;
    prw_image mono[2] = {{0}}, off[2] = {{0}}, on[2] = {{0}}, mono_on = {0};
    prw_render_desc d = base_desc(128, 128, 4);
    bool ok = render(g_demo, d, &eyes[0], 1, &mono[0]) && render(g_demo, d, &eyes[1], 1, &mono[1]) &&
              render(g_demo, d, eyes, 2, off);
    prw_render_desc don = d;
    don.quality.stereo_reuse = PRW_STEREO_REUSE_REPROJECT;
    ok = ok && render(g_demo, don, eyes, 2, on) && render(g_demo, don, &eyes[1], 1, &mono_on);
    if (ok) {
        CHECK_MSG(same(&off[0], &mono[0]) && same(&off[1], &mono[1]), "knob off: eyes differ from mono");
        CHECK_MSG(same(&on[0], &mono[0]), "knob on: the left eye differs from mono");
        CHECK_MSG(same(&mono_on, &mono[1]), "knob on, one view: differs from knob off");
        CHECK_MSG(!same(&on[1], &mono[1]), "knob on: the right eye did not change at all (reuse not active?)");
    }
    free_images(mono, 2);
    free_images(off, 2);
    free_images(on, 2);
    prw_image_free(&mono_on);
}

static double ldr_flip(const prw_image *test, const prw_image *ref, double ev100);

static void test_reuse_nothing_is_full(void)
{
    if (!up()) return;
    prw_view eyes[2];
    if (!demo_eyes(eyes)) return;
    for (uint32_t msaa = 1; msaa <= 4; msaa += 3) {
        prw_image full = {0}, on[2] = {{0}};
        prw_render_desc d = base_desc(128, 128, msaa);
        prw_render_desc dn = d;
        dn.quality.stereo_reuse = PRW_STEREO_REUSE_REPROJECT;
        dbg_of(&dn)->reproject_tolerance = -1; /* reuse nothing */
        if (render(g_demo, d, &eyes[1], 1, &full) && render(g_demo, dn, eyes, 2, on)) {
            size_t diff = count_diff_rgb(&on[1], &full);
            if (msaa == 1) {
                printf("msaa 1, nothing reused: %zu of %d right-eye pixels differ from the full render\n", diff,
                       128 * 128);
                CHECK(diff == 0);
                CHECK(same(&on[1], &full));
            } else { /* the right eye is 2x2-supersampled instead of 4x MSAA: close, not identical */
                double fl = ldr_flip(&on[1], &full, eyes[1].ev100);
                printf("msaa 4, nothing reused (right eye 2x2 supersampled): LDR-FLIP vs 4x MSAA %.4f, %zu pixels "
                       "differ\n",
                       fl, diff);
                CHECK(fl >= 0 && fl <= 0.02);
                CHECK(all_finite(&on[1]));
            }
        }
        prw_image_free(&full);
        free_images(on, 2);
    }
}

/* Emissive background plane z = -z2 and foreground plane z = -z1 covering x < 0 (|y| < 0.25 z1). */
static prw_scene *strip_scene(double z1, double z2)
{
    prw_error e = {{0}};
    prw_scene *s = prw_scene_create();
    prw_material bg = prw_material_default(), fg = prw_material_default();
    bg.base_color[0] = bg.base_color[1] = bg.base_color[2] = 0.0f;
    fg.base_color[0] = fg.base_color[1] = fg.base_color[2] = 0.0f;
    bg.specular = fg.specular = 0.0f;
    bg.emission[0] = 20, bg.emission[1] = 60, bg.emission[2] = 100;
    fg.emission[0] = 200, fg.emission[1] = 80, fg.emission[2] = 10;
    int mb = prw_scene_add_material(s, &bg), mf = prw_scene_add_material(s, &fg);
    /* front faces towards +z (the camera): cross(u, v) = +z */
    bool ok = prw_scene_add_quad(s, "bg", prw_v3(0, 0, -z2), prw_v3(50, 0, 0), prw_v3(0, 50, 0), mb, &e) >= 0 &&
              prw_scene_add_quad(s, "fg", prw_v3(-10, 0, -z1), prw_v3(10, 0, 0), prw_v3(0, 0.25 * z1, 0), mf, &e) >= 0;
    CHECK_MSG(ok, "%s", e.msg);
    prw_scene_update(s);
    return s;
}

static void strip_case(uint32_t msaa, double tol_px, double depth_tol)
{
    const double z1 = 2.0, z2 = 6.0, b = 0.3, yfov = 60.0 * PRW_PI / 180.0;
    const int W = 128, H = 128;
    prw_scene *s = strip_scene(z1, z2);
    prw_view eyes[2];
    for (int k = 0; k < 2; k++) {
        double x = (k ? 0.5 : -0.5) * b;
        eyes[k] = prw_view_look_at(prw_v3(x, 0, 0), prw_v3(x, 0, -1), prw_v3(0, 1, 0), yfov, 0.05, W, H, 0);
    }
    double f = 0.5 * H / tan(0.5 * yfov); /* pixels */
    double strip = b * f * (1 / z1 - 1 / z2), border = b * f / z2;
    /* the plane's edge x = 0 in the right image: u = W/2 + f (0 - b/2) / z1 */
    double edge = 0.5 * W - f * 0.5 * b / z1;
    prw_image full = {0}, on[2] = {{0}};
    prw_render_desc d = base_desc(W, H, msaa);
    prw_render_desc dn = d;
    dn.quality.stereo_reuse = PRW_STEREO_REUSE_REPROJECT;
    dbg_of(&dn)->reproject_mark = true;
    dbg_of(&dn)->reproject_tolerance = depth_tol;
    if (render(s, d, &eyes[1], 1, &full) && render(s, dn, eyes, 2, on)) {
        const prw_image *r = &on[1];
        double worst_strip = 0, worst_border = 0, worst_start = 0, other = 0;
        int rows = 0;
        /* rows well inside the plane's height (|y| < 0.25 z1 at z1: +-0.25 f px around the centre) */
        for (int y = H / 2 - (int)(0.2 * f); y <= H / 2 + (int)(0.2 * f); y++, rows++) {
            double in_strip = 0, in_border = 0, first = -1;
            for (int x = 0; x < W; x++) {
                double a = r->rgba[4 * ((size_t)y * W + x) + 3]; /* share of the pixel shaded by the right eye */
                if (x >= W - (int)ceil(border) - 2) in_border += a;
                else if (x >= (int)edge - 3 && x <= (int)(edge + strip) + 3) {
                    in_strip += a;
                    if (a > 0.5 && first < 0) first = x;
                } else other += a;
            }
            worst_strip = fmax(worst_strip, fabs(in_strip - strip));
            worst_border = fmax(worst_border, fabs(in_border - border));
            worst_start = fmax(worst_start, fabs(first - edge));
        }
        if (depth_tol > 1) { /* control: without the depth test the strip is reused (wrongly) */
            printf("control, depth test off: strip off by %.3f px (must exceed %.1f)\n", worst_strip, 0.5 * strip);
            CHECK(worst_strip > 0.5 * strip);
            prw_image_free(&full);
            free_images(on, 2);
            prw_scene_destroy(s);
            return;
        }
        printf("msaa %u, %d rows: disoccluded strip expected %.3f px (b f (1/z1 - 1/z2)), worst row off by %.3f px; "
               "border strip expected %.3f px (b f / z2), worst off by %.3f px; strip start vs plane edge %.3f px "
               "worst; other shaded pixels %.2f\n",
               msaa, rows, strip, worst_strip, border, worst_border, worst_start, other);
        CHECK(worst_strip <= tol_px);
        CHECK(worst_border <= tol_px);
        CHECK(worst_start <= tol_px);
        CHECK(other <= 0.5 * tol_px * rows); /* nothing else is a hole (MSAA: a few fractional edge pixels) */
        CHECK(all_finite(r));
        /* reused pixels (alpha 0) are exactly the fully rendered ones: emission does not depend on the view */
        size_t reused = 0, wrong = 0;
        for (size_t i = 0; i < (size_t)W * H; i++) {
            if (r->rgba[4 * i + 3] != 0.0f) continue;
            reused++;
            for (int c = 0; c < 3; c++)
                if (fabsf(r->rgba[4 * i + c] - full.rgba[4 * i + c]) > 1e-3f * full.rgba[4 * i + c]) {
                    wrong++;
                    break;
                }
        }
        printf("msaa %u: %zu fully reused pixels, %zu differ from the full render by > 1e-3 relative\n", msaa, reused,
               wrong);
        CHECK(reused > (size_t)W * H / 2);
        CHECK(wrong == 0);
    }
    prw_image_free(&full);
    free_images(on, 2);
    prw_scene_destroy(s);
}

static void test_disocclusion_strip(void)
{
    if (!up()) return;
    strip_case(1, 1.0, 0);
    strip_case(4, 1.5, 0);
    strip_case(1, 1.0, 1e6);
}

static double ldr_flip(const prw_image *test, const prw_image *ref, double ev100)
{
    prw_error e = {{0}};
    prw_image a = {0}, b = {0};
    size_t n = (size_t)ref->width * ref->height;
    float *map = prw_malloc(n * sizeof *map);
    double mean = -1;
    if (prw_metric_tonemap(test, ev100, &a, &e) && prw_metric_tonemap(ref, ev100, &b, &e) &&
        prw_flip_ldr_encoded(&a, &b, PRW_FLIP_DEFAULT_PPD, map, &e)) {
        prw_flip_stats st;
        prw_flip_pool(map, n, &st);
        mean = st.mean;
    } else {
        fprintf(stderr, "flip: %s\n", e.msg);
        prw_test_failures++;
    }
    free(map);
    prw_image_free(&a);
    prw_image_free(&b);
    return mean;
}

static void test_demo_flip(void)
{
    if (!up()) return;
    prw_view eyes[2];
    if (!demo_eyes(eyes)) return;
    prw_image full = {0}, on[2] = {{0}};
    prw_render_desc d = base_desc(128, 128, 4);
    prw_render_desc dn = d;
    dn.quality.stereo_reuse = PRW_STEREO_REUSE_REPROJECT;
    dbg_of(&dn)->reproject_mark = true;
    if (render(g_demo, d, &eyes[1], 1, &full) && render(g_demo, dn, eyes, 2, on)) {
        CHECK(all_finite(&on[0]) && all_finite(&on[1]));
        double shaded = 0;
        for (size_t i = 0; i < 128 * 128; i++) shaded += on[1].rgba[4 * i + 3];
        shaded /= 128 * 128;
        if (getenv("PRW_REUSE_DUMP")) { /* debugging aid: the shaded share as a PGM */
            FILE *f = fopen(getenv("PRW_REUSE_DUMP"), "wb");
            if (f) {
                fprintf(f, "P5 128 128 255\n");
                for (size_t i = 0; i < 128 * 128; i++) fputc((int)(255 * on[1].rgba[4 * i + 3]), f);
                fclose(f);
            }
        }
        /* control: the left eye itself as the right eye (no reprojection) */
        double fl = ldr_flip(&on[1], &full, eyes[1].ev100), fc = ldr_flip(&on[0], &full, eyes[1].ev100);
        printf("demo, camera 0, 128x128, msaa 4, desktop eyes IPD 0.063 m: right eye LDR-FLIP vs full %.4f, "
               "%.1f %% of its pixels shaded; control (left eye as the right eye) FLIP %.4f\n",
               fl, 100 * shaded, fc);
        CHECK(fl >= 0 && fl <= 0.05);
        CHECK(shaded > 0 && shaded < 0.5);
        CHECK(fc > 2 * fl);
    }
    prw_image_free(&full);
    free_images(on, 2);
}

static void test_multiview_refused(void)
{
    if (!up()) return;
    if (!prw_gpu_features_enabled(g_gpu)->multiview) {
        printf("device lacks multiview: skipped\n");
        return;
    }
    prw_view eyes[2];
    if (!demo_eyes(eyes)) return;
    prw_render_desc d = base_desc(64, 64, 1);
    d.max_views = 2;
    d.views_backend = PRW_VIEWS_MULTIVIEW;
    d.quality.stereo_reuse = PRW_STEREO_REUSE_REPROJECT;
    prw_renderer *r = NULL;
    prw_error e = {{0}};
    CHECK(!prw_renderer_create(g_gpu, g_demo, &d, &r, &e));
    CHECK(strstr(e.msg, "per-view loop backend only") != NULL);
    prw_renderer_destroy(r);
}

/* Measurement, not a test (runs only with PRW_REUSE_TIMING=WxH): base-pass GPU time (timestamps) of the
 * demo frame from camera 0, mono / stereo with the knob off / on / on with nothing reused, msaa 1 and 4;
 * the eight renderers take turns for 5 rounds (the first is dropped), medians printed. */
static int cmp_d(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static void test_timing(void)
{
    const char *sz = getenv("PRW_REUSE_TIMING");
    if (!sz) {
        printf("PRW_REUSE_TIMING=WxH not set: skipped\n");
        return;
    }
    if (!up()) return;
    unsigned w = 320, h = 180;
    if (sscanf(sz, "%ux%u", &w, &h) != 2) return;
    prw_error e = {{0}};
    prw_view tmp[2], centre, eyes[2];
    if (!demo_eyes(tmp)) return;
    if (!prw_view_from_camera(g_demo, 0, w, h, &centre, &e) || !prw_stereo_desktop(&centre, 0.063, 0.7, eyes, &e)) return;
    enum { NC = 8, ROUNDS = 5 };
    prw_renderer *r[NC] = {0};
    double ms[NC][ROUNDS] = {{0}};
    for (int c = 0; c < NC; c++) {
        int mode = c % 4;
        prw_render_desc d = base_desc(w, h, c < 4 ? 1 : 4);
        d.timestamps = true;
        d.max_views = mode ? 2 : 1;
        d.quality.stereo_reuse = mode >= 2 ? PRW_STEREO_REUSE_REPROJECT : PRW_STEREO_REUSE_OFF;
        dbg_of(&d)->reproject_tolerance = mode == 3 ? -1 : 0;
        if (!prw_renderer_create(g_gpu, g_demo, &d, &r[c], &e)) {
            fprintf(stderr, "%s\n", e.msg);
            prw_test_failures++;
            goto done;
        }
    }
    for (int k = 0; k < ROUNDS; k++)
        for (int c = 0; c < NC; c++) {
            int mode = c % 4;
            prw_frame_stats st;
            if (!prw_renderer_render(r[c], mode ? eyes : &centre, mode ? 2 : 1, &st, &e)) goto done;
            for (uint32_t p = 0; p < st.pass_count; p++)
                if (!strcmp(st.passes[p].name, "base")) ms[c][k] = st.passes[p].gpu_ms;
        }
    for (int c = 0; c < NC; c++) {
        static const char *names[4] = {"mono", "stereo off", "stereo reproject", "stereo reproject, nothing reused"};
        qsort(&ms[c][1], ROUNDS - 1, sizeof(double), cmp_d);
        printf("%ux%u msaa %d %-34s base pass (both eyes) median %.1f ms\n", w, h, c < 4 ? 1 : 4, names[c % 4],
               0.5 * (ms[c][2] + ms[c][3]));
    }
done:
    for (int c = 0; c < NC; c++) prw_renderer_destroy(r[c]);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"knob_off_unchanged", test_knob_off_unchanged},
        {"reuse_nothing_is_full", test_reuse_nothing_is_full},
        {"disocclusion_strip", test_disocclusion_strip},
        {"demo_flip", test_demo_flip},
        {"multiview_refused", test_multiview_refused},
        {"timing", test_timing},
    };
    int rc = prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
    prw_scene_destroy(g_demo);
    if (g_gpu) {
        uint32_t n = prw_gpu_validation_count(g_gpu);
        prw_gpu_destroy(g_gpu);
        if (n || prw_gpu_validation_total()) {
            fprintf(stderr, "%u Vulkan validation messages\n", prw_gpu_validation_total());
            rc = 1;
        }
    }
    return rc;
}
