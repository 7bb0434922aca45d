/* prw_env: SH irradiance against closed forms and direct integration; the split-sum prefilter's
 * properties (uniform stays uniform, roughness 0 reproduces the map, the sphere mean is kept,
 * thread-count independence); the DFG terms against the material model's own albedo fit. */
#include <stdlib.h>
#include <string.h>

#include "prw_brdf.h"
#include "prw_env.h"
#include "prw_test.h"

#define PI 3.14159265358979323846

static float *map_new(uint32_t w, uint32_t h) { return prw_calloc((size_t)w * h * 3, sizeof(float)); }

/* Direct numerical irradiance: sum over pixels of L max(n.d, 0) dOmega, each pixel split into s x s
 * sub-pixels (the map is constant per pixel, the cosine is not). */
static void direct_irradiance(const float *rgb, uint32_t w, uint32_t h, const double n[3], int s, double out[3])
{
    out[0] = out[1] = out[2] = 0;
    for (uint32_t j = 0; j < h; j++)
        for (int sj = 0; sj < s; sj++) {
            double v0 = (j + (double)sj / s) / h, v1 = (j + (sj + 1.0) / s) / h;
            double dw = 2 * PI / (w * s) * (cos(PI * v0) - cos(PI * v1));
            for (uint32_t i = 0; i < w; i++)
                for (int si = 0; si < s; si++) {
                    double d[3];
                    prw_env_uv_to_dir((i + (si + 0.5) / s) / w, 0.5 * (v0 + v1), d);
                    double c = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
                    if (c <= 0) continue;
                    const float *p = rgb + 3 * ((size_t)j * w + i);
                    for (int k = 0; k < 3; k++) out[k] += p[k] * c * dw;
                }
        }
}

static void random_dir(uint32_t *st, double d[3])
{
    for (;;) {
        for (int k = 0; k < 3; k++) {
            *st = *st * 1664525u + 1013904223u;
            d[k] = (*st >> 8) / 8388608.0 - 1.0;
        }
        double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (l > 0.1 && l <= 1) {
            for (int k = 0; k < 3; k++) d[k] /= l;
            return;
        }
    }
}

static void test_mapping(void)
{
    /* The prw_environment convention: image centre column = -Z, u grows towards +X, row 0 = +Y. */
    double d[3], u, v;
    prw_env_uv_to_dir(0.5, 0.5, d);
    CHECK(fabs(d[2] + 1) < 1e-12);
    prw_env_uv_to_dir(0.75, 0.5, d);
    CHECK(fabs(d[0] - 1) < 1e-12);
    prw_env_uv_to_dir(0.3, 0.0, d);
    CHECK(fabs(d[1] - 1) < 1e-12);
    uint32_t st = 7;
    for (int k = 0; k < 100; k++) {
        double a[3], b[3];
        random_dir(&st, a);
        prw_env_dir_to_uv(a, &u, &v);
        prw_env_uv_to_dir(u, v, b);
        CHECK(fabs(a[0] - b[0]) + fabs(a[1] - b[1]) + fabs(a[2] - b[2]) < 1e-12);
    }
    double sum = 0;
    for (uint32_t j = 0; j < 37; j++) sum += 50 * prw_env_pixel_solid_angle(50, 37, j);
    CHECK_NEAR(sum, 4 * PI, 1e-12);
}

static void test_sh_uniform(void)
{
    uint32_t w = 64, h = 32;
    float *m = map_new(w, h);
    for (size_t k = 0; k < (size_t)w * h; k++) m[3 * k] = 1, m[3 * k + 1] = 2, m[3 * k + 2] = 0.5f;
    float sh[9][3];
    prw_error e;
    CHECK_OK(prw_env_sh_project(m, w, h, sh, &e), &e);
    uint32_t st = 1;
    double worst = 0;
    for (int t = 0; t < 200; t++) {
        double n[3];
        random_dir(&st, n);
        float E[3];
        prw_env_sh_irradiance(sh, n, E);
        worst = fmax(worst, fabs(E[0] - PI) / PI);
        worst = fmax(worst, fabs(E[1] - 2 * PI) / (2 * PI));
        worst = fmax(worst, fabs(E[2] - 0.5 * PI) / (0.5 * PI));
    }
    printf("sh uniform: max relative error of E = pi L over 200 normals %.2e\n", worst);
    CHECK(worst < 1e-4);
    free(m);
}

/* L0 above the horizon (y > 0), 0 below: E(theta) = pi L0 (1 + cos theta) / 2 exactly for the SH9
 * irradiance (the step has no even l >= 2 content and A_l = 0 for odd l >= 3), so the only error is
 * float rounding; the direct integration of the map is the independent check. */
static void test_sh_hemisphere(void)
{
    uint32_t w = 256, h = 128; /* even h: the horizon is a row border */
    float *m = map_new(w, h);
    for (uint32_t j = 0; j < h / 2; j++)
        for (uint32_t i = 0; i < w; i++) m[3 * ((size_t)j * w + i)] = m[3 * ((size_t)j * w + i) + 1] = m[3 * ((size_t)j * w + i) + 2] = 2.0f;
    float sh[9][3];
    prw_error e;
    CHECK_OK(prw_env_sh_project(m, w, h, sh, &e), &e);
    double worst_cf = 0, worst_direct = 0;
    for (int t = 0; t <= 12; t++) {
        double th = PI * t / 12, n[3] = {sin(th) * 0.6, cos(th), sin(th) * 0.8};
        float E[3];
        prw_env_sh_irradiance(sh, n, E);
        double exact = PI * 2.0 * (1 + cos(th)) / 2;
        double dir[3];
        direct_irradiance(m, w, h, n, 2, dir);
        worst_cf = fmax(worst_cf, fabs(E[0] - exact) / (2 * PI));
        worst_direct = fmax(worst_direct, fabs(dir[0] - exact) / (2 * PI));
    }
    printf("sh hemisphere: max |E_sh - E_exact| / (pi L0) %.2e; direct integration vs exact %.2e\n", worst_cf,
           worst_direct);
    CHECK(worst_cf < 1e-4);
    CHECK(worst_direct < 2e-3);
    free(m);
}

/* A sky with a sun-like blob: SH9 irradiance against direct integration.  The truncation error
 * (l >= 4 content) is what is printed (3.9 % of the mean irradiance at the worst of 40 normals);
 * the bound is loose (5 %). */
static void test_sh_vs_direct(void)
{
    uint32_t w = 128, h = 64;
    float *m = map_new(w, h);
    double sun[3] = {0.3, 0.8, -0.52};
    double l = sqrt(sun[0] * sun[0] + sun[1] * sun[1] + sun[2] * sun[2]);
    for (int k = 0; k < 3; k++) sun[k] /= l;
    for (uint32_t j = 0; j < h; j++)
        for (uint32_t i = 0; i < w; i++) {
            double d[3];
            prw_env_uv_to_dir((i + 0.5) / w, (j + 0.5) / h, d);
            double c = d[0] * sun[0] + d[1] * sun[1] + d[2] * sun[2];
            double sky = d[1] > 0 ? 1 + d[1] : 0.3;
            double blob = c > 0.95 ? 20 * (c - 0.95) / 0.05 : 0;
            float *p = m + 3 * ((size_t)j * w + i);
            p[0] = (float)(sky + blob);
            p[1] = (float)(0.8 * sky + 0.9 * blob);
            p[2] = (float)(0.5 * sky + 0.6 * blob);
        }
    float sh[9][3];
    prw_error e;
    CHECK_OK(prw_env_sh_project(m, w, h, sh, &e), &e);
    uint32_t st = 3;
    double worst = 0, mean = 0;
    int nn = 40; /* 0.04 s: not scaled down in light mode (the bound is on the mean over these normals) */
    for (int t = 0; t < nn; t++) {
        double n[3], dir[3];
        random_dir(&st, n);
        float E[3];
        prw_env_sh_irradiance(sh, n, E);
        direct_irradiance(m, w, h, n, 1, dir);
        mean += dir[0] / nn;
        worst = fmax(worst, fabs(E[0] - dir[0]));
    }
    printf("sh vs direct (sky + sun blob, %d normals): max |E_sh - E_direct| = %.4f, %.2f %% of the mean E %.3f\n", nn,
           worst, 100 * worst / mean, mean);
    CHECK(worst < 0.05 * mean);
    free(m);
}

static void fill_test_map(float *m, uint32_t w, uint32_t h)
{
    uint32_t st = 11;
    for (uint32_t j = 0; j < h; j++)
        for (uint32_t i = 0; i < w; i++) {
            double d[3];
            prw_env_uv_to_dir((i + 0.5) / w, (j + 0.5) / h, d);
            st = st * 1664525u + 1013904223u;
            double noise = (st >> 8) / 16777216.0;
            float *p = m + 3 * ((size_t)j * w + i);
            p[0] = (float)(1 + d[1] + 0.5 * noise + (((i / 8) + (j / 8)) % 2 ? 4 : 0));
            p[1] = (float)(0.5 + 0.5 * d[0] * d[0] + noise);
            p[2] = (float)(((i / 4) % 2) ? 3 : 0.2);
        }
}

static double sphere_mean(const float *m, uint32_t w, uint32_t h, int c)
{
    double s = 0;
    for (uint32_t j = 0; j < h; j++) {
        double r = 0;
        for (uint32_t i = 0; i < w; i++) r += m[3 * ((size_t)j * w + i) + c];
        s += r * prw_env_pixel_solid_angle(w, h, j);
    }
    return s / (4 * PI);
}

static void test_prefilter_uniform(void)
{
    uint32_t w = 32, h = 16, oh = 16, levels = 5;
    float *m = map_new(w, h);
    for (size_t k = 0; k < (size_t)w * h; k++) m[3 * k] = 3, m[3 * k + 1] = 0.25f, m[3 * k + 2] = 1;
    float *out = prw_malloc((size_t)levels * oh * 2 * oh * 3 * sizeof(float));
    prw_error e;
    CHECK_OK(prw_env_prefilter(m, w, h, oh, levels, 64, out, &e), &e);
    double worst = 0;
    for (size_t k = 0; k < (size_t)levels * oh * 2 * oh; k++) {
        worst = fmax(worst, fabs(out[3 * k] - 3.0) / 3);
        worst = fmax(worst, fabs(out[3 * k + 1] - 0.25) / 0.25);
        worst = fmax(worst, fabs(out[3 * k + 2] - 1.0));
    }
    printf("prefilter uniform: max relative deviation over %u levels %.2e\n", levels, worst);
    CHECK(worst < 1e-5);
    free(out);
    free(m);
}

/* Roughness 0 (alpha 0.002): the lobe is narrower than a texel, so an output texel centre gets its
 * own source texel but for the GGX tail: of 256 Hammersley half vectors, those with
 * tan theta_h > 0.0245 (0.66 %) leave a texel of 5.6 degrees, hence |P_0 - L| <= ~0.01 on values in
 * [0, 1).  Near the poles a texel is narrower than the lobe in u: printed, not checked.  Checked on
 * a map of independent random texels (any blur shows). */
static void test_prefilter_r0(void)
{
    uint32_t w = 64, h = 32;
    float *m = map_new(w, h);
    uint32_t st = 5;
    for (size_t k = 0; k < (size_t)w * h * 3; k++) {
        st = st * 1664525u + 1013904223u;
        m[k] = (st >> 8) / 16777216.0f;
    }
    float *out = prw_malloc((size_t)2 * h * w * 3 * sizeof(float));
    prw_error e;
    CHECK_OK(prw_env_prefilter(m, w, h, h, 2, 256, out, &e), &e);
    double worst = 0, worst1 = 0, worst_pole = 0;
    for (size_t k = 0; k < (size_t)w * h * 3; k++) {
        uint32_t j = (uint32_t)(k / 3 / w);
        double st_ = sin(PI * (j + 0.5) / h);
        if (st_ > 0.5) worst = fmax(worst, fabs(out[k] - m[k]));
        else worst_pole = fmax(worst_pole, fabs(out[k] - m[k]));
        worst1 = fmax(worst1, fabs(out[(size_t)w * h * 3 + k] - m[k]));
    }
    printf("  near the poles (sin theta <= 0.5): %.3f\n", worst_pole);
    printf("prefilter roughness 0: max |P_0 - L| %.2e (values in [0, 1)); roughness 1: %.3f\n", worst, worst1);
    CHECK(worst < 0.01);
    CHECK(worst1 > 0.1); /* roughness 1 blurs: the check above can see a blur */
    free(out);
    free(m);
}

/* The kernel depends on d.l only, so the sphere mean of every level equals the source's up to the
 * sampling error.  Bound: 1 % (what 256 Hammersley samples give on this map is printed). */
static void test_prefilter_energy(void)
{
    uint32_t w = 128, h = 64, oh = 32, levels = 4, S = (uint32_t)prw_test_scale(256, 2);
    float *m = map_new(w, h);
    fill_test_map(m, w, h);
    float *out = prw_malloc((size_t)levels * oh * 2 * oh * 3 * sizeof(float));
    prw_error e;
    CHECK_OK(prw_env_prefilter(m, w, h, oh, levels, S, out, &e), &e);
    for (uint32_t k = 0; k < levels; k++) {
        double worst = 0;
        for (int c = 0; c < 3; c++) {
            double a = sphere_mean(m, w, h, c), b = sphere_mean(out + (size_t)k * oh * 2 * oh * 3, 2 * oh, oh, c);
            worst = fmax(worst, fabs(b - a) / a);
        }
        printf("prefilter energy: level %u (roughness %.2f, %u samples): max relative change of the sphere mean %.2e\n",
               k, prw_env_level_roughness(k, levels), S, worst);
        CHECK(worst < 0.01);
    }
    free(out);
    free(m);
}

static void test_prefilter_threads(void)
{
    uint32_t w = 64, h = 32, oh = 16, levels = 3;
    float *m = map_new(w, h);
    fill_test_map(m, w, h);
    size_t n = (size_t)levels * oh * 2 * oh * 3;
    float *a = prw_malloc(n * sizeof(float)), *b = prw_malloc(n * sizeof(float));
    prw_error e;
    int saved = prw_threads_get();
    prw_threads_set(1);
    CHECK_OK(prw_env_prefilter(m, w, h, oh, levels, 64, a, &e), &e);
    prw_threads_set(3);
    CHECK_OK(prw_env_prefilter(m, w, h, oh, levels, 64, b, &e), &e);
    prw_threads_set(saved);
    CHECK(memcmp(a, b, n * sizeof(float)) == 0);
    free(a);
    free(b);
    free(m);
}

static void test_prefilter_bad_input(void)
{
    float m[3 * 8] = {0};
    float out[3 * 8];
    prw_error e;
    m[7] = NAN;
    CHECK(!prw_env_prefilter(m, 4, 2, 1, 1, 1, out, &e));
    CHECK(strstr(e.msg, "not finite") != NULL);
    m[7] = 0;
    CHECK(!prw_env_prefilter(m, 4, 2, 1, 0, 1, out, &e));
    CHECK(!prw_env_prefilter(m, 1, 2, 1, 1, 1, out, &e));
    float sh[9][3];
    m[0] = INFINITY;
    CHECK(!prw_env_sh_project(m, 4, 2, sh, &e));
}

/* A + B is the single-scattering albedo with F = 1: 1 - Ec of the material model's fit (generated
 * by an independent quadrature, materials/tools/gen_ggx_fit.c); B <= A + B; Schlick at F0 = 1 is F = 1. */
static void test_dfg(void)
{
    double worst = 0;
    const double mus[] = {0.1, 0.3, 0.6, 1.0}, rs[] = {0.1, 0.3, 0.6, 1.0};
    for (int a = 0; a < 4; a++)
        for (int r = 0; r < 4; r++) {
            double A, B;
            prw_env_dfg(mus[a], rs[r], &A, &B);
            double E = 1 - prw_ggx_Ec((float)mus[a], (float)rs[r]);
            worst = fmax(worst, fabs(A + B - E));
            CHECK(A >= 0 && B >= 0 && B < A + B);
        }
    printf("dfg: max |A + B - (1 - Ec_fit)| over 16 (mu, roughness) %.4f\n", worst);
    CHECK(worst < 0.01);
    /* A mirror (roughness 0, alpha 0.002) reflects F(mu): B = (1 - mu)^5, A = 1 - B. */
    double worst0 = 0;
    for (int a = 0; a < 4; a++) {
        double A, B, mu = mus[a] * 0.9;
        prw_env_dfg(mu, 0.0, &A, &B);
        worst0 = fmax(worst0, fabs(B - pow(1 - mu, 5)) + fabs(A - (1 - pow(1 - mu, 5))));
    }
    printf("dfg: roughness 0 against Schlick at the mirror direction: max error %.2e\n", worst0);
    CHECK(worst0 < 0.01);
}

static const prw_test_case cases[] = {
    {"mapping", test_mapping},
    {"sh_uniform", test_sh_uniform},
    {"sh_hemisphere", test_sh_hemisphere},
    {"sh_vs_direct", test_sh_vs_direct},
    {"prefilter_uniform", test_prefilter_uniform},
    {"prefilter_r0", test_prefilter_r0},
    {"prefilter_energy", test_prefilter_energy},
    {"prefilter_threads", test_prefilter_threads},
    {"prefilter_bad_input", test_prefilter_bad_input},
    {"dfg", test_dfg},
};

int main(int argc, char **argv) { return prw_test_main(argc, argv, cases, (int)(sizeof cases / sizeof cases[0])); }
