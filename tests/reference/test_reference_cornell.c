/* The Cornell box glTF (cornell_gltf.h, written here) through the path tracer, full GI:
 *  - variance: the variance file predicts the seed-to-seed error.  For independent renders a, b of
 *    the same pixels E[(a - b)^2] = var_a + var_b, so R = sum (a - b)^2 / sum (var_a + var_b) over
 *    pixels and channels, pooled over seed pairs, must be 1 (checked within 5 %).  Pixels whose
 *    footprint sees the light (grown by one pixel) are left out of R and reported apart: a pixel
 *    the 1000 cd/m^2 light's edge crosses is a Bernoulli draw between 1000 and ~5, and the ~80 of
 *    them make R swing 0.8-1.5 between seed pairs (measured), whatever the variance estimator;
 *  - mean: the image mean per channel stays within 2 sigma of the mean the tracer gave before its
 *    speed work (MEAN_* below, with their own sigma: the image mean is the integral of radiance over
 *    the image plane, so it does not depend on the resolution).
 * Regenerate MEAN_* (only when the model changes on purpose, with the reason in the commit):
 *   build/tests/reference/cornell_box /tmp/cb.gltf &&
 *   build/app/prw --threads 2 reference /tmp/cb.gltf --size 256x256 --spp 2048 --seed 1001 --out /tmp/cbref.exr
 *   then the image mean per channel of /tmp/cbref.exr and sqrt(sum var) / pixels of /tmp/cbref.var.exr
 *   (any EXR reader; e.g. numpy in Blender's Python). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cornell_gltf.h"
#include "ref_scenes.h"

/* Recorded at 156ddfa (the tracer before its speed work; its images are bit-identical to 1fbbe53 on the demo), 256x256, 2048 spp, seed 1001. */
static const double MEAN_RGB[3] = {11.663087, 7.497346, 2.290789};
static const double MEAN_SIGMA[3] = {0.001616, 0.001112, 0.000390};

static prw_scene *cornell_scene(prw_view *v, uint32_t w, uint32_t h)
{
    char err[512];
    const char *path = prw_test_path("cornell.gltf");
    if (!cornell_write_gltf(path, 1000, err, sizeof err)) {
        fprintf(stderr, "%s\n", err);
        prw_test_failures++;
        return NULL;
    }
    prw_scene *s = prw_scene_create();
    prw_error e = {{0}};
    bool ok = prw_scene_open_model(s, path, &e);
    if (ok) prw_scene_update(s);
    ok = ok && prw_ref_view_for_camera(s, NULL, w, h, v, &e);
    if (!ok) {
        fprintf(stderr, "%s: %s\n", path, e.msg);
        prw_test_failures++;
        prw_scene_destroy(s);
        return NULL;
    }
    CHECK(s->light_count == 0); /* lit by the emissive quad alone */
    return s;
}

/* Pixels whose footprint (5 x 5 camera rays) sees an emitter directly: 1 in mask. */
static unsigned char *emitter_mask(const prw_scene *s, const prw_view *v, size_t *count)
{
    prw_error e = {{0}};
    prw_ref_renderer *r = NULL;
    *count = 0;
    if (!prw_ref_create(s, v->eye, 1, &r, &e)) {
        fprintf(stderr, "prw_ref_create: %s\n", e.msg);
        prw_test_failures++;
        return NULL;
    }
    unsigned char *m = calloc((size_t)v->width * v->height, 1);
    for (uint32_t y = 0; y < v->height; y++)
        for (uint32_t x = 0; x < v->width; x++)
            for (int k = 0; k < 25 && !m[(size_t)y * v->width + x]; k++) {
                prw_ref_hit h;
                double fx = x + (k % 5 + 0.5) / 5.0, fy = y + (k / 5 + 0.5) / 5.0;
                if (!prw_ref_primary_hit(r, v, fx, fy, &h) || h.material < 0) continue;
                const prw_material *mt = &s->materials[h.material];
                if (mt->emission[0] > 0 || mt->emission[1] > 0 || mt->emission[2] > 0) m[(size_t)y * v->width + x] = 1;
            }
    prw_ref_destroy(r);
    /* grown by one pixel: a footprint's sliver of the light can fall between the rays */
    unsigned char *g = calloc((size_t)v->width * v->height, 1);
    *count = 0;
    for (uint32_t y = 0; y < v->height; y++)
        for (uint32_t x = 0; x < v->width; x++) {
            bool any = false;
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++) {
                    long xx = (long)x + dx, yy = (long)y + dy;
                    if (xx >= 0 && yy >= 0 && xx < (long)v->width && yy < (long)v->height)
                        any = any || m[(size_t)yy * v->width + (size_t)xx];
                }
            g[(size_t)y * v->width + x] = any;
            *count += any;
        }
    free(m);
    return g;
}

static void test_variance_predicts_error(void)
{
    /* the same workload in light mode: fewer pixels or pairs make R itself too noisy for 5 % */
    const uint32_t W = 96, H = W;
    const uint64_t SPP = 16;
    prw_view v;
    prw_scene *s = cornell_scene(&v, W, H);
    if (!s) return;
    prw_ref_filter all = {PRW_REF_ALL, 0};
    const uint64_t seeds[][2] = {{1, 2}, {3, 4}, {5, 6}};
    const int pairs = 3;
    double pooled_num = 0, pooled_den = 0;
    size_t masked = 0;
    unsigned char *mask = emitter_mask(s, &v, &masked);
    for (int p = 0; p < pairs && mask; p++) {
        ref_result a, b;
        bool ok = ref_run(s, &v, 0, SPP, seeds[p][0], all, 2, &a);
        ok = ok && ref_run(s, &v, 0, SPP, seeds[p][1], all, 2, &b);
        if (ok) {
            double num[2] = {0, 0}, den[2] = {0, 0};
            for (size_t i = 0; i < (size_t)W * H; i++)
                for (int c = 0; c < 3; c++) {
                    double d = (double)a.mean[4 * i + c] - b.mean[4 * i + c];
                    num[mask[i]] += d * d;
                    den[mask[i]] += (double)a.var[4 * i + c] + b.var[4 * i + c];
                }
            double R = den[0] > 0 ? num[0] / den[0] : 0, Re = den[1] > 0 ? num[1] / den[1] : 0;
            printf("  seeds %llu/%llu, %ux%u, %llu spp: sum (a-b)^2 / sum (var_a + var_b) = %.4f over %zu pixels "
                   "(%.4f over the %zu that see the light)\n",
                   (unsigned long long)seeds[p][0], (unsigned long long)seeds[p][1], W, H, (unsigned long long)SPP, R,
                   (size_t)W * H - masked, Re, masked);
            pooled_num += num[0], pooled_den += den[0];
        }
        ref_result_free(&a);
        ref_result_free(&b);
    }
    double R = pooled_den > 0 ? pooled_num / pooled_den : 0;
    printf("  pooled over %d seed pair(s): %.4f\n", pairs, R);
    CHECK_MSG(mask && fabs(R - 1) <= 0.05, "R = %.4f: the variance file mispredicts the seed-to-seed error", R);
    free(mask);
    prw_scene_destroy(s);
}

static void test_mean_unchanged(void)
{
    const uint32_t W = (uint32_t)prw_test_scale(128, 2), H = W;
    const uint64_t SPP = (uint64_t)prw_test_scale(128, 4);
    prw_view v;
    prw_scene *s = cornell_scene(&v, W, H);
    if (!s) return;
    prw_ref_filter all = {PRW_REF_ALL, 0};
    ref_result a;
    if (ref_run(s, &v, 0, SPP, 77, all, 2, &a)) {
        size_t n = (size_t)W * H;
        for (int c = 0; c < 3; c++) {
            double m = 0, var = 0;
            for (size_t i = 0; i < n; i++) m += a.mean[4 * i + c], var += a.var[4 * i + c];
            m /= (double)n;
            double sig = sqrt(var) / (double)n;
            double tol = 2 * sqrt(sig * sig + MEAN_SIGMA[c] * MEAN_SIGMA[c]);
            printf("  channel %d: mean %.5f +- %.5f, recorded %.5f +- %.5f (%+.2f sigma)\n", c, m, sig, MEAN_RGB[c],
                   MEAN_SIGMA[c], (m - MEAN_RGB[c]) / (tol / 2));
            CHECK_MSG(fabs(m - MEAN_RGB[c]) <= tol, "channel %d: mean %.5f, recorded %.5f, 2 sigma %.5f", c, m,
                      MEAN_RGB[c], tol);
        }
    }
    ref_result_free(&a);
    prw_scene_destroy(s);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"variance_predicts_error", test_variance_predicts_error},
        {"mean_unchanged", test_mean_unchanged},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
