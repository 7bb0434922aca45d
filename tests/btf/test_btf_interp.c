/* The interpolation of a BTF between its measured directions (materials/btf/prw_btf_interp.h,
 * prw_btf_eval.h):
 *  - weights:   on the Bonn 81 set, for 200000 random directions: the weights are >= 0 and sum to 1
 *               (a partition of unity); the light weights (times cos theta_l / cos theta_k) reproduce
 *               cos theta_l exactly and fall to 0 at the horizon; at each measured direction its own
 *               weight is 1;
 *  - smooth:    a BTF sampled from a smooth BRDF x cos theta_l (Lambert plus a broad Phong lobe) on the
 *               81 x 81 set reproduces it between the measured directions: worst error within the
 *               measured cone <= 3 % of the largest value (2.2 % measured) (the figure is printed), exact at the measured
 *               pairs and texel centres; bilinear between texels, wrapping;
 *  - packed:    the packed evaluation equals the raw one to half precision on a compressed copy;
 *  - refused:   bad direction sets are refused naming the direction. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_bsdf.h"
#include "prw_btf_codec.h"
#include "prw_btf_eval.h"
#include "prw_test.h"

#define PRW_PI 3.14159265358979323846

static uint64_t st = 7;
static double rnd(void)
{
    st = st * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(st >> 11) * 0x1.0p-53;
}

static void rand_dir(double theta_max, double d[3])
{
    double z = cos(theta_max) + rnd() * (1 - cos(theta_max)), ph = 2 * PRW_PI * rnd(), r = sqrt(fmax(0, 1 - z * z));
    d[0] = r * cos(ph), d[1] = r * sin(ph), d[2] = z;
}

static void test_weights(void)
{
    float dirs[2 * 81];
    prw_btf_dirs_ubo81(dirs);
    prw_btf_dirtab t;
    prw_error e;
    CHECK_OK(prw_btf_dirtab_build(dirs, 81, &t, &e), &e);
    printf("bonn 81: %u triangles\n", t.tri_count);
    double worst_sum = 0, worst_neg = 0, worst_lsum_in = 0, worst_light_horizon = 0;
    int n = prw_test_scale(200000, 10);
    for (int i = 0; i < n; i++) {
        double d[3];
        rand_dir(PRW_PI / 2, d);
        uint32_t idx[3];
        float w[3], lw[3];
        prw_btf_dirtab_weights(&t, d, false, idx, w);
        worst_sum = fmax(worst_sum, fabs(w[0] + w[1] + w[2] - 1));
        for (int k = 0; k < 3; k++) {
            worst_neg = fmin(worst_neg, w[k]);
            CHECK(idx[k] < 81);
        }
        prw_btf_dirtab_weights(&t, d, true, idx, lw);
        /* the light weights carry cos theta_l / cos theta_k: they reproduce cos theta_l itself exactly */
        double lin = 0;
        for (int k = 0; k < 3; k++) lin += lw[k] * t.cos_theta[idx[k]];
        worst_lsum_in = fmax(worst_lsum_in, fabs(lin - d[2]));
        double th = acos(d[2]);
        if (th > 89.9 * PRW_PI / 180) worst_light_horizon = fmax(worst_light_horizon, lw[0] + lw[1] + lw[2]);
    }
    printf("weights: |sum - 1| <= %.3g, min %.3g; light weights: |sum w_k cos theta_k - cos theta_l| <= %.3g; beyond 89.9 deg: sum <= %.3g\n",
           worst_sum, worst_neg, worst_lsum_in, worst_light_horizon);
    CHECK(worst_sum < 1e-5);
    CHECK(worst_neg >= 0);
    CHECK(worst_lsum_in < 1e-5);
    CHECK(worst_light_horizon < 0.01);
    /* exact at the measured directions */
    double worst_own = 0;
    for (uint32_t i = 0; i < 81; i++) {
        double d[3];
        prw_btf_dir_vector(dirs[2 * i], dirs[2 * i + 1], d);
        uint32_t idx[3];
        float w[3];
        prw_btf_dirtab_weights(&t, d, false, idx, w);
        double own = 0;
        for (int k = 0; k < 3; k++)
            if (idx[k] == i) own += w[k];
        worst_own = fmax(worst_own, fabs(own - 1));
        prw_btf_dirtab_weights(&t, d, true, idx, w);
        own = 0;
        for (int k = 0; k < 3; k++)
            if (idx[k] == i) own += w[k];
        worst_own = fmax(worst_own, fabs(own - 1));
    }
    printf("at the 81 measured directions: own weight within %.3g of 1\n", worst_own);
    CHECK(worst_own < 1e-5);
    /* the lookup grid only chooses where the search starts: the same interpolation as a search from triangle 0
     * (compared through g(k) = (7 k mod 13), which differs between the directions) */
    uint32_t *grid = t.grid;
    double worst_grid = 0;
    for (int i = 0; i < n / 4; i++) {
        double d[3];
        rand_dir(PRW_PI / 2, d);
        uint32_t ia[3], ib[3];
        float wa[3], wb[3];
        t.grid = grid;
        prw_btf_dirtab_weights(&t, d, false, ia, wa);
        t.grid = NULL;
        prw_btf_dirtab_weights(&t, d, false, ib, wb);
        double ga = 0, gb = 0;
        for (int k = 0; k < 3; k++) ga += wa[k] * ((7 * ia[k]) % 13), gb += wb[k] * ((7 * ib[k]) % 13);
        worst_grid = fmax(worst_grid, fabs(ga - gb));
    }
    t.grid = grid;
    printf("grid start against a search from triangle 0: worst difference %.3g (values 0..12)\n", worst_grid);
    CHECK(worst_grid < 1e-4);
    prw_btf_dirtab_free(&t);
}

/* f(v, l) cos theta_l for texel (x, y): a Lambert term varying over the texels plus a broad lobe. */
static double smooth_value(const double v[3], const double l[3], uint32_t x, uint32_t y, int c)
{
    double kd = 0.2 + 0.15 * c + 0.1 * x + 0.05 * y;
    double r[3] = {-v[0], -v[1], v[2]}; /* mirror of v about the normal */
    double cs = fmax(0, r[0] * l[0] + r[1] * l[1] + r[2] * l[2]);
    double f = kd / PRW_PI + 0.3 * (2 + 1) / (2 * PRW_PI) * cs * cs;
    return f * fmax(l[2], 0);
}

static void fill_smooth(prw_btf *b, const float *dirs)
{
    for (uint32_t v = 0; v < b->views; v++)
        for (uint32_t l = 0; l < b->lights; l++) {
            double dv[3], dl[3];
            prw_btf_dir_vector(dirs[2 * v], dirs[2 * v + 1], dv);
            prw_btf_dir_vector(dirs[2 * l], dirs[2 * l + 1], dl);
            for (uint32_t y = 0; y < b->height; y++)
                for (uint32_t x = 0; x < b->width; x++)
                    for (int c = 0; c < 3; c++) b->rgb[prw_btf_at(b, v, l, x, y) + c] = (float)smooth_value(dv, dl, x, y, c);
        }
}

static void test_smooth(void)
{
    float dirs[2 * 81];
    prw_btf_dirs_ubo81(dirs);
    prw_btf b;
    prw_btf_dirtab t;
    prw_error e;
    CHECK_OK(prw_btf_create(2, 2, 81, 81, &b, &e), &e);
    memcpy(b.view_dirs, dirs, sizeof dirs);
    memcpy(b.light_dirs, dirs, sizeof dirs);
    fill_smooth(&b, dirs);
    CHECK_OK(prw_btf_dirtab_build(dirs, 81, &t, &e), &e);
    /* exact at measured pairs and texel centres (with wrap: x + 2 is the same texel) */
    double worst_exact = 0, vmax = 0;
    for (uint32_t v = 0; v < 81; v += 7)
        for (uint32_t l = 0; l < 81; l += 5) {
            double dv[3], dl[3];
            prw_btf_dir_vector(dirs[2 * v], dirs[2 * v + 1], dv);
            prw_btf_dir_vector(dirs[2 * l], dirs[2 * l + 1], dl);
            float rgb[3];
            prw_btf_eval(&b, &t, &t, 1.5 + 2 * (int)(v % 3) - 2, -0.5, dv, dl, rgb); /* texel (1, 1) */
            for (int c = 0; c < 3; c++) worst_exact = fmax(worst_exact, fabs(rgb[c] - b.rgb[prw_btf_at(&b, v, l, 1, 1) + c]));
        }
    for (size_t i = 0; i < (size_t)81 * 81 * 4 * 3; i++) vmax = fmax(vmax, b.rgb[i]);
    printf("exact at measured pairs: worst |diff| %.3g (max value %.3g)\n", worst_exact, vmax);
    CHECK(worst_exact <= 1e-6 * vmax);
    /* between the measured directions, texel (0, 0) centre; and bilinear half-way between texels */
    double worst_in = 0, worst_all = 0, worst_bil = 0;
    int n = prw_test_scale(100000, 10);
    for (int i = 0; i < n; i++) {
        double dv[3], dl[3];
        rand_dir(PRW_PI / 2, dv);
        rand_dir(PRW_PI / 2, dl);
        float rgb[3], mid[3];
        prw_btf_eval(&b, &t, &t, 0.5, 0.5, dv, dl, rgb);
        prw_btf_eval(&b, &t, &t, 1.0, 0.5, dv, dl, mid); /* half-way between texels (0,0) and (1,0) */
        bool in = dv[2] >= cos(75 * PRW_PI / 180) && dl[2] >= cos(75 * PRW_PI / 180);
        for (int c = 0; c < 3; c++) {
            double err = fabs(rgb[c] - smooth_value(dv, dl, 0, 0, c)) / vmax;
            if (in) worst_in = fmax(worst_in, err);
            worst_all = fmax(worst_all, err);
            float r1[3];
            prw_btf_eval(&b, &t, &t, 1.5, 0.5, dv, dl, r1);
            worst_bil = fmax(worst_bil, fabs(mid[c] - 0.5 * (rgb[c] + r1[c])) / vmax);
        }
    }
    printf("smooth BRDF x cos: worst error / max value %.4f within 75 deg (both directions), %.4f over the whole "
           "hemisphere; bilinear half-way between texels: %.2g\n",
           worst_in, worst_all, worst_bil);
    CHECK(worst_in <= 0.03);
    CHECK(worst_bil <= 1e-6);
    /* packed (FMF with 4 components: 4 texels, exact up to half precision) */
    prw_btf_codec_params cp = {.codec = PRW_BTF_CODEC_FMF, .components = 4, .seed = 1, .threads = 1};
    prw_btf_packed p;
    CHECK_OK(prw_btf_compress(&b, &cp, &p, &e), &e);
    prw_btf_material m;
    CHECK_OK(prw_btf_material_from_packed(&p, "smooth", &m, &e), &e);
    CHECK(m.shared);
    double worst_p = 0;
    for (int i = 0; i < 2000; i++) {
        double dv[3], dl[3], x = 4 * rnd() - 2, y = 4 * rnd() - 2;
        rand_dir(PRW_PI / 2, dv);
        rand_dir(PRW_PI / 2, dl);
        float a[3], h[3];
        prw_btf_eval(&b, &t, &t, x, y, dv, dl, a);
        prw_btf_material_eval(&m, x, y, dv, dl, h);
        for (int c = 0; c < 3; c++) worst_p = fmax(worst_p, fabs(a[c] - h[c]) / vmax);
    }
    printf("packed (FMF 4) against raw: worst |diff| / max %.3g\n", worst_p);
    CHECK(worst_p < 4e-3);
    prw_btf_material_free(&m);
    prw_btf_dirtab_free(&t);
    prw_btf_free(&b);
}

static void test_refused(void)
{
    prw_btf_dirtab t;
    prw_error e;
    float two[4] = {0.2f, 1.0f, 0.2f, 1.0f};
    CHECK(!prw_btf_dirtab_build(two, 2, &t, &e) && strstr(e.msg, "directions 0 and 1 are the same"));
    printf("refused: %s\n", e.msg);
    float flat[2] = {1.6f, 0};
    CHECK(!prw_btf_dirtab_build(flat, 1, &t, &e) && strstr(e.msg, "direction 0"));
    printf("refused: %s\n", e.msg);
    float nan[2] = {NAN, 0};
    CHECK(!prw_btf_dirtab_build(nan, 1, &t, &e) && strstr(e.msg, "direction 0"));
    CHECK(!prw_btf_dirtab_build(two, 0, &t, &e));
    /* a single direction (the normal) and the first 16 Bonn directions still triangulate */
    float one[2] = {0, 0};
    CHECK_OK(prw_btf_dirtab_build(one, 1, &t, &e), &e);
    prw_btf_dirtab_free(&t);
    float dirs[2 * 81];
    prw_btf_dirs_ubo81(dirs);
    CHECK_OK(prw_btf_dirtab_build(dirs, 16, &t, &e), &e);
    double d[3] = {0.3, -0.8, 0.2};
    uint32_t idx[3];
    float w[3];
    prw_btf_dirtab_weights(&t, d, false, idx, w);
    CHECK(fabs(w[0] + w[1] + w[2] - 1) < 1e-5);
    prw_btf_dirtab_free(&t);
}

/* The scale rule's average: a BTF sampled from the material model itself (every texel the same material,
 * or half the texels each of two base colours) is fitted back: parameters and rms; the file (version 2)
 * round-trips it; a version-1 file (no average) still reads. */
static void test_average(void)
{
    float dirs[2 * 81];
    prw_btf_dirs_ubo81(dirs);
    static const struct {
        double base[3], base2[3], metallic, roughness;
    } cases[] = {
        {{0.7, 0.3, 0.1}, {0.7, 0.3, 0.1}, 0.0, 0.5},
        {{0.9, 0.8, 0.5}, {0.9, 0.8, 0.5}, 1.0, 0.3},
        {{0.6, 0.2, 0.2}, {0.2, 0.2, 0.6}, 0.0, 0.7}, /* two colours: the fit is their mean */
    };
    prw_error e;
    for (size_t k = 0; k < PRW_ARRAY_LEN(cases); k++) {
        prw_btf b;
        CHECK_OK(prw_btf_create(2, 1, 81, 81, &b, &e), &e);
        memcpy(b.view_dirs, dirs, sizeof dirs);
        memcpy(b.light_dirs, dirs, sizeof dirs);
        for (uint32_t x = 0; x < 2; x++) {
            prw_bsdf m = {.metallic = cases[k].metallic, .roughness = cases[k].roughness, .specular = 1};
            for (int c = 0; c < 3; c++) m.base[c] = x ? cases[k].base2[c] : cases[k].base[c];
            for (uint32_t v = 0; v < 81; v++)
                for (uint32_t l = 0; l < 81; l++) {
                    double wo[3], wi[3], f[3];
                    prw_btf_dir_vector(dirs[2 * v], dirs[2 * v + 1], wo);
                    prw_btf_dir_vector(dirs[2 * l], dirs[2 * l + 1], wi);
                    prw_bsdf_eval(&m, wo, wi, f);
                    for (int c = 0; c < 3; c++) b.rgb[prw_btf_at(&b, v, l, x, 0) + c] = (float)(f[c] * wi[2]);
                }
        }
        double t0 = prw_now();
        prw_btf_average av;
        CHECK_OK(prw_btf_fit_average(&b, &av, &e), &e);
        double t1 = prw_now();
        printf("average %zu: base %.3f %.3f %.3f metallic %.2f roughness %.4f, rms %.3f %% (%.2f s)\n", k, av.base[0], av.base[1],
               av.base[2], av.metallic, av.roughness, av.rms_pct, t1 - t0);
        for (int c = 0; c < 3; c++) CHECK_NEAR(av.base[c], 0.5 * (cases[k].base[c] + cases[k].base2[c]), 0.01);
        CHECK_NEAR(av.metallic, cases[k].metallic, 1e-6);
        CHECK_NEAR(av.roughness, cases[k].roughness, 0.0125);
        CHECK(av.rms_pct < 1.0);
        /* the file keeps it (version 2) */
        prw_btf_codec_params cp = {.codec = PRW_BTF_CODEC_FMF, .components = 2, .seed = 1, .threads = 1};
        prw_btf_packed p, q;
        CHECK_OK(prw_btf_compress(&b, &cp, &p, &e), &e);
        CHECK(p.has_average && p.average.roughness == av.roughness && p.average.base[0] == av.base[0]);
        char *path = prw_test_path("avg.btfc");
        CHECK_OK(prw_btf_packed_write(path, &p, &e), &e);
        CHECK_OK(prw_btf_packed_read(path, &q, &e), &e);
        CHECK(q.has_average && memcmp(&q.average, &p.average, sizeof p.average) == 0);
        prw_btf_packed_free(&q);
        if (k == 0) {
            /* every truncation refused naming the file; an average out of range refused */
            char *data = NULL;
            size_t n = 0;
            CHECK_OK(prw_read_file(path, &data, &n, &e), &e);
            CHECK(n == prw_btf_packed_bytes(&p));
            int accepted = 0;
            for (size_t len = 0; len < n; len++) {
                if (prw_btf_packed_read_memory(data, len, "cut.btfc", &q, &e)) accepted++, prw_btf_packed_free(&q);
                else if (strncmp(e.msg, "cut.btfc: ", 10) != 0) accepted += 1000;
            }
            CHECK_MSG(accepted == 0, "%d truncations accepted or misnamed", accepted);
            float two = 2.0f; /* the roughness: the 5th float of the 7 at the end */
            memcpy(data + n - 28 + 16, &two, 4);
            CHECK(!prw_btf_packed_read_memory(data, n, "bad.btfc", &q, &e) && strstr(e.msg, "average"));
            printf("refused: %s\n", e.msg);
            free(data);
        }
        /* without the average: version 1, 24 bytes shorter, read back without one */
        p.has_average = false;
        CHECK_OK(prw_btf_packed_write(path, &p, &e), &e);
        CHECK_OK(prw_btf_packed_read(path, &q, &e), &e);
        CHECK(!q.has_average);
        prw_btf_packed_free(&q);
        prw_btf_packed_free(&p);
        prw_btf_free(&b);
    }
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"weights", test_weights}, {"smooth", test_smooth}, {"refused", test_refused}, {"average", test_average}};
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
