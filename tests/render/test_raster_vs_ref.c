/* Raster against reference on the demo scene (issue 3, must-show 4): direct light only, 4x MSAA, 128²;
 * and at 128x72 with the rect light's soft shadows (issue 16: <= 0.04 beyond noise).
 *
 * The rasterizer computes direct light only (no indirect term yet), so it is compared with the path
 * tracer's "direct" light-path filter (emission seen directly plus one scattering vertex).  Two
 * references with different seeds give the reference's own noise; the test requires
 *   mean LDR-FLIP(raster, ref A) - mean LDR-FLIP(ref B, ref A) <= 0.05
 * (FLIP at 67 ppd on the frozen metric tone map of DESIGN.md §5).  It also prints every other metric
 * against the reference and, for information, the full-GI gap: the raster against the unfiltered
 * reference (the part of the image the later GI passes must supply).
 *
 * The remaining raster-vs-reference differences are the rasterizer's documented approximations:
 * hard shadow maps in the 128² case (the reference's rect-light shadows are soft; the 128x72 case
 * turns the soft shadows on), the rect light's specular
 * quadrature (a grid of cells of alpha / 2, or 10 x 10 nodes mapped around the mirror direction), and
 * shadow-map resolution.  The test can fail: the raster image at twice its radiance (one stop) gives
 * about 0.38 beyond noise (checked as a control below), and the previous representative-point
 * specular of the rect light, which overestimated the window's glossy reflection on the floor
 * several-fold, gave 0.10.
 *
 * Light mode (prw_test_light, the sanitizer builds): an eighth of the samples, figures printed, only
 * the control (raster x2) and the comparisons' success checked.
 * Environment: PRW_RVR_SPP (default 64 at 128², 256 at 128x72) reference samples per pixel; PRW_RVR_GI=1 also renders the
 * unfiltered reference and prints the full-GI gap; PRW_RVR_OUT=DIR writes raster.exr,
 * ref_direct_a.exr, ref_direct_b.exr (and ref_all.exr) there for `prw compare`.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_demo.h"
#include "prw_image.h"
#include "prw_metrics.h"
#include "prw_reference.h"
#include "prw_render.h"
#include "prw_test.h"
#include "prw_test_gpu.h"

/* One comparison: image size, the raster's quality, reference spp default and the bound. */
typedef struct rvr_case {
    uint32_t w, h;
    prw_quality q;
    uint64_t spp;
    double margin;
    const char *prefix; /* of the PRW_RVR_OUT file names */
} rvr_case;

static bool render_raster(const prw_scene *s, const prw_view *v, const rvr_case *c, prw_image *hdr, prw_error *e)
{
    prw_render_desc rd = {.width = c->w, .height = c->h, .quality = c->q};
    return prw_test_render(s, &rd, v, 1, hdr, NULL, e);
}

static bool render_ref(prw_ref_renderer *ref, const prw_view *v, uint64_t spp, uint64_t seed, prw_ref_filter_kind k,
                       prw_image *out, prw_error *e)
{
    prw_ref_desc d = {.s0 = 0, .s1 = spp, .seed = seed, .filter = {.kind = k}};
    prw_ref_acc acc = {0};
    prw_ref_stats st;
    float *mean = NULL, *var = NULL;
    bool ok = prw_ref_render(ref, v, &d, &acc, &st, e) && prw_ref_acc_images(&acc, &mean, &var, e);
    if (ok) {
        ok = prw_image_alloc(out, v->width, v->height, e);
        if (ok) memcpy(out->rgba, mean, (size_t)v->width * v->height * 4 * sizeof(float));
        printf("reference %s seed %llu: %llu spp in %.1f s%s\n", k == PRW_REF_DIRECT ? "direct" : "all",
               (unsigned long long)seed, (unsigned long long)st.spp, st.seconds,
               acc.nonfinite ? " (non-finite samples dropped)" : "");
    }
    free(mean);
    free(var);
    prw_ref_acc_free(&acc);
    return ok;
}

static void print_metrics(const char *what, const prw_compare_metrics *m)
{
    printf("  %-28s LDR-FLIP mean %.4f (median %.4f, max %.3f)  HDR-FLIP mean %.4f  PSNR %.2f dB  SSIM %.4f  "
           "relMSE %.5f\n",
           what, m->ldr_flip.mean, m->ldr_flip.weighted_median, m->ldr_flip.max, m->hdr_flip.mean, m->basic.psnr,
           m->ssim, m->basic.relmse);
}

static void write_if(const char *dir, const char *prefix, const char *name, const prw_image *im, double ev100)
{
    if (!dir || !*dir) return;
    char path[4096];
    snprintf(path, sizeof path, "%s/%s%s", dir, prefix, name);
    prw_error e;
    char ev[64];
    snprintf(ev, sizeof ev, "%.17g", ev100);
    prw_kv kv[] = {{"prw:ev100", ev}};
    if (!prw_exr_write(path, im, kv, 1, &e)) fprintf(stderr, "%s\n", e.msg);
    else printf("wrote %s\n", path);
    /* and the metric tone map as PNG, for looking at */
    prw_image tm = {0};
    if (!prw_metric_tonemap(im, ev100, &tm, &e)) return;
    uint8_t *px = prw_malloc((size_t)tm.width * tm.height * 3);
    for (size_t i = 0; i < (size_t)tm.width * tm.height; i++)
        for (int c = 0; c < 3; c++) {
            float v = tm.rgba[i * 4 + c];
            px[i * 3 + c] = (uint8_t)lrintf(255.0f * (v < 0 ? 0 : v > 1 ? 1 : v));
        }
    size_t n = strlen(path);
    if (n > 4) memcpy(path + n - 4, ".png", 4);
    if (prw_png_write8(path, tm.width, tm.height, 3, px, &e)) printf("wrote %s\n", path);
    free(px);
    prw_image_free(&tm);
}

static void run_case(const rvr_case *c)
{
    prw_error e;
    prw_scene *s = prw_scene_create();
    CHECK_OK(prw_demo_build(s, prw_v3(0, 0, 0), &e), &e);
    prw_view v;
    CHECK_OK(prw_ref_view_for_camera(s, "main", c->w, c->h, &v, &e), &e);
    const char *only = getenv("PRW_RVR_ONLY_LIGHT"); /* diagnosis: keep one light (index) */
    if (only)
        for (uint32_t i = 0; i < s->light_count; i++)
            if (i != (uint32_t)atoi(only)) s->lights[i].intensity = 0;

    prw_image raster = {0}, ra = {0}, rb = {0}, rall = {0};
    CHECK_OK(render_raster(s, &v, c, &raster, &e), &e);

    const char *spp_env = getenv("PRW_RVR_SPP");
    /* light mode (sanitizer builds: memory errors, not statistical power): an eighth of the samples,
     * figures printed, the bound not judged (it needs the full reference), the control still checked */
    bool light = prw_test_light() && !spp_env;
    uint64_t spp = spp_env ? strtoull(spp_env, NULL, 10) : (uint64_t)prw_test_scale((int)c->spp, 8);
    if (spp < 1) spp = 1;
    prw_ref_renderer *ref = NULL;
    CHECK_OK(prw_ref_create(s, v.eye, 0, &ref, &e), &e);
    bool with_gi = getenv("PRW_RVR_GI") && atoi(getenv("PRW_RVR_GI")) != 0;
    bool ok = render_ref(ref, &v, spp, 1, PRW_REF_DIRECT, &ra, &e) && render_ref(ref, &v, spp, 2, PRW_REF_DIRECT, &rb, &e) &&
              (!with_gi || render_ref(ref, &v, spp, 1, PRW_REF_ALL, &rall, &e));
    prw_ref_destroy(ref);
    CHECK_OK(ok, &e);

    prw_compare_opts o = {.ev100 = v.ev100};
    prw_compare_metrics err, noise, gi = {0};
    CHECK_OK(prw_compare_images(&raster, &ra, &o, &err, NULL, NULL, &e), &e);
    CHECK_OK(prw_compare_images(&rb, &ra, &o, &noise, NULL, NULL, &e), &e);
    if (with_gi) CHECK_OK(prw_compare_images(&raster, &rall, &o, &gi, NULL, NULL, &e), &e);
    char knobs[1024];
    prw_quality_format(&c->q, knobs, sizeof knobs);
    printf("demo, camera main, %ux%u, EV100 %.2f, reference %llu spp, raster %s:\n", c->w, c->h, v.ev100,
           (unsigned long long)spp, knobs);
    print_metrics("raster vs direct reference", &err);
    print_metrics("reference noise (seed 2 vs 1)", &noise);
    if (with_gi) print_metrics("full-GI gap (raster vs all)", &gi);
    double beyond = err.ldr_flip.mean - noise.ldr_flip.mean;
    printf("  mean LDR-FLIP beyond the reference noise: %.4f (limit %.3f)\n", beyond, c->margin);
    if (light) printf("  (light mode: %llu spp, the limit not judged)\n", (unsigned long long)spp);
    else
        CHECK_MSG(beyond <= c->margin, "FLIP %.4f - noise %.4f = %.4f > %.3f", err.ldr_flip.mean, noise.ldr_flip.mean,
                  beyond, c->margin);
    /* The test must be able to fail: the same comparison with the raster image's exposure off by
     * one stop (a unit or exposure bug of the mildest kind) must exceed the margin. */
    prw_image wrong = {0};
    CHECK_OK(prw_image_alloc(&wrong, c->w, c->h, &e), &e);
    for (size_t i = 0; i < (size_t)c->w * c->h * 4; i++) wrong.rgba[i] = raster.rgba[i] * ((i & 3) == 3 ? 1.0f : 2.0f);
    prw_compare_metrics bad;
    CHECK_OK(prw_compare_images(&wrong, &ra, &o, &bad, NULL, NULL, &e), &e);
    printf("  (control: raster x2 gives FLIP beyond noise %.4f)\n", bad.ldr_flip.mean - noise.ldr_flip.mean);
    CHECK(bad.ldr_flip.mean - noise.ldr_flip.mean > c->margin);
    /* The full-GI gap is larger than the direct-only error: indirect light is missing from the raster. */
    if (with_gi) CHECK(gi.ldr_flip.mean > err.ldr_flip.mean);

    const char *dir = getenv("PRW_RVR_OUT");
    write_if(dir, c->prefix, "raster.exr", &raster, v.ev100);
    write_if(dir, c->prefix, "ref_direct_a.exr", &ra, v.ev100);
    write_if(dir, c->prefix, "ref_direct_b.exr", &rb, v.ev100);
    if (with_gi) write_if(dir, c->prefix, "ref_all.exr", &rall, v.ev100);
    prw_image_free(&wrong);
    prw_image_free(&raster);
    prw_image_free(&ra);
    prw_image_free(&rb);
    prw_image_free(&rall);
    prw_scene_destroy(s);
}

/* 128², 4x MSAA, 2048² shadow map, the default (hard) rect-light shadow: the issue-3 bound. */
static void test_demo_direct(void)
{
    rvr_case c = {.w = 128, .h = 128, .q = prw_quality_default(), .spp = 64, .margin = 0.05, .prefix = ""};
    c.q.msaa = 4;
    c.q.shadow_size = 2048;
    c.q.soft_shadows = 0;
    run_case(&c);
}

/* The soft rect-light shadows (knob soft_shadows, shadows.glsl) at the GI issue's size, 128x72, with the
 * default 1024² shadow map: beyond noise 0.034 at soft_shadows=3 (256 spp references), against 0.060 with
 * the hard shadow — which this bound rejects (checked: soft_shadows=0 fails it). */
static void test_demo_direct_soft(void)
{
    rvr_case c = {.w = 128, .h = 72, .q = prw_quality_default(), .spp = 256, .margin = 0.04, .prefix = "soft_"};
    c.q.msaa = 4;
    c.q.soft_shadows = 3;
    const char *knob = getenv("PRW_RVR_SOFT"); /* diagnosis: another soft_shadows value */
    if (knob) c.q.soft_shadows = (uint32_t)atoi(knob);
    run_case(&c);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {{"demo_direct", test_demo_direct}, {"demo_direct_soft", test_demo_direct_soft}};
    int rc = prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
    return prw_test_gpu_finish() ? 1 : rc; /* one gpu for all cases: pipelines compiled once */
}
