/* GPU tone mapping against the C reference (must-show 1 of issue 6), on lavapipe with the validation
 * layer: per operator and display profile, the display-encoded float signal before quantisation
 * differs from prw_tm_apply by at most 1e-4; the renderer's passes (demo scene, demo path) likewise;
 * extremes stay finite; the pass graph skips the statistics pass when nothing needs it; without
 * display_signal the 8-bit image is the same. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_demo.h"
#include "prw_demo_path.h"
#include "prw_render.h"
#include "prw_test.h"
#include "tm_scenes.h"

static const char *const k_profiles[] = {"srgb", "office-lcd", "default-lcd", "bright-lcd", "hdr10-1000", "hmd-lcd"};

static prw_gpu *g_gpu;
static prw_scene *g_scene;
static prw_renderer *g_r;

static bool up(void)
{
    if (g_r) return true;
    prw_error e;
    prw_gpu_desc d = {.device_index = -1, .validation = true};
    g_scene = prw_scene_create();
    prw_render_desc rd = {.width = 64, .height = 48,   .max_views = 2, .quality = prw_quality_default(),
                          .display_signal = true};
    rd.quality.msaa = 1;
    rd.quality.shadow_size = 256;
    if (!prw_gpu_create(&d, &g_gpu, &e) || !prw_demo_build(g_scene, prw_v3(0, 0, 0), &e) ||
        !prw_renderer_create(g_gpu, g_scene, &rd, &g_r, &e)) {
        fprintf(stderr, "setup: %s\n", e.msg);
        prw_test_failures++;
        return false;
    }
    return true;
}

static double max_diff(const prw_image *a, const prw_image *b, int *at)
{
    double m = 0;
    *at = -1;
    for (int k = 0; k < a->width * a->height; k++)
        for (int c = 0; c < 3; c++) {
            double d = fabs((double)a->rgba[4 * k + c] - (double)b->rgba[4 * k + c]);
            if (!(d <= m)) {
                m = isnan(d) ? INFINITY : d;
                *at = k;
            }
        }
    return m;
}

static bool set_tm(const char *prof, prw_tm_op op, prw_display *d, bool report)
{
    prw_error e;
    prw_display_builtin(prof, d);
    prw_tonemap_settings s = {.op = op, .report = report};
    if (!prw_renderer_set_tonemap(g_r, d, &s, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        return false;
    }
    return true;
}

/* One image through GPU and C; returns the max difference and checks the statistics and counts. */
static double compare_image(const prw_image *hdr, const char *prof, prw_tm_op op, double ev100, const char *what)
{
    prw_display d;
    prw_error e;
    if (!set_tm(prof, op, &d, true)) return INFINITY;
    prw_image gsig = {0}, csig = {0};
    prw_tm_stats gst;
    prw_tm_report grep, crep;
    if (!prw_renderer_tonemap_image(g_r, hdr, ev100, &gsig, &gst, &grep, &e)) {
        CHECK_MSG(false, "%s", e.msg);
        return INFINITY;
    }
    prw_tonemap_settings s = {.op = op, .report = true};
    prw_tm_params p;
    prw_tm_prepare(&s, &d, prw_exposure_scale(ev100), &p);
    prw_tm_stats cst;
    prw_tm_stats_image(hdr, &cst);
    CHECK(prw_tm_apply(&p, &cst, hdr, &csig, &crep, &e));
    int at;
    double m = max_diff(&gsig, &csig, &at);
    CHECK_MSG(m <= 1e-4, "%s %s %s: max |GPU - C| = %.3g at pixel %d (GPU %.7f C %.7f)", what, prof,
              prw_tm_op_name(op), m, at, at >= 0 ? gsig.rgba[4 * at] : 0, at >= 0 ? csig.rgba[4 * at] : 0);
    CHECK_MSG(fabs(gst.log_avg - cst.log_avg) <= 1e-4 * cst.log_avg && fabs(gst.max_lum - cst.max_lum) <= 1e-6 * cst.max_lum &&
                  gst.count == cst.count,
              "%s stats: GPU %.6g %.6g %llu, C %.6g %.6g %llu", what, gst.log_avg, gst.max_lum,
              (unsigned long long)gst.count, cst.log_avg, cst.max_lum, (unsigned long long)cst.count);
    /* classification at a boundary may differ by float rounding: allow 0.1 % of the pixels */
    uint64_t tol = 1 + cst.count / 1000;
    CHECK_MSG(grep.pixels == cst.count && llabs((long long)grep.below_black - (long long)crep.below_black) <= (long long)tol &&
                  llabs((long long)grep.above_peak - (long long)crep.above_peak) <= (long long)tol &&
                  llabs((long long)grep.out_of_gamut - (long long)crep.out_of_gamut) <= (long long)tol,
              "%s %s %s counts GPU %llu/%llu/%llu of %llu, C %llu/%llu/%llu", what, prof, prw_tm_op_name(op),
              (unsigned long long)grep.below_black, (unsigned long long)grep.above_peak,
              (unsigned long long)grep.out_of_gamut, (unsigned long long)grep.pixels,
              (unsigned long long)crep.below_black, (unsigned long long)crep.above_peak,
              (unsigned long long)crep.out_of_gamut);
    prw_image_free(&gsig);
    prw_image_free(&csig);
    return m;
}

static void test_operators(void)
{
    if (!up()) return;
    double worst[PRW_TM_OP_COUNT] = {0};
    const double drs[] = {2, 4, 6};
    for (size_t si = 0; si < PRW_ARRAY_LEN(drs); si++) {
        prw_image hdr;
        double exposure = tm_scene_field(&hdr, 64, 64, drs[si], 7 + (unsigned)si);
        double ev100 = log2(1.0 / (1.2 * exposure));
        for (size_t pi = 0; pi < PRW_ARRAY_LEN(k_profiles); pi++)
            for (int op = 0; op < PRW_TM_OP_COUNT; op++)
                worst[op] = fmax(worst[op], compare_image(&hdr, k_profiles[pi], (prw_tm_op)op, ev100, "field"));
        prw_image_free(&hdr);
    }
    for (int op = 0; op < PRW_TM_OP_COUNT; op++)
        printf("%-9s max |GPU - C| over 6 profiles x 3 fields: %.3g\n", prw_tm_op_name((prw_tm_op)op), worst[op]);
}

static void test_extremes(void)
{
    if (!up()) return;
    for (int x = 0; x < TM_EXT_COUNT; x++) {
        prw_image hdr;
        tm_scene_extreme(&hdr, 40, 33, x);
        for (size_t pi = 0; pi < PRW_ARRAY_LEN(k_profiles); pi++)
            for (int op = 0; op < PRW_TM_OP_COUNT; op++) {
                prw_display d;
                prw_error e;
                if (!set_tm(k_profiles[pi], (prw_tm_op)op, &d, false)) continue;
                prw_image sig = {0};
                if (!prw_renderer_tonemap_image(g_r, &hdr, 7.0, &sig, NULL, NULL, &e)) {
                    CHECK_MSG(false, "%s", e.msg);
                    continue;
                }
                int bad = 0;
                for (int k = 0; k < 40 * 33 * 4; k++) bad += !(sig.rgba[k] >= 0.0f && sig.rgba[k] <= 1.0f);
                CHECK_MSG(bad == 0, "%s %s %s: %d values not in [0, 1]", tm_scene_extreme_name(x), k_profiles[pi],
                          prw_tm_op_name((prw_tm_op)op), bad);
                prw_image_free(&sig);
                /* the C reference on the same input, except NaN/Inf ones (the GPU image is float too) */
                compare_image(&hdr, k_profiles[pi], (prw_tm_op)op, 7.0, tm_scene_extreme_name(x));
            }
        prw_image_free(&hdr);
    }
}

/* The renderer's own passes on the demo scene (two views: one statistics state for both). */
static void test_renderer(void)
{
    if (!up()) return;
    prw_error e;
    prw_view v[2];
    int cam = prw_scene_find_camera(g_scene, "main");
    CHECK_OK(prw_view_from_camera(g_scene, cam, 64, 48, &v[0], &e), &e);
    v[1] = v[0];
    v[1].eye.x += 0.063;
    v[1].view.m[12] -= 0.063;
    for (size_t pi = 0; pi < PRW_ARRAY_LEN(k_profiles); pi++)
        for (int op = 0; op < PRW_TM_OP_COUNT; op++) {
            prw_display d;
            if (!set_tm(k_profiles[pi], (prw_tm_op)op, &d, op == PRW_TM_NEUTRAL)) continue;
            prw_frame_stats st;
            CHECK_OK(prw_renderer_render(g_r, v, 2, &st, &e), &e);
            bool stats_ran = false;
            for (uint32_t i = 0; i < st.pass_count; i++)
                if (strcmp(st.passes[i].name, "tm_stats") == 0) stats_ran = !st.passes[i].skipped;
            /* the pass runs for the operators that key on the statistics; absolute and a report (neutral
             * here) get them and the counts from the apply pass itself (tonemap_fused.comp) */
            bool want = op == PRW_TM_REINHARD || op == PRW_TM_ADAPTIVE || op == PRW_TM_LOCAL || op == PRW_TM_SELECTIVE;
            bool fused = op == PRW_TM_ABSOLUTE || op == PRW_TM_NEUTRAL;
            CHECK_MSG(stats_ran == want, "%s: tm_stats %s", prw_tm_op_name((prw_tm_op)op), stats_ran ? "ran" : "skipped");
            /* C reference over both views' HDR (one statistics state) */
            prw_image hdr[2] = {{0}}, sig[2] = {{0}}, both = {0};
            CHECK_OK(prw_renderer_read_hdr(g_r, 0, &hdr[0], &e) && prw_renderer_read_hdr(g_r, 1, &hdr[1], &e) &&
                         prw_renderer_read_signal(g_r, 0, &sig[0], &e) && prw_renderer_read_signal(g_r, 1, &sig[1], &e),
                     &e);
            prw_image_alloc(&both, 64, 96, &e);
            memcpy(both.rgba, hdr[0].rgba, 64 * 48 * 16);
            memcpy(both.rgba + 64 * 48 * 4, hdr[1].rgba, 64 * 48 * 16);
            prw_tm_stats cst;
            prw_tm_stats_image(&both, &cst);
            prw_tonemap_settings s = {.op = (prw_tm_op)op};
            prw_tm_params p;
            prw_tm_prepare(&s, &d, prw_exposure_scale(v[0].ev100), &p);
            for (int k = 0; k < 2; k++) {
                prw_image c = {0};
                CHECK(prw_tm_apply(&p, &cst, &hdr[k], &c, NULL, &e));
                int at;
                double m = max_diff(&sig[k], &c, &at);
                CHECK_MSG(m <= 1e-4, "demo view %d %s %s: %.3g at %d: in (%.9g %.9g %.9g) GPU (%.7g %.7g %.7g) C (%.7g %.7g %.7g)", k, k_profiles[pi], prw_tm_op_name((prw_tm_op)op), m, at,
                          hdr[k].rgba[4 * at], hdr[k].rgba[4 * at + 1], hdr[k].rgba[4 * at + 2], sig[k].rgba[4 * at],
                          sig[k].rgba[4 * at + 1], sig[k].rgba[4 * at + 2], c.rgba[4 * at], c.rgba[4 * at + 1],
                          c.rgba[4 * at + 2]);
                prw_image_free(&c);
            }
            prw_tm_stats gst;
            prw_tm_report rep;
            bool counted = prw_renderer_tonemap_report(g_r, &gst, &rep);
            CHECK(counted == (op == PRW_TM_ABSOLUTE || op == PRW_TM_NEUTRAL));
            if (counted) CHECK(rep.pixels == 2 * 64 * 48);
            if (stats_ran || fused)
                CHECK_MSG(gst.count == 2 * 64 * 48 && fabs(gst.log_avg - cst.log_avg) <= 1e-4 * cst.log_avg &&
                              fabs(gst.max_lum - cst.max_lum) <= 1e-6 * cst.max_lum,
                          "%s: two-view statistics GPU %.6g %.6g %llu, C %.6g %.6g %llu", prw_tm_op_name((prw_tm_op)op),
                          gst.log_avg, gst.max_lum, (unsigned long long)gst.count, cst.log_avg, cst.max_lum,
                          (unsigned long long)cst.count);
            /* the 8-bit image is the quantised signal */
            uint8_t ldr[64 * 48 * 4];
            CHECK_OK(prw_renderer_read_ldr(g_r, 0, ldr, &e), &e);
            int worst = 0;
            for (int k = 0; k < 64 * 48; k++)
                for (int q = 0; q < 3; q++)
                    worst = PRW_MAX(worst, abs((int)ldr[4 * k + q] - (int)lrintf(sig[0].rgba[4 * k + q] * 255.0f)));
            CHECK_MSG(worst <= 1, "ldr vs signal: %d", worst);
            for (int k = 0; k < 2; k++) {
                prw_image_free(&hdr[k]);
                prw_image_free(&sig[k]);
            }
            prw_image_free(&both);
        }
    /* back to the default: the provisional tone map */
    prw_display d;
    set_tm("srgb", PRW_TM_EXPOSURE, &d, false);
}

static double scene_lum(const float *rgb)
{
    return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2];
}

/* must-show 2 (a) on the demo path: no pixel above peak, < 0.5 % at peak (compressive operators).
 * The demo's window is a flat 2000 cd/m^2 emitter and the frame's brightest object on many path
 * frames: with Reinhard's white point or the adaptive shoulder ending exactly at the frame maximum
 * it sat at peak (1.24 % of a 64x48 frame); PRW_TM_WHITE_HEADROOM puts it just below.  Also printed:
 * "clipped" = at peak although below the frame's largest scene luminance (< 0.999 x). */
static void test_demo_path(void)
{
    if (!up()) return;
    prw_error e;
    prw_camera_path path;
    CHECK_OK(prw_demo_path_build(&path, prw_v3(0, 0, 0), &e), &e);
    const prw_tm_op ops[] = {PRW_TM_REINHARD, PRW_TM_NEUTRAL, PRW_TM_ADAPTIVE};
    for (size_t pi = 1; pi < PRW_ARRAY_LEN(k_profiles); pi++)
        for (size_t oi = 0; oi < PRW_ARRAY_LEN(ops); oi++) {
            prw_display d;
            if (!set_tm(k_profiles[pi], ops[oi], &d, false)) continue;
            double over = 0;
            long at_peak = 0, clipped = 0, total = 0;
            for (uint64_t f = 0; f < PRW_DEMO_PATH_FRAMES; f += 6) {
                prw_view v;
                prw_image sig = {0}, hdr = {0};
                CHECK_OK(prw_camera_path_frame_view(&path, f, 64, 48, 0.05, 7.0, 0, &v, &e), &e);
                CHECK_OK(prw_renderer_render(g_r, &v, 1, NULL, &e) && prw_renderer_read_signal(g_r, 0, &sig, &e) &&
                             prw_renderer_read_hdr(g_r, 0, &hdr, &e),
                         &e);
                double lmin = prw_display_min(&d), lmax = prw_display_max(&d), ymax = 0;
                for (int k = 0; k < 64 * 48; k++) ymax = fmax(ymax, scene_lum(hdr.rgba + 4 * k));
                for (int k = 0; k < 64 * 48; k++) {
                    double y = tm_displayed_lum(&d, sig.rgba + 4 * k);
                    over = fmax(over, (y - d.peak) / d.peak);
                    bool top = (y - lmin) / (lmax - lmin) >= 1 - 1e-4;
                    at_peak += top;
                    clipped += top && scene_lum(hdr.rgba + 4 * k) < 0.999 * ymax;
                    total++;
                }
                prw_image_free(&sig);
                prw_image_free(&hdr);
            }
            printf("demo path %-12s %-9s max over peak %+.2e, clipped at peak %.3f %% (at peak %.3f %%)\n",
                   k_profiles[pi], prw_tm_op_name(ops[oi]), over, 100.0 * clipped / total, 100.0 * at_peak / total);
            CHECK(over <= 1e-6);
            CHECK_MSG((double)at_peak / total < 0.005, "%s %s: %.3f %% at peak", k_profiles[pi],
                      prw_tm_op_name(ops[oi]), 100.0 * at_peak / total);
            CHECK_MSG(clipped <= at_peak, "%s %s: clipped count", k_profiles[pi], prw_tm_op_name(ops[oi]));
        }
    prw_camera_path_free(&path);
    prw_display d;
    set_tm("srgb", PRW_TM_EXPOSURE, &d, false);
}

/* A renderer without display_signal: the graph drops the float signal and the passes write the 8-bit
 * image alone (the shaders' no-signal variants); that image and the counts equal those of the renderer
 * that keeps the signal, for every path (apply, fused statistics, separable local, selective), and
 * reading the signal is a clear error. */
static void test_no_signal(void)
{
    if (!up()) return;
    prw_error e;
    prw_renderer *r2 = NULL;
    prw_render_desc rd = {.width = 64, .height = 48, .max_views = 2, .quality = prw_quality_default()};
    rd.quality.msaa = 1;
    rd.quality.shadow_size = 256;
    CHECK_OK(prw_renderer_create(g_gpu, g_scene, &rd, &r2, &e), &e);
    if (!r2) return;
    prw_view v[2];
    CHECK_OK(prw_view_from_camera(g_scene, prw_scene_find_camera(g_scene, "main"), 64, 48, &v[0], &e), &e);
    v[1] = v[0];
    v[1].eye.x += 0.063;
    v[1].view.m[12] -= 0.063;
    const char *profs[] = {"srgb", "hdr10-1000"};
    for (size_t pi = 0; pi < PRW_ARRAY_LEN(profs); pi++)
        for (int op = 0; op < PRW_TM_OP_COUNT; op++) {
            prw_display d;
            prw_display_builtin(profs[pi], &d);
            prw_tonemap_settings s = {.op = (prw_tm_op)op, .report = op == PRW_TM_NEUTRAL || op == PRW_TM_EXPOSURE};
            uint8_t a[2][64 * 48 * 4], b[2][64 * 48 * 4];
            CHECK_OK(prw_renderer_set_tonemap(g_r, &d, &s, &e) && prw_renderer_set_tonemap(r2, &d, &s, &e) &&
                         prw_renderer_render(g_r, v, 2, NULL, &e) && prw_renderer_render(r2, v, 2, NULL, &e) &&
                         prw_renderer_read_ldr(g_r, 0, a[0], &e) && prw_renderer_read_ldr(g_r, 1, a[1], &e) &&
                         prw_renderer_read_ldr(r2, 0, b[0], &e) && prw_renderer_read_ldr(r2, 1, b[1], &e),
                     &e);
            CHECK_MSG(memcmp(a, b, sizeof a) == 0, "%s %s: the 8-bit images differ without the signal", profs[pi],
                      prw_tm_op_name((prw_tm_op)op));
            prw_tm_stats sa, sb;
            prw_tm_report ra, rb;
            bool ca = prw_renderer_tonemap_report(g_r, &sa, &ra), cb = prw_renderer_tonemap_report(r2, &sb, &rb);
            CHECK_MSG(ca == cb && (!ca || (ra.pixels == rb.pixels && ra.below_black == rb.below_black &&
                                           ra.above_peak == rb.above_peak && ra.out_of_gamut == rb.out_of_gamut)),
                      "%s %s: counts differ without the signal", profs[pi], prw_tm_op_name((prw_tm_op)op));
        }
    prw_image sig = {0};
    CHECK(!prw_renderer_read_signal(r2, 0, &sig, &e) && strstr(e.msg, "display_signal"));
    prw_renderer_destroy(r2);
    prw_display d;
    set_tm("srgb", PRW_TM_EXPOSURE, &d, false);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"operators", test_operators},
        {"extremes", test_extremes},
        {"renderer", test_renderer},
        {"demo_path", test_demo_path},
        {"no_signal", test_no_signal},
    };
    int rc = prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
    prw_renderer_destroy(g_r);
    prw_scene_destroy(g_scene);
    if (g_gpu) {
        uint32_t n = prw_gpu_validation_count(g_gpu);
        prw_gpu_destroy(g_gpu);
        if (n || prw_gpu_validation_total()) {
            fprintf(stderr, "%u validation messages\n", prw_gpu_validation_total());
            rc = 1;
        }
    }
    return rc;
}
