/* The BTF material kind in the reference path tracer (engine/reference, prw_btf_eval.h):
 *  - lambert:   a BTF made by sampling a Lambert material (value = rho / pi cos theta_l on the Bonn 81 x 81
 *               set, as prw_btf_synth.h defines a BTF value) on a floor under a point light and a uniform sky
 *               (light sampling, cosine BSDF sampling and MIS all used) renders like the Lambert material
 *               itself: rendered with the same seed (the same paths: both sample cosine-weighted) the image
 *               means per channel agree within 0.2 % (the half-float storage); with another seed within
 *               3 sigma + 0.2 % (the light weights interpolate the reflectance, so a Lambert sample is
 *               reproduced exactly between the measured directions, prw_btf_interp.h);
 *  - synthetic: BTFs of the generator (fabric CLUSTER 16x2 and flakes SPARSE 4x0+4, 8 x 8 texels, 81 x 81
 *               directions) render without a non-finite sample or pixel and with light on them;
 *  - refused:   a BTF file changed after the scene was loaded is refused by the renderer, naming it. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_btf_codec.h"
#include "prw_btf_synth.h"
#include "prw_reference.h"
#include "prw_scene.h"
#include "prw_test.h"

static const double RHO[3] = {0.6, 0.4, 0.2};

static void write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "wb");
    if (!f) return;
    fputs(text, f);
    fclose(f);
}

/* tilt != 0: times (1 + tilt sin theta_v cos phi_v), a view dependence the material model cannot fit */
static bool write_lambert_btf(const char *path, double tilt, prw_error *e)
{
    prw_btf b;
    if (!prw_btf_create(4, 4, 81, 81, &b, e)) return false;
    prw_btf_dirs_ubo81(b.view_dirs);
    prw_btf_dirs_ubo81(b.light_dirs);
    for (uint32_t v = 0; v < 81; v++)
        for (uint32_t l = 0; l < 81; l++) {
            double cl = cos(b.light_dirs[2 * l]) * (1 + tilt * sin(b.view_dirs[2 * v]) * cos(b.view_dirs[2 * v + 1]));
            for (uint32_t y = 0; y < 4; y++)
                for (uint32_t x = 0; x < 4; x++)
                    for (int c = 0; c < 3; c++) b.rgb[prw_btf_at(&b, v, l, x, y) + c] = (float)(RHO[c] / PRW_PI * cl);
        }
    prw_btf_codec_params cp = {.codec = PRW_BTF_CODEC_FMF, .components = 1, .seed = 1, .threads = 1};
    prw_btf_packed p;
    bool ok = prw_btf_compress(&b, &cp, &p, e);
    prw_btf_free(&b);
    ok = ok && prw_btf_packed_write(path, &p, e);
    prw_btf_packed_free(&p);
    return ok;
}

/* The floor scene with material JSON `mat` (named "floor"); sphere: a ball of the same material on it. */
static prw_scene *floor_scene_with(const char *mat, bool sphere, prw_error *e)
{
    char text[2048];
    snprintf(text, sizeof text,
             "{\"prw_manifest\": 1, \"materials\": [%s],"
             " \"meshes\": [{\"name\": \"floor\", \"quad\": {\"centre\": [0, 0, 0], \"half_u\": [1, 0, 0], \"half_v\": [0, 0, -1]},"
             " \"material\": \"floor\"}%s],"
             " \"lights\": [{\"type\": \"point\", \"position\": [0.4, 0.8, 0.3], \"intensity\": 2}],"
             " \"environment\": {\"uniform_cd_m2\": [0.5, 0.6, 0.7]},"
             " \"cameras\": [{\"position\": [0, 1.2, 1.4], \"target\": [0, 0, 0], \"yfov_deg\": 50}]}",
             mat, sphere ? ", {\"name\": \"ball\", \"sphere\": {\"centre\": [-0.2, 0.3, 0.1], \"radius\": 0.3, \"slices\": 24, \"stacks\": 12}, \"material\": \"floor\"}" : "");
    char *path = prw_test_path("floor.json");
    write_text(path, text);
    prw_scene *s = prw_scene_create();
    if (!prw_scene_load_manifest(s, path, e)) {
        prw_scene_destroy(s);
        return NULL;
    }
    return s;
}

static prw_scene *floor_scene(const char *mat, prw_error *e) { return floor_scene_with(mat, false, e); }

typedef struct img_stats {
    double mean[3], var_mean[3]; /* image mean and the variance of that mean */
    uint64_t nonfinite;
    bool finite;
} img_stats;

static bool render(const prw_scene *s, uint32_t W, uint32_t H, uint64_t spp, uint64_t seed, img_stats *out, prw_error *e)
{
    memset(out, 0, sizeof *out);
    prw_view v;
    if (!prw_ref_view_for_camera(s, NULL, W, H, &v, e)) return false;
    prw_ref_renderer *r = NULL;
    if (!prw_ref_create(s, v.eye, 2, &r, e)) return false;
    prw_ref_desc d = {.s0 = 0, .s1 = spp, .seed = seed, .filter = {PRW_REF_ALL, 0}, .threads = 2};
    prw_ref_acc acc;
    prw_ref_stats st;
    float *mean = NULL, *var = NULL;
    bool ok = prw_ref_render(r, &v, &d, &acc, &st, e) && prw_ref_acc_images(&acc, &mean, &var, e);
    if (ok) {
        out->nonfinite = acc.nonfinite;
        out->finite = true;
        size_t n = (size_t)W * H;
        for (size_t i = 0; i < n; i++)
            for (int c = 0; c < 3; c++) {
                if (!isfinite(mean[4 * i + c]) || !isfinite(var[4 * i + c])) out->finite = false;
                out->mean[c] += mean[4 * i + c] / (double)n;
                out->var_mean[c] += var[4 * i + c] / ((double)n * n);
            }
        prw_ref_acc_free(&acc);
    }
    free(mean), free(var);
    prw_ref_destroy(r);
    return ok;
}

static void test_lambert(void)
{
    prw_error e;
    CHECK_OK(write_lambert_btf(prw_test_path("lambert.btfc"), 0, &e), &e);
    char mat[512];
    snprintf(mat, sizeof mat, "{\"name\": \"floor\", \"base_color\": [%g, %g, %g], \"metallic\": 0, \"roughness\": 1, \"specular\": 0}",
             RHO[0], RHO[1], RHO[2]);
    prw_scene *sl = floor_scene(mat, &e);
    prw_scene *sb = floor_scene("{\"name\": \"floor\", \"btf\": \"lambert.btfc\", \"btf_texel_m\": 0.01}", &e);
    CHECK_OK(sl && sb, &e);
    CHECK(sb->materials[0].kind == PRW_MATERIAL_BTF);
    uint32_t W = 24, H = 24;
    uint64_t spp = (uint64_t)prw_test_scale(256, 8);
    img_stats a, b, b2;
    double t0 = prw_now();
    CHECK_OK(render(sl, W, H, spp, 5, &a, &e), &e);
    double t1 = prw_now();
    CHECK_OK(render(sb, W, H, spp, 5, &b, &e), &e);
    double t2 = prw_now();
    CHECK_OK(render(sb, W, H, spp, 6, &b2, &e), &e);
    for (int c = 0; c < 3; c++) {
        double diff = b.mean[c] - a.mean[c], d2 = b2.mean[c] - a.mean[c];
        double sigma = sqrt(a.var_mean[c] + b2.var_mean[c]);
        printf("channel %d: Lambert %.5f cd/m2; Lambert BTF, same seed: %+.4f %%; other seed: %+.3f %% (%.1f sigma, sigma %.3f %%)\n",
               c, a.mean[c], 100 * diff / a.mean[c], 100 * d2 / a.mean[c], d2 / sigma, 100 * sigma / a.mean[c]);
        /* same seed: the same paths (NEE alike; both sample cosine-weighted), so only the half-float storage differs */
        CHECK(fabs(diff) <= 0.002 * a.mean[c]);
        /* independent seeds: within noise (+ the same storage allowance) */
        CHECK(fabs(d2) <= 3 * sigma + 0.002 * a.mean[c]);
        CHECK(a.mean[c] > 0);
    }
    printf("%u x %u, %llu spp: Lambert %.2f s, BTF %.2f s\n", W, H, (unsigned long long)spp, t1 - t0, t2 - t1);
    CHECK(a.nonfinite == 0 && b.nonfinite == 0 && b2.nonfinite == 0 && a.finite && b.finite && b2.finite);
    prw_scene_destroy(sl);
    prw_scene_destroy(sb);
}

/* The same on a UV sphere over the floor (frames turning with dP/du, degenerate uv triangles at the poles,
 * interreflection between ball and floor): same seed, image means within 3 sigma + 0.2 % (the paths
 * coincide until a Russian-roulette decision flips on the half-float values; sigma as if independent). */
static void test_sphere(void)
{
    prw_error e;
    CHECK_OK(write_lambert_btf(prw_test_path("lambert_s.btfc"), 0, &e), &e);
    char mat[512];
    snprintf(mat, sizeof mat, "{\"name\": \"floor\", \"base_color\": [%g, %g, %g], \"metallic\": 0, \"roughness\": 1, \"specular\": 0}",
             RHO[0], RHO[1], RHO[2]);
    prw_scene *sl = floor_scene_with(mat, true, &e);
    prw_scene *sb = floor_scene_with("{\"name\": \"floor\", \"btf\": \"lambert_s.btfc\", \"btf_texel_m\": 0.01}", true, &e);
    CHECK_OK(sl && sb, &e);
    img_stats a, b;
    uint64_t spp = (uint64_t)prw_test_scale(64, 4);
    CHECK_OK(render(sl, 24, 24, spp, 5, &a, &e), &e);
    CHECK_OK(render(sb, 24, 24, spp, 5, &b, &e), &e);
    for (int c = 0; c < 3; c++) {
        double sigma = sqrt(a.var_mean[c] + b.var_mean[c]);
        printf("sphere + floor, channel %d: Lambert %.5f, Lambert BTF %.5f cd/m2 (%+.4f %%, sigma as if independent %.3f %%)\n", c,
               a.mean[c], b.mean[c], 100 * (b.mean[c] - a.mean[c]) / a.mean[c], 100 * sigma / a.mean[c]);
        CHECK(fabs(b.mean[c] - a.mean[c]) <= 3 * sigma + 0.002 * a.mean[c]);
    }
    CHECK(a.nonfinite == 0 && b.nonfinite == 0 && a.finite && b.finite);
    prw_scene_destroy(sl);
    prw_scene_destroy(sb);
}

static void synthetic_case(prw_btf_synth_kind kind, const prw_btf_codec_params *cp, const char *file)
{
    prw_error e;
    /* light mode (sanitizer builds): a 4 x 4 tile, the same synthesis, codec and render code at a quarter
     * of the cost (synthesis and compression are most of this case) */
    uint32_t size = prw_test_light() ? 4 : 8;
    prw_btf_synth_params sp = {.kind = kind, .size = size, .dirs = 81, .texel_m = 1e-3, .seed = 3, .threads = 2};
    prw_btf b;
    double t0 = prw_now();
    CHECK_OK(prw_btf_synthesize(&sp, &b, &e), &e);
    prw_btf_packed p;
    bool ok = prw_btf_compress(&b, cp, &p, &e);
    prw_btf_free(&b);
    CHECK_OK(ok, &e);
    ok = prw_btf_packed_write(prw_test_path(file), &p, &e);
    prw_btf_packed_free(&p);
    CHECK_OK(ok, &e);
    double t1 = prw_now();
    char mat[256];
    snprintf(mat, sizeof mat, "{\"name\": \"floor\", \"btf\": \"%s\", \"btf_texel_m\": 0.004}", file);
    prw_scene *s = floor_scene(mat, &e);
    CHECK_OK(s != NULL, &e);
    img_stats a;
    CHECK_OK(render(s, 24, 24, (uint64_t)prw_test_scale(32, 4), 5, &a, &e), &e);
    printf("%s %ux%u BTF (synthesis + compression %.1f s): image mean %.4f %.4f %.4f cd/m2, %llu non-finite samples\n",
           prw_btf_synth_name(kind), size, size, t1 - t0, a.mean[0], a.mean[1], a.mean[2], (unsigned long long)a.nonfinite);
    CHECK(a.finite && a.nonfinite == 0);
    CHECK(a.mean[0] > 0 && a.mean[1] > 0 && a.mean[2] > 0);
    prw_scene_destroy(s);
}

static void test_synthetic(void)
{
    prw_btf_codec_params fabric = {.codec = PRW_BTF_CODEC_CLUSTER, .clusters = 16, .components = 2, .seed = 1, .threads = 2};
    synthetic_case(PRW_BTF_SYNTH_FABRIC, &fabric, "fabric.btfc");
    prw_btf_codec_params flakes = {.codec = PRW_BTF_CODEC_SPARSE, .clusters = 4, .components = 0, .sparse_per_texel = 4,
                                   .seed = 1, .threads = 2};
    synthetic_case(PRW_BTF_SYNTH_FLAKES, &flakes, "flakes.btfc");
}

static void test_refused(void)
{
    prw_error e;
    CHECK_OK(write_lambert_btf(prw_test_path("changing.btfc"), 0, &e), &e);
    prw_scene *s = floor_scene("{\"name\": \"floor\", \"btf\": \"changing.btfc\", \"btf_texel_m\": 0.01}", &e);
    CHECK_OK(s != NULL, &e);
    write_text(prw_test_path("changing.btfc"), "PRWBTFC1 but no longer the file the scene was loaded with.....");
    prw_ref_renderer *r = NULL;
    CHECK(!prw_ref_create(s, prw_v3(0, 1, 1), 1, &r, &e) && strstr(e.msg, "material 'floor'") &&
          strstr(e.msg, "changing.btfc: changed since the scene was loaded"));
    printf("refused: %s\n", e.msg);
    prw_ref_destroy(r);
    prw_scene_destroy(s);
}

/* The scale rule (btf_scale_rule), on a Lambert BTF tilted with the view azimuth (which the model cannot fit):
 * texels far above the pixel footprint render exactly as without the rule; texels far below it render as
 * the glTF material with the file's fitted average (same seed: the same paths), visibly unlike the BTF. */
static void test_scale_rule(void)
{
    prw_error e;
    CHECK_OK(write_lambert_btf(prw_test_path("rule.btfc"), 0.6, &e), &e);
    prw_btf_packed p;
    CHECK_OK(prw_btf_packed_read(prw_test_path("rule.btfc"), &p, &e), &e);
    CHECK(p.has_average);
    prw_btf_average av = p.average;
    prw_btf_packed_free(&p);
    printf("fitted average of the Lambert BTF: base %.4f %.4f %.4f, metallic %.2f, roughness %.4f, specular %.2f, rms %.2f %%\n",
           av.base[0], av.base[1], av.base[2], av.metallic, av.roughness, av.specular, av.rms_pct);
    static const char *const mats[4] = {
        "{\"name\": \"floor\", \"btf\": \"rule.btfc\", \"btf_texel_m\": 0.5}",
        "{\"name\": \"floor\", \"btf\": \"rule.btfc\", \"btf_texel_m\": 0.5, \"btf_scale_rule\": true}",
        "{\"name\": \"floor\", \"btf\": \"rule.btfc\", \"btf_texel_m\": 1e-5, \"btf_scale_rule\": true}",
        NULL};
    char avg[256];
    snprintf(avg, sizeof avg,
             "{\"name\": \"floor\", \"base_color\": [%.9g, %.9g, %.9g], \"metallic\": %.9g, \"roughness\": %.9g, \"specular\": %.9g}",
             av.base[0], av.base[1], av.base[2], av.metallic, av.roughness, av.specular);
    img_stats st[4];
    for (int i = 0; i < 4; i++) {
        prw_scene *s = floor_scene(mats[i] ? mats[i] : avg, &e);
        CHECK_OK(s != NULL, &e);
        CHECK_OK(render(s, 16, 16, (uint64_t)prw_test_scale(64, 4), 9, &st[i], &e), &e);
        prw_scene_destroy(s);
    }
    for (int c = 0; c < 3; c++) {
        printf("channel %d: BTF %.5f, rule with 0.5 m texels %.5f, rule with 10 um texels %.5f, fitted glTF material %.5f\n", c,
               st[0].mean[c], st[1].mean[c], st[2].mean[c], st[3].mean[c]);
        CHECK(st[1].mean[c] == st[0].mean[c]);
        CHECK_NEAR(st[2].mean[c], st[3].mean[c], 1e-5 * st[3].mean[c]);
        /* the average is another model (it cannot follow the view tilt): not the BTF's image */
        CHECK(fabs(st[2].mean[c] - st[0].mean[c]) > 100 * 1e-5 * st[3].mean[c]);
    }
}

/* A width x 1 BTF of reflectance f(x, l) = (rho[x] + k sin theta_l cos phi_l) / pi (the BTF stores f cos theta_l). */
static bool write_frame_btf(const char *path, uint32_t width, const double *rho, double k, prw_error *e)
{
    prw_btf b;
    if (!prw_btf_create(width, 1, 81, 81, &b, e)) return false;
    prw_btf_dirs_ubo81(b.view_dirs);
    prw_btf_dirs_ubo81(b.light_dirs);
    for (uint32_t v = 0; v < 81; v++)
        for (uint32_t l = 0; l < 81; l++) {
            double th = b.light_dirs[2 * l], ph = b.light_dirs[2 * l + 1];
            for (uint32_t x = 0; x < width; x++)
                for (int c = 0; c < 3; c++)
                    b.rgb[prw_btf_at(&b, v, l, x, 0) + c] = (float)((rho[x] + k * sin(th) * cos(ph)) / PRW_PI * cos(th));
        }
    prw_btf_codec_params cp = {.codec = PRW_BTF_CODEC_FMF, .components = width, .seed = 1, .threads = 1};
    prw_btf_packed p;
    bool ok = prw_btf_compress(&b, &cp, &p, e);
    prw_btf_free(&b);
    ok = ok && prw_btf_packed_write(path, &p, e);
    prw_btf_packed_free(&p);
    return ok;
}

/* Radiance straight up from the floor at x (m) under a 10-lux directional light travelling along dir. */
static double floor_radiance(const char *btf, double texel_m, const double dir[3], double x, prw_error *e, bool *ok)
{
    char text[1024];
    snprintf(text, sizeof text,
             "{\"prw_manifest\": 1, \"materials\": [{\"name\": \"floor\", \"btf\": \"%s\", \"btf_texel_m\": %g}],"
             " \"meshes\": [{\"quad\": {\"centre\": [0, 0, 0], \"half_u\": [1, 0, 0], \"half_v\": [0, 0, -1]}, \"material\": \"floor\"}],"
             " \"lights\": [{\"type\": \"directional\", \"direction\": [%g, %g, %g], \"intensity\": 10}],"
             " \"cameras\": [{\"position\": [0, 2, 0], \"direction\": [0, -1, 0], \"up\": [0, 0, -1]}]}",
             btf, texel_m, dir[0], dir[1], dir[2]);
    char *path = prw_test_path("frame.json");
    write_text(path, text);
    prw_scene *s = prw_scene_create();
    prw_ref_renderer *r = NULL;
    prw_ref_ray_result res;
    memset(&res, 0, sizeof res);
    *ok = prw_scene_load_manifest(s, path, e) && prw_ref_create(s, prw_v3(0, 1, 0), 1, &r, e);
    if (*ok) {
        prw_ref_ray ray = {.origin = prw_v3(x, 1, 0.1), .dir = prw_v3(0, -1, 0), .tnear = 0};
        prw_ref_ray_desc d = {.s0 = 0, .s1 = 1, .seed = 1, .filter = {PRW_REF_ALL, 0}, .camera = true, .threads = 1};
        *ok = prw_ref_trace_rays(r, &ray, 1, &d, &res, NULL, NULL, e);
    }
    prw_ref_destroy(r);
    prw_scene_destroy(s);
    return res.mean[0];
}

/* The BTF's frame and texel mapping on a builder quad (x = dP/du = +X, texel = uv |dP/duv| / texel size),
 * in closed form: radiance = 10 lux x f cos theta_l exactly at measured directions. */
static void test_frame(void)
{
    prw_error e;
    bool ok;
    const double aniso_rho[1] = {1.0}, two[2] = {0.2, 0.8};
    CHECK_OK(write_frame_btf(prw_test_path("aniso.btfc"), 1, aniso_rho, 0.9, &e), &e);
    CHECK_OK(write_frame_btf(prw_test_path("two.btfc"), 2, two, 0, &e), &e);
    /* light from +X (BTF +x) and -X at theta_l 53.13 deg (cos 0.6): f = (1 +- 0.9 * 0.8) / pi; from +Z: 1 / pi */
    const double from_px[3] = {-0.8, -0.6, 0}, from_nx[3] = {0.8, -0.6, 0}, from_pz[3] = {0, -0.6, -0.8};
    double lp = floor_radiance("aniso.btfc", 0.01, from_px, 0, &e, &ok);
    CHECK_OK(ok, &e);
    double ln = floor_radiance("aniso.btfc", 0.01, from_nx, 0, &e, &ok);
    double lz = floor_radiance("aniso.btfc", 0.01, from_pz, 0, &e, &ok);
    double ep = 10 * 1.72 / PRW_PI * 0.6, en = 10 * 0.28 / PRW_PI * 0.6, ez = 10 / PRW_PI * 0.6;
    printf("anisotropic BTF, light from +X / -X / +Z: %.4f / %.4f / %.4f cd/m2 (closed form %.4f / %.4f / %.4f)\n", lp, ln, lz, ep,
           en, ez);
    CHECK(fabs(lp - ep) <= 0.03 * ep && fabs(ln - en) <= 0.03 * ep && fabs(lz - ez) <= 0.03 * ep);
    /* two texels of 1 m on the 2 m quad: texel 0 centred at X = -0.5, texel 1 at +0.5, blended half-way at 0 */
    const double down[3] = {0, -1, 0};
    double a = floor_radiance("two.btfc", 1.0, down, -0.5, &e, &ok);
    CHECK_OK(ok, &e);
    double b = floor_radiance("two.btfc", 1.0, down, 0.5, &e, &ok);
    double m = floor_radiance("two.btfc", 1.0, down, 0.0, &e, &ok);
    printf("two texels of 1 m, light from above: X = -0.5 / 0 / +0.5: %.4f / %.4f / %.4f cd/m2 (closed form %.4f / %.4f / %.4f)\n", a, m, b,
           10 * 0.2 / PRW_PI, 10 * 0.5 / PRW_PI, 10 * 0.8 / PRW_PI);
    CHECK(fabs(a - 2 / PRW_PI) <= 0.002 * 8 / PRW_PI && fabs(b - 8 / PRW_PI) <= 0.002 * 8 / PRW_PI &&
          fabs(m - 5 / PRW_PI) <= 0.002 * 8 / PRW_PI);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"lambert", test_lambert},         {"synthetic", test_synthetic}, {"refused", test_refused},
        {"scale_rule", test_scale_rule}, {"frame", test_frame},       {"sphere", test_sphere}};
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
