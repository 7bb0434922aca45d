/* Full GI in the rasterizer on the Cornell box glTF (issue 16, must-show 2): the base pass with the
 * emissive ceiling quad as a rect light and the baked indirect diffuse light maps, against the path
 * tracer's full image, 4x MSAA, shadow map 2048, validation layer on.
 *
 * The scene is written here (tests/reference/cornell_gltf.c: classic geometry, Lambert, an emissive
 * ceiling quad, no light source) and baked here with the renderer's default bake (radiosity_size of
 * prw_quality_default(), PRW_GI_DEFAULT_SAMPLES, PRW_GI_DEFAULT_FILTER_RADIUS; no cache).
 * References: all light with seeds 1 and 2 (the noise), direct light (seed 3) for the indirect part,
 * the emission filter (seed 4) for the emitter mask (as test_emissive_raster: a pixel is out where
 * the emission filter is not 0, so partly covered edge pixels are out too).
 * Over the pixels that are not the emitter:
 *   - mean radiance per channel of the raster image within MEAN_BOUND of reference A's,
 *   - the indirect part, mean(image) - mean(direct reference), per channel within INDIRECT_BOUND of
 *     mean(A) - mean(direct reference),
 *   - LDR-FLIP beyond noise = mean FLIP(raster, A) - mean FLIP(B, A) <= FLIP_BOUND (metric tone map
 *     at EV100 8, the box's exposure).
 * The noise of each figure (B in place of the raster) is printed beside it.  A control renders without
 * light maps (the indirect part missing) and must fail the indirect criterion and the mean criterion;
 * the light-map term scaled by 0.9 (image = no-maps + 0.9 (raster - no-maps)) is printed for
 * information (at 128x128 it reads 0.048 on the mean and 0.096 on the indirect part: both bounds catch it).
 * The bake gathers with the same path tracer as the reference (the choice of solver); the
 * rasterizer's storage, filtering, lookup and shading of it are what is checked here.
 *
 * Light mode (prw_test_light, the sanitizer builds): 64x64, 32 spp, a reduced bake, figures printed
 * but only the control and finiteness checked (the bounds need the full sizes).
 * Environment: PRW_CGI_SIZE (image side, default 256), PRW_CGI_SPP (reference spp, default 32: at 64, 128 and 256
 * the figures moved by <= 0.0006 and the verdicts were the same; the noise guard below keeps the reference
 * noise under a quarter of each bound),
 * PRW_CGI_RADIOSITY / PRW_CGI_SAMPLES (bake, default: the renderer's), PRW_CGI_OUT=DIR writes
 * raster.exr, nolm.exr, ref_a.exr, ref_b.exr, ref_direct.exr there for `prw compare`. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cornell_gltf.h"
#include "lightmaps.h"
#include "prw_gi.h"
#include "prw_image.h"
#include "prw_metrics.h"
#include "prw_reference.h"
#include "prw_render.h"
#include "prw_test.h"
#include "prw_test_gpu.h"

#define MEAN_BOUND 0.03
#define INDIRECT_BOUND 0.05
#define FLIP_BOUND 0.05
#define EV100 8.0 /* glTF cameras carry none; the box's walls are some 100 cd/m^2 */

static uint32_t g_size;

static unsigned long env_u(const char *name, unsigned long def)
{
    const char *v = getenv(name);
    return v && *v ? strtoul(v, NULL, 10) : def;
}

static bool render_raster(const prw_scene *s, const prw_view *v, const prw_lightmaps *lm, prw_image *hdr, prw_error *e)
{
    prw_render_desc rd = {.width = g_size, .height = g_size, .quality = prw_quality_default(), .lightmaps = lm};
    rd.quality.msaa = 4;
    rd.quality.shadow_size = 2048;
    return prw_test_render(s, &rd, v, 1, hdr, NULL, e);
}

static const char *kind_name(prw_ref_filter_kind k)
{
    return k == PRW_REF_ALL ? "all" : k == PRW_REF_DIRECT ? "direct" : "emission";
}

static bool render_ref(prw_ref_renderer *ref, const prw_view *v, uint64_t spp, uint64_t seed, prw_ref_filter_kind k,
                       prw_image *out, prw_error *e)
{
    prw_ref_desc d = {.s0 = 0, .s1 = spp, .seed = seed, .filter = {.kind = k}};
    prw_ref_acc acc = {0};
    prw_ref_stats st;
    float *mean = NULL, *var = NULL;
    bool ok = prw_ref_render(ref, v, &d, &acc, &st, e) && prw_ref_acc_images(&acc, &mean, &var, e) &&
              prw_image_alloc(out, g_size, g_size, e);
    if (ok) {
        memcpy(out->rgba, mean, (size_t)g_size * g_size * 4 * sizeof(float));
        printf("reference %s seed %llu: %llu spp in %.1f s\n", kind_name(k), (unsigned long long)seed,
               (unsigned long long)st.spp, st.seconds);
    }
    free(mean);
    free(var);
    prw_ref_acc_free(&acc);
    return ok;
}

/* Per-channel means over the pixels where mask is 0. */
static void masked_mean(const prw_image *im, const uint8_t *mask, double out[3])
{
    double sum[3] = {0, 0, 0};
    size_t n = 0;
    for (size_t i = 0; i < (size_t)g_size * g_size; i++) {
        if (mask[i]) continue;
        for (int c = 0; c < 3; c++) sum[c] += im->rgba[4 * i + (size_t)c];
        n++;
    }
    for (int c = 0; c < 3; c++) out[c] = n ? sum[c] / (double)n : 0.0;
}

/* The largest relative difference per channel of test against ref (ref > 0 expected). */
static double worst_rel(const double test[3], const double ref[3])
{
    double w = 0;
    for (int c = 0; c < 3; c++) {
        double d = ref[c] > 0 ? fabs(test[c] / ref[c] - 1.0) : INFINITY;
        if (d > w) w = d;
    }
    return w;
}

/* Mean LDR-FLIP (metric tone map at EV100) of test against ref over the pixels where mask is 0. */
static bool masked_flip(const prw_image *test, const prw_image *ref, const uint8_t *mask, double *out, prw_error *e)
{
    prw_image te = {0}, re = {0};
    float *map = prw_malloc((size_t)g_size * g_size * sizeof(float));
    bool ok = prw_metric_tonemap(test, EV100, &te, e) && prw_metric_tonemap(ref, EV100, &re, e) &&
              prw_flip_ldr_encoded(&te, &re, PRW_FLIP_DEFAULT_PPD, map, e);
    double f = 0;
    size_t n = 0;
    for (size_t i = 0; ok && i < (size_t)g_size * g_size; i++)
        if (!mask[i]) f += map[i], n++;
    *out = n ? f / (double)n : 0;
    free(map);
    prw_image_free(&te);
    prw_image_free(&re);
    return ok;
}

static void write_if(const char *dir, const char *name, const prw_image *im)
{
    if (!dir || !*dir) return;
    char path[4096], ev[64];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    snprintf(ev, sizeof ev, "%.17g", EV100);
    prw_kv kv[] = {{"prw:ev100", ev}};
    prw_error e;
    if (prw_exr_write(path, im, kv, 1, &e)) printf("wrote %s\n", path);
    else fprintf(stderr, "%s\n", e.msg);
}

typedef struct figures {
    double mean[3], indirect[3]; /* means over the non-emitter pixels; indirect = mean - direct reference's */
    double mean_err, indirect_err, flip;
} figures;

static bool figures_of(const prw_image *im, const prw_image *ra, const uint8_t *mask, const double mra[3],
                       const double mdir[3], figures *f, prw_error *e)
{
    double ind_ref[3];
    masked_mean(im, mask, f->mean);
    for (int c = 0; c < 3; c++) f->indirect[c] = f->mean[c] - mdir[c], ind_ref[c] = mra[c] - mdir[c];
    f->mean_err = worst_rel(f->mean, mra);
    f->indirect_err = worst_rel(f->indirect, ind_ref);
    return masked_flip(im, ra, mask, &f->flip, e);
}

static void test_cornell_full_gi(void)
{
    bool light = prw_test_light();
    g_size = (uint32_t)env_u("PRW_CGI_SIZE", light ? 64 : 256);
    if (g_size < 16 || g_size > 1024) g_size = 256;
    uint64_t spp = env_u("PRW_CGI_SPP", 32);
    if (spp < 1) spp = 1;

    char err[512];
    const char *path = prw_test_path("cornell.gltf");
    CHECK_MSG(cornell_write_gltf(path, 1000, err, sizeof err), "%s", err);
    prw_error e = {{0}};
    prw_scene *s = prw_scene_create();
    CHECK_OK(prw_scene_open_model(s, path, &e), &e);
    prw_scene_update(s);
    prw_view v;
    CHECK_OK(prw_ref_view_for_camera(s, NULL, g_size, g_size, &v, &e), &e);
    v.ev100 = EV100;

    /* the bake: the renderer's default unless told (light mode: reduced) */
    prw_quality q = prw_quality_default();
    prw_gi_options o = {.radiosity_size = (uint32_t)env_u("PRW_CGI_RADIOSITY", light ? 32 : q.radiosity_size),
                        .samples = (uint32_t)env_u("PRW_CGI_SAMPLES", light ? 16 : PRW_GI_DEFAULT_SAMPLES),
                        .seed = 0, .filter_radius = PRW_GI_DEFAULT_FILTER_RADIUS};
    prw_gi_bake *b = NULL;
    prw_gi_result gr;
    CHECK_OK(prw_gi_run(s, &o, true, NULL, NULL, &b, &gr, &e), &e);
    printf("bake: radiosity_size %u, %u samples%s, texel %.4f m, %u atlases, %llu texels + %llu vertices, %.1f s\n",
           o.radiosity_size, o.samples,
           o.radiosity_size == q.radiosity_size && o.samples == PRW_GI_DEFAULT_SAMPLES ? " (the default bake)"
                                                                                        : " (reduced)",
           b->texel_size, b->atlas_count, (unsigned long long)b->sampled_texels,
           (unsigned long long)b->sampled_vertices, gr.seconds_total);
    prw_app_lightmaps *lms = NULL;
    CHECK_OK(prw_app_lightmaps_from_bake(s, b, &lms, &e), &e);

    prw_image raster = {0}, nolm = {0}, ra = {0}, rb = {0}, rdir = {0}, em = {0};
    CHECK_OK(render_raster(s, &v, prw_app_lightmaps_get(lms), &raster, &e), &e);
    CHECK_OK(render_raster(s, &v, NULL, &nolm, &e), &e); /* the control: no light maps */
    prw_ref_renderer *ref = NULL;
    CHECK_OK(prw_ref_create(s, v.eye, 0, &ref, &e), &e);
    bool ok = render_ref(ref, &v, spp, 1, PRW_REF_ALL, &ra, &e) && render_ref(ref, &v, spp, 2, PRW_REF_ALL, &rb, &e) &&
              render_ref(ref, &v, spp, 3, PRW_REF_DIRECT, &rdir, &e) &&
              render_ref(ref, &v, 16, 4, PRW_REF_EMISSION, &em, &e);
    prw_ref_destroy(ref);
    CHECK_OK(ok, &e);

    size_t n = (size_t)g_size * g_size, masked = 0;
    uint8_t *mask = prw_calloc(n, 1);
    for (size_t i = 0; i < n; i++) {
        if (em.rgba[4 * i] > 0 || em.rgba[4 * i + 1] > 0 || em.rgba[4 * i + 2] > 0) mask[i] = 1, masked++;
        for (int c = 0; c < 3; c++) CHECK(isfinite(raster.rgba[4 * i + c]) && raster.rgba[4 * i + c] >= 0);
    }
    double mra[3], mdir[3];
    masked_mean(&ra, mask, mra);
    masked_mean(&rdir, mask, mdir);
    figures fr, fn, fc; /* raster, noise (B), control (no light maps) */
    CHECK_OK(figures_of(&raster, &ra, mask, mra, mdir, &fr, &e), &e);
    CHECK_OK(figures_of(&rb, &ra, mask, mra, mdir, &fn, &e), &e);
    CHECK_OK(figures_of(&nolm, &ra, mask, mra, mdir, &fc, &e), &e);
    double flip_beyond = fr.flip - fn.flip, ctl_flip_beyond = fc.flip - fn.flip;

    printf("cornell box, %ux%u, 4x MSAA, full GI (direct + indirect diffuse light maps), reference all %llu spp, "
           "%zu emitter pixels left out, metric EV100 %.1f:\n",
           g_size, g_size, (unsigned long long)spp, masked, EV100);
    printf("  mean R/G/B      reference %.5g %.5g %.5g | raster %.5g %.5g %.5g (ratio %.4f %.4f %.4f)\n", mra[0], mra[1],
           mra[2], fr.mean[0], fr.mean[1], fr.mean[2], fr.mean[0] / mra[0], fr.mean[1] / mra[1], fr.mean[2] / mra[2]);
    printf("  indirect R/G/B  reference %.5g %.5g %.5g | raster %.5g %.5g %.5g (direct reference %.5g %.5g %.5g)\n",
           mra[0] - mdir[0], mra[1] - mdir[1], mra[2] - mdir[2], fr.indirect[0], fr.indirect[1], fr.indirect[2],
           mdir[0], mdir[1], mdir[2]);
    printf("  mean, worst channel      raster %.4f  noise (B vs A) %.4f  bound %.2f  no light maps %.4f\n", fr.mean_err,
           fn.mean_err, MEAN_BOUND, fc.mean_err);
    printf("  indirect, worst channel  raster %.4f  noise (B vs A) %.4f  bound %.2f  no light maps %.4f\n",
           fr.indirect_err, fn.indirect_err, INDIRECT_BOUND, fc.indirect_err);
    printf("  LDR-FLIP  raster vs A %.4f  noise (B vs A) %.4f  beyond noise %.4f (bound %.2f); no light maps beyond "
           "noise %.4f\n",
           fr.flip, fn.flip, flip_beyond, FLIP_BOUND, ctl_flip_beyond);

    /* for information: how a mild error of the light maps (their term 10 % too dark) reads */
    prw_image dim = {0};
    figures fd;
    CHECK_OK(prw_image_alloc(&dim, g_size, g_size, &e), &e);
    for (size_t i = 0; i < n * 4; i++) dim.rgba[i] = nolm.rgba[i] + 0.9f * (raster.rgba[i] - nolm.rgba[i]);
    CHECK_OK(figures_of(&dim, &ra, mask, mra, mdir, &fd, &e), &e);
    printf("  (light-map term x 0.9: mean %.4f, indirect %.4f, LDR-FLIP beyond noise %.4f)\n", fd.mean_err,
           fd.indirect_err, fd.flip - fn.flip);
    prw_image_free(&dim);
    CHECK(masked > 0 && masked < n / 4);
    /* the control: without light maps the indirect part is missing and the test fails */
    CHECK_MSG(fc.indirect_err > INDIRECT_BOUND && fc.mean_err > MEAN_BOUND,
              "the control (no light maps) passes: indirect %.4f, mean %.4f", fc.indirect_err, fc.mean_err);
    if (!light) {
        CHECK_MSG(fn.mean_err < MEAN_BOUND / 4 && fn.indirect_err < INDIRECT_BOUND / 4,
                  "the reference noise (%.4f, %.4f) is too large for the bounds", fn.mean_err, fn.indirect_err);
        CHECK_MSG(fr.mean_err <= MEAN_BOUND, "mean per channel off by %.4f > %.2f", fr.mean_err, MEAN_BOUND);
        CHECK_MSG(fr.indirect_err <= INDIRECT_BOUND, "indirect part off by %.4f > %.2f", fr.indirect_err,
                  INDIRECT_BOUND);
        CHECK_MSG(flip_beyond <= FLIP_BOUND, "LDR-FLIP beyond noise %.4f > %.2f", flip_beyond, FLIP_BOUND);
    }

    const char *dir = getenv("PRW_CGI_OUT");
    write_if(dir, "raster.exr", &raster);
    write_if(dir, "nolm.exr", &nolm);
    write_if(dir, "ref_a.exr", &ra);
    write_if(dir, "ref_b.exr", &rb);
    write_if(dir, "ref_direct.exr", &rdir);
    free(mask);
    prw_image_free(&raster);
    prw_image_free(&nolm);
    prw_image_free(&ra);
    prw_image_free(&rb);
    prw_image_free(&rdir);
    prw_image_free(&em);
    prw_app_lightmaps_destroy(lms);
    prw_scene_destroy(s);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {{"cornell_full_gi", test_cornell_full_gi}};
    int rc = prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
    return prw_test_gpu_finish() ? 1 : rc; /* one gpu for all cases: pipelines compiled once */
}
