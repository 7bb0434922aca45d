/* The BTF material kind in the rasterizer's base pass (shaders/base_btf.frag) against the path
 * tracer's direct light (`prw reference --filter direct`), 4x MSAA, validation layer on.
 *
 * Scene: a floor quad and a UV sphere on it, both of one BTF (closed form, 4 x 2 texels of 0.1 m: a
 * checker of two albedos per channel, times cos theta_l and a per-channel term of the view and light
 * azimuths, so a wrong frame, texel mapping, light / view table or decode changes the channels
 * differently), under a point light (case point) or a 0.5 x 0.3 m rect light (case rect), both
 * shadowed, no environment.  For a point light the reference's
 * direct light has no sampling noise other than its pixel filter; its own noise is printed (seed 2 vs
 * 1) and must be below a quarter of the bound.  Criteria: the mean per channel over all pixels within BOUND, and the mean per-pixel absolute
 * difference (over the pixels the reference lights) within PIXEL_BOUND of the mean radiance: the
 * latter catches a texel mapping or frame error that the means average away.  What remains is the
 * rasterizer's shadow map against exact visibility, MSAA against the reference's pixel filter, and
 * float against double in the BTF's frame.  Also LDR-FLIP beyond the reference's noise <= 0.05
 * (must-show 4).  A BTF that differs only in its azimuthal term (the
 * decode or the direction interpolation going wrong) is checked to fail the same criteria. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_btf_codec.h"
#include "prw_image.h"
#include "prw_metrics.h"
#include "prw_reference.h"
#include "prw_render.h"
#include "prw_test.h"
#include "prw_test_gpu.h"

enum { SIZE = 64 };
#define BOUND 0.01
#define PIXEL_BOUND 0.04
#define RECT_BOUND 0.015 /* rect lights: the reference has sampling noise */
#define RECT_PIXEL_BOUND 0.06
#define ALIAS_BOUND 0.08 /* scale_rule: mean |pixel luminance difference| / mean */

static void write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "wb");
    if (!f) return;
    fputs(text, f);
    fclose(f);
}

/* The closed-form BTF; a: per-channel weight of the azimuthal term (sin_l sin_v cos(phi_l - phi_v)). */
static const double k_alb[2][3] = {{0.7, 0.5, 0.3}, {0.2, 0.4, 0.6}};
static const double k_alb_contrast[2][3] = {{0.9, 0.9, 0.9}, {0.02, 0.02, 0.02}};

static bool write_btf_alb(const char *path, const double a[3], const double alb[2][3], prw_error *e)
{
    prw_btf b;
    if (!prw_btf_create(4, 2, 81, 81, &b, e)) return false;
    prw_btf_dirs_ubo81(b.view_dirs);
    prw_btf_dirs_ubo81(b.light_dirs);
    for (uint32_t v = 0; v < 81; v++)
        for (uint32_t l = 0; l < 81; l++) {
            double dv[3], dl[3];
            prw_btf_dir_vector(b.view_dirs[2 * v], b.view_dirs[2 * v + 1], dv);
            prw_btf_dir_vector(b.light_dirs[2 * l], b.light_dirs[2 * l + 1], dl);
            double az = dv[0] * dl[0] + dv[1] * dl[1];
            for (uint32_t y = 0; y < 2; y++)
                for (uint32_t x = 0; x < 4; x++)
                    for (int c = 0; c < 3; c++)
                        b.rgb[prw_btf_at(&b, v, l, x, y) + (size_t)c] =
                            (float)(alb[(x + y) & 1][c] / 3.14159265358979 * dl[2] * (1 + a[c] * az));
        }
    prw_btf_codec_params cp = {.codec = PRW_BTF_CODEC_CLUSTER, .components = 4, .clusters = 2, .seed = 1, .threads = 2};
    prw_btf_packed p;
    bool ok = prw_btf_compress(&b, &cp, &p, e);
    prw_btf_free(&b);
    ok = ok && prw_btf_packed_write(path, &p, e);
    if (ok) prw_btf_packed_free(&p);
    return ok;
}

/* file: relative to the manifest (both in the test directory) */
static const char *k_point = "{\"type\": \"point\", \"position\": [0.5, 1.2, 0.4], \"intensity\": 3}";
static const char *k_rect = "{\"type\": \"rect\", \"position\": [0.6, 1.1, 0.5], \"target\": [0, 0, 0], \"up\": [0, 1, 0],"
                            " \"width\": 0.5, \"height\": 0.3, \"intensity\": 20, \"unit\": \"cd/m2\"}";

static bool write_btf(const char *path, const double a[3], prw_error *e) { return write_btf_alb(path, a, k_alb, e); }

static prw_scene *btf_scene(const char *file, const char *light, prw_error *e)
{
    char text[4096];
    snprintf(text, sizeof text,
             "{\"prw_manifest\": 1, \"materials\": [{\"name\": \"cloth\", \"btf\": \"%s\", \"btf_texel_m\": 0.1, \"btf_scale_rule\": true}],"
             " \"meshes\": [{\"name\": \"floor\", \"quad\": {\"centre\": [0, 0, 0], \"half_u\": [1, 0, 0], \"half_v\": [0, 0, -1]},"
             " \"material\": \"cloth\"},"
             " {\"name\": \"ball\", \"sphere\": {\"centre\": [-0.2, 0.3, 0.1], \"radius\": 0.3, \"slices\": 32, \"stacks\": 16},"
             " \"material\": \"cloth\"}],"
             " \"lights\": [%s],"
             " \"cameras\": [{\"position\": [0, 1.3, 1.6], \"target\": [0, 0.1, 0], \"yfov_deg\": 55}]}",
             file, light);
    char *path = prw_test_path("btf_raster.json");
    write_text(path, text);
    prw_scene *s = prw_scene_create();
    if (!prw_scene_load_manifest(s, path, e)) {
        prw_scene_destroy(s);
        return NULL;
    }
    prw_scene_update(s);
    return s;
}

static bool render_raster_at(const prw_scene *s, const prw_view *v, uint32_t w, uint32_t h, uint32_t msaa, prw_image *hdr,
                             prw_error *e)
{
    prw_render_desc rd = {.width = w, .height = h, .quality = prw_quality_default()};
    rd.quality.msaa = msaa;
    rd.quality.shadow_size = 2048;
    return prw_test_render(s, &rd, v, 1, hdr, NULL, e);
}

static bool render_raster(const prw_scene *s, const prw_view *v, prw_image *hdr, prw_error *e)
{
    return render_raster_at(s, v, SIZE, SIZE, 4, hdr, e);
}

static bool render_ref(const prw_scene *s, const prw_view *v, uint64_t spp, uint64_t seed, prw_image *out, prw_error *e)
{
    prw_ref_renderer *ref = NULL;
    if (!prw_ref_create(s, v->eye, 2, &ref, e)) return false;
    prw_ref_desc d = {.s0 = 0, .s1 = spp, .seed = seed, .filter = {.kind = PRW_REF_DIRECT}};
    prw_ref_acc acc = {0};
    prw_ref_stats st;
    float *mean = NULL, *var = NULL;
    bool ok = prw_ref_render(ref, v, &d, &acc, &st, e) && prw_ref_acc_images(&acc, &mean, &var, e);
    if (ok) ok = prw_image_alloc(out, SIZE, SIZE, e);
    if (ok) memcpy(out->rgba, mean, (size_t)SIZE * SIZE * 4 * sizeof(float));
    free(mean), free(var);
    prw_ref_acc_free(&acc);
    prw_ref_destroy(ref);
    return ok;
}

/* worst relative difference of the channel means; mean |a - b| over lit pixels / mean of b */
static void compare(const prw_image *a, const prw_image *b, double *mean_rel, double *pixel_rel, double ma[3], double mb[3])
{
    double sa[3] = {0, 0, 0}, sb[3] = {0, 0, 0}, sd = 0, sl = 0;
    for (size_t i = 0; i < (size_t)SIZE * SIZE; i++)
        for (int c = 0; c < 3; c++) {
            double x = a->rgba[4 * i + (size_t)c], y = b->rgba[4 * i + (size_t)c];
            sa[c] += x, sb[c] += y;
            if (y > 0) sd += fabs(x - y), sl += y;
        }
    *mean_rel = 0;
    for (int c = 0; c < 3; c++) {
        ma[c] = sa[c] / (SIZE * SIZE), mb[c] = sb[c] / (SIZE * SIZE);
        *mean_rel = fmax(*mean_rel, fabs(sa[c] / sb[c] - 1));
    }
    *pixel_rel = sl > 0 ? sd / sl : INFINITY;
}

static void run_case(const char *what, const char *light, double bound, double pixel_bound)
{
    prw_error e = {{0}};
    const double a[3] = {0.8, 0.0, -0.6}, a_broken[3] = {-0.8, 0.6, 0.6};
    char *good = prw_test_path("btf_raster.btfc"), *broken = prw_test_path("btf_raster_broken.btfc");
    CHECK_OK(write_btf(good, a, &e), &e);
    CHECK_OK(write_btf(broken, a_broken, &e), &e);
    prw_scene *s = btf_scene("btf_raster.btfc", light, &e), *sb = btf_scene("btf_raster_broken.btfc", light, &e); /* beside the manifest */
    CHECK_MSG(s && sb, "%s", e.msg);
    if (!s || !sb) return;
    prw_view v;
    CHECK_OK(prw_ref_view_for_camera(s, NULL, SIZE, SIZE, &v, &e), &e);
    v.ev100 = -1.0; /* the scene mean (~0.11 cd/m^2) near middle grey in the metric tone map */
    uint64_t spp = prw_test_light() ? 16 : 64;
    prw_image raster = {0}, other = {0}, ra = {0}, rb = {0};
    CHECK_OK(render_raster(s, &v, &raster, &e), &e);
    CHECK_OK(render_raster(sb, &v, &other, &e), &e);
    CHECK_OK(render_ref(s, &v, spp, 1, &ra, &e), &e);
    CHECK_OK(render_ref(s, &v, spp, 2, &rb, &e), &e);
    if (raster.rgba && other.rgba && ra.rgba && rb.rgba) {
        double m, px, mn, pxn, mo, pxo, mr[3], mref[3], tmp[3];
        size_t bad = 0;
        for (size_t i = 0; i < (size_t)SIZE * SIZE * 4; i++) bad += !isfinite(raster.rgba[i]);
        compare(&raster, &ra, &m, &px, mr, mref);
        compare(&rb, &ra, &mn, &pxn, tmp, tmp);
        compare(&other, &ra, &mo, &pxo, tmp, tmp);
        printf("btf floor + sphere, %s light, %dx%d, reference direct %llu spp:\n  mean R/G/B reference %.5g %.5g %.5g | raster "
               "%.5g %.5g %.5g\n",
               what, SIZE, SIZE, (unsigned long long)spp, mref[0], mref[1], mref[2], mr[0], mr[1], mr[2]);
        printf("  worst channel mean: raster %.4f (bound %.3f), reference noise %.4f, other BTF %.4f\n", m, bound, mn, mo);
        printf("  mean |pixel difference| / mean: raster %.4f (bound %.2f), reference noise %.4f, other BTF %.4f\n", px,
               pixel_bound, pxn, pxo);
        prw_compare_opts o = {.ev100 = v.ev100};
        prw_compare_metrics fm, fn;
        bool fok = prw_compare_images(&raster, &ra, &o, &fm, NULL, NULL, &e) && prw_compare_images(&rb, &ra, &o, &fn, NULL, NULL, &e);
        CHECK_OK(fok, &e);
        if (fok) {
            printf("  LDR-FLIP raster %.4f, reference noise %.4f (EV100 %.1f): beyond noise %.4f (bound 0.05, must-show 4)\n",
                   fm.ldr_flip.mean, fn.ldr_flip.mean, v.ev100, fm.ldr_flip.mean - fn.ldr_flip.mean);
            CHECK_MSG(fm.ldr_flip.mean - fn.ldr_flip.mean <= 0.05, "%s: LDR-FLIP beyond noise %.4f", what,
                      fm.ldr_flip.mean - fn.ldr_flip.mean);
        }
        CHECK(bad == 0);
        CHECK_MSG(m <= bound, "%s: channel means off by %.4f", what, m);
        CHECK_MSG(px <= pixel_bound, "%s: pixels off by %.4f", what, px);
        CHECK_MSG(mn < bound / 4, "%s: the reference noise %.4f is too large for the bound", what, mn);
        CHECK_MSG(mo > bound || pxo > pixel_bound, "%s: a different BTF passes too (%.4f, %.4f)", what, mo, pxo);
        const char *dir = getenv("PRW_BTF_RASTER_OUT");
        if (dir && *dir) {
            char path[4096];
            snprintf(path, sizeof path, "%s/btf_raster_%s.exr", dir, what);
            if (prw_exr_write(path, &raster, NULL, 0, &e)) printf("wrote %s\n", path);
            snprintf(path, sizeof path, "%s/btf_ref_%s.exr", dir, what);
            if (prw_exr_write(path, &ra, NULL, 0, &e)) printf("wrote %s\n", path);
        }
    }
    prw_image_free(&raster), prw_image_free(&other), prw_image_free(&ra), prw_image_free(&rb);
    prw_scene_destroy(s), prw_scene_destroy(sb);
}

/* The scale rule (must-show 6, at one distance range): a floor receding to the horizon, 1 cm texels,
 * 64 x 64 without MSAA against the same view at 512 x 512 box-filtered to 64 x 64 (8 x 8 supersampling: the near
 * texels resolved there, the average BRDF where even those pixels are above a texel): LDR-FLIP <= 0.05
 * and the floor's mean luminance within 2 % (the figures), and the mean per-pixel luminance
 * difference within ALIAS_BOUND: at 64 x 64 FLIP's viewing model blurs the aliasing away (0.047
 * with the rule disabled in base_btf.frag), the per-pixel difference does not (0.28 then, 0.027 with
 * the rule). */
static void test_scale_rule(void)
{
    prw_error e = {{0}};
    const double a[3] = {0, 0, 0}; /* a Lambertian checker: its fitted average is the exact mean (the fit's own
                                      error, e.g. with the azimuthal term, is not what this case measures) */
    CHECK_OK(write_btf_alb(prw_test_path("btf_far.btfc"), a, k_alb_contrast, &e), &e); /* black / white texels */
    char text[2048];
    snprintf(text, sizeof text,
             "{\"prw_manifest\": 1, \"materials\": [{\"name\": \"cloth\", \"btf\": \"btf_far.btfc\", \"btf_texel_m\": 0.01}],"
             " \"meshes\": [{\"name\": \"floor\", \"quad\": {\"centre\": [0, 0, -19], \"half_u\": [1, 0, 0], \"half_v\": [0, 0, -20]},"
             " \"material\": \"cloth\"}],"
             " \"lights\": [{\"type\": \"directional\", \"direction\": [0.3, -1, -0.4], \"intensity\": 2}],"
             " \"cameras\": [{\"position\": [0, 0.4, 1], \"target\": [0, 0, -6], \"yfov_deg\": 40}]}");
    char *path = prw_test_path("btf_far.json");
    write_text(path, text);
    prw_scene *s = prw_scene_create();
    bool ok = prw_scene_load_manifest(s, path, &e);
    if (ok) prw_scene_update(s);
    prw_view v, vh;
    ok = ok && prw_ref_view_for_camera(s, NULL, SIZE, SIZE, &v, &e) && prw_ref_view_for_camera(s, NULL, 8 * SIZE, 8 * SIZE, &vh, &e);
    CHECK_OK(ok, &e);
    prw_image lo = {0}, hi = {0}, down = {0};
    if (ok) {
        v.ev100 = vh.ev100 = 0.0;
        CHECK_OK(render_raster_at(s, &v, SIZE, SIZE, 1, &lo, &e), &e);
        CHECK_OK(render_raster_at(s, &vh, 8 * SIZE, 8 * SIZE, 1, &hi, &e), &e);
    }
    if (lo.rgba && hi.rgba && prw_image_alloc(&down, SIZE, SIZE, &e)) {
        for (uint32_t y = 0; y < SIZE; y++)
            for (uint32_t x = 0; x < SIZE; x++)
                for (int c = 0; c < 4; c++) {
                    double sum = 0;
                    for (uint32_t j = 0; j < 8; j++)
                        for (uint32_t i = 0; i < 8; i++) sum += hi.rgba[(((size_t)(8 * y + j) * 8 * SIZE) + 8 * x + i) * 4 + (size_t)c];
                    down.rgba[((size_t)y * SIZE + x) * 4 + (size_t)c] = (float)(sum / 64);
                }
        double yl = 0, yd = 0, ad = 0;
        for (size_t i = 0; i < (size_t)SIZE * SIZE; i++) {
            double a_ = 0.2126 * lo.rgba[4 * i] + 0.7152 * lo.rgba[4 * i + 1] + 0.0722 * lo.rgba[4 * i + 2];
            double b_ = 0.2126 * down.rgba[4 * i] + 0.7152 * down.rgba[4 * i + 1] + 0.0722 * down.rgba[4 * i + 2];
            yl += a_, yd += b_, ad += fabs(a_ - b_);
        }
        prw_compare_opts o = {.ev100 = v.ev100};
        prw_compare_metrics m;
        CHECK_OK(prw_compare_images(&lo, &down, &o, &m, NULL, NULL, &e), &e);
        printf("scale rule, receding floor, %dx%d vs 8x8 supersampled: LDR-FLIP %.4f (bound 0.05), mean luminance %.5g vs "
               "%.5g (%.2f %%, bound 2 %%)\n",
               SIZE, SIZE, m.ldr_flip.mean, yl / (SIZE * SIZE), yd / (SIZE * SIZE), 100 * fabs(yl / yd - 1));
        printf("  mean |pixel luminance difference| / mean %.4f (bound %.2f: the aliasing the rule removes)\n", ad / yd,
               ALIAS_BOUND);
        CHECK_MSG(yd > 0, "black supersampled frame");
        CHECK_MSG(m.ldr_flip.mean <= 0.05, "LDR-FLIP %.4f", m.ldr_flip.mean);
        CHECK_MSG(ad / yd <= ALIAS_BOUND, "pixels off by %.4f", ad / yd);
        CHECK_MSG(fabs(yl / yd - 1) <= 0.02, "mean luminance off by %.2f %%", 100 * fabs(yl / yd - 1));
        const char *dir = getenv("PRW_BTF_RASTER_OUT");
        if (dir && *dir) {
            char out[4096];
            snprintf(out, sizeof out, "%s/btf_far_lo.exr", dir);
            prw_exr_write(out, &lo, NULL, 0, &e);
            snprintf(out, sizeof out, "%s/btf_far_ss.exr", dir);
            prw_exr_write(out, &down, NULL, 0, &e);
        }
    }
    prw_image_free(&lo), prw_image_free(&hi), prw_image_free(&down);
    prw_scene_destroy(s);
}

/* Must-show 6 over distances: the receding floor of test_scale_rule seen by a camera rising from 0.25 m
 * to 1.27 m (x 1.5 per frame, its target fixed; light mode: 3 frames), so the switch to the average
 * BRDF sweeps the floor.  Each frame at 64 x 64 against the same frame at 8 x 8 supersampling:
 * LDR-FLIP <= 0.05, the floor's mean luminance within 2 %, the frame-to-frame change of the mean
 * within 2 % of the supersampled frames' change (no pop where the rule switches), and the mean
 * per-pixel luminance difference within ALIAS_BOUND (what FLIP at 64 x 64 blurs away: aliasing). */
static void test_scale_rule_distances(void)
{
    prw_error e = {{0}};
    const double a[3] = {0, 0, 0};
    CHECK_OK(write_btf_alb(prw_test_path("btf_far.btfc"), a, k_alb_contrast, &e), &e);
    enum { FRAMES = 5 };
    double mean_lo[FRAMES], mean_ss[FRAMES];
    int frames = prw_test_light() ? 3 : FRAMES;
    prw_gpu *gpu = prw_test_gpu(&e);
    CHECK_OK(gpu != NULL, &e);
    double h = 0.25;
    for (int f = 0; gpu && f < frames; f++, h *= 1.5) {
        char text[2048];
        snprintf(text, sizeof text,
                 "{\"prw_manifest\": 1, \"materials\": [{\"name\": \"cloth\", \"btf\": \"btf_far.btfc\", \"btf_texel_m\": 0.01}],"
                 " \"meshes\": [{\"name\": \"floor\", \"quad\": {\"centre\": [0, 0, -19], \"half_u\": [1, 0, 0], \"half_v\": [0, 0, -20]},"
                 " \"material\": \"cloth\"}],"
                 " \"lights\": [{\"type\": \"directional\", \"direction\": [0.3, -1, -0.4], \"intensity\": 2}],"
                 " \"cameras\": [{\"position\": [0, %.17g, 1], \"target\": [0, 0, -4], \"yfov_deg\": 40}]}",
                 h);
        char *path = prw_test_path("btf_far.json");
        write_text(path, text);
        prw_scene *s = prw_scene_create();
        bool ok = prw_scene_load_manifest(s, path, &e);
        if (ok) prw_scene_update(s);
        prw_view v, vh;
        ok = ok && prw_ref_view_for_camera(s, NULL, SIZE, SIZE, &v, &e) &&
             prw_ref_view_for_camera(s, NULL, 8 * SIZE, 8 * SIZE, &vh, &e);
        prw_image lo = {0}, hi = {0}, down = {0};
        v.ev100 = vh.ev100 = 0.0;
        for (int k = 0; ok && k < 2; k++) {
            prw_renderer *r = NULL;
            uint32_t n = k ? 8 * SIZE : SIZE;
            prw_render_desc rd = {.width = n, .height = n, .quality = prw_quality_default()};
            rd.quality.msaa = 1;
            ok = prw_renderer_create(gpu, s, &rd, &r, &e) && prw_renderer_render(r, k ? &vh : &v, 1, NULL, &e) &&
                 prw_renderer_read_hdr(r, 0, k ? &hi : &lo, &e);
            prw_renderer_destroy(r);
        }
        ok = ok && prw_image_alloc(&down, SIZE, SIZE, &e);
        CHECK_OK(ok, &e);
        if (ok) {
            for (uint32_t y = 0; y < SIZE; y++)
                for (uint32_t x = 0; x < SIZE; x++)
                    for (int c = 0; c < 4; c++) {
                        double sum = 0;
                        for (uint32_t j = 0; j < 8; j++)
                            for (uint32_t i = 0; i < 8; i++)
                                sum += hi.rgba[(((size_t)(8 * y + j) * 8 * SIZE) + 8 * x + i) * 4 + (size_t)c];
                        down.rgba[((size_t)y * SIZE + x) * 4 + (size_t)c] = (float)(sum / 64);
                    }
            double yl = 0, yd = 0, ad = 0;
            for (size_t i = 0; i < (size_t)SIZE * SIZE; i++) {
                double a_ = 0.2126 * lo.rgba[4 * i] + 0.7152 * lo.rgba[4 * i + 1] + 0.0722 * lo.rgba[4 * i + 2];
                double b_ = 0.2126 * down.rgba[4 * i] + 0.7152 * down.rgba[4 * i + 1] + 0.0722 * down.rgba[4 * i + 2];
                yl += a_, yd += b_, ad += fabs(a_ - b_);
            }
            mean_lo[f] = yl, mean_ss[f] = yd;
            prw_compare_opts o = {.ev100 = v.ev100};
            prw_compare_metrics m;
            CHECK_OK(prw_compare_images(&lo, &down, &o, &m, NULL, NULL, &e), &e);
            double step = f ? (yl / mean_lo[f - 1]) / (yd / mean_ss[f - 1]) - 1 : 0;
            printf("scale rule, camera at %.3f m: LDR-FLIP %.4f (bound 0.05), mean luminance %+.2f %% (bound 2 %%), change "
                   "from the previous frame against the supersampled change %+.2f %% (bound 2 %%), mean |pixel difference| "
                   "%.4f (bound %.2f)\n",
                   h, m.ldr_flip.mean, 100 * (yl / yd - 1), 100 * step, ad / yd, ALIAS_BOUND);
            CHECK_MSG(yd > 0, "black supersampled frame");
            CHECK_MSG(m.ldr_flip.mean <= 0.05, "camera %.3f m: LDR-FLIP %.4f", h, m.ldr_flip.mean);
            CHECK_MSG(fabs(yl / yd - 1) <= 0.02, "camera %.3f m: mean luminance off by %.2f %%", h, 100 * fabs(yl / yd - 1));
            CHECK_MSG(ad / yd <= ALIAS_BOUND, "camera %.3f m: pixels off by %.4f", h, ad / yd);
            CHECK_MSG(fabs(step) <= 0.02, "camera %.3f m: the mean changed %.2f %% more than the supersampled frames'", h,
                      100 * step);
        }
        prw_image_free(&lo), prw_image_free(&hi), prw_image_free(&down);
        prw_scene_destroy(s);
    }
    uint32_t msgs = prw_gpu_validation_total();
    CHECK_MSG(msgs == 0, "%u validation messages", msgs);
}

static void test_point(void) { run_case("point", k_point, BOUND, PIXEL_BOUND); }
static void test_rect(void) { run_case("rect", k_rect, RECT_BOUND, RECT_PIXEL_BOUND); }

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {{"point", test_point}, {"rect", test_rect}, {"scale_rule", test_scale_rule},
                                         {"scale_rule_distances", test_scale_rule_distances}};
    int rc = prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
    return prw_test_gpu_finish() ? 1 : rc; /* one gpu for all cases: pipelines compiled once */
}
