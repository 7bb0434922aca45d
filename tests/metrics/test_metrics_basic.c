/* RMSE, relMSE, PSNR (basic.c) and the frozen metric tone map (tonemap_metric.c). */
#include <math.h>
#include <string.h>

#include "prw_metrics.h"
#include "prw_test.h"
#include "testutil.h"

static void t_identical(void)
{
    prw_error e = {{0}};
    prw_image a;
    CHECK_OK(prw_image_alloc(&a, 17, 9, &e), &e);
    trng r = {7};
    for (int i = 0; i < 17 * 9 * 4; i++) a.rgba[i] = (float)(3.0 * trng_uniform(&r));
    prw_basic_metrics m;
    CHECK_OK(prw_metrics_basic(&a, &a, 0.0, &m, &e), &e);
    CHECK(m.mse == 0.0 && m.rmse == 0.0 && m.relmse == 0.0);
    CHECK(isinf(m.psnr) && m.psnr > 0); /* reported as "inf" by prw compare */
    CHECK_NEAR(m.peak, prw_image_max_rgb(&a), 0.0);
    prw_image_free(&a);
}

/* Added Gaussian noise of variance s^2: PSNR = 10 log10(peak^2 / s^2). */
static void t_psnr_noise(void)
{
    prw_error e = {{0}};
    const int w = 1024, h = 1024;
    const double sigma = 0.02;
    prw_image ref, test;
    CHECK_OK(prw_image_alloc(&ref, w, h, &e), &e);
    CHECK_OK(prw_image_alloc(&test, w, h, &e), &e);
    trng r = {0x9E3779B97F4A7C15ULL};
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            for (int c = 0; c < 3; c++) {
                float v = (float)(0.25 + 1.75 * x / (w - 1.0)); /* max channel value 2.0 */
                px(&ref, x, y)[c] = v;
                px(&test, x, y)[c] = (float)(v + sigma * trng_normal(&r));
            }
    prw_basic_metrics m;
    CHECK_OK(prw_metrics_basic(&test, &ref, 1.0, &m, &e), &e);
    /* 3 M samples: the MSE estimate is within ~0.3 % (4 sd), i.e. ~0.012 dB */
    CHECK_NEAR(m.psnr, 10.0 * log10(1.0 / (sigma * sigma)), 0.02);
    CHECK_NEAR(m.rmse, sigma, sigma * 0.003);
    CHECK_OK(prw_metrics_basic(&test, &ref, 0.0, &m, &e), &e); /* default peak: reference max */
    CHECK_NEAR(m.peak, 2.0, 1e-6);
    CHECK_NEAR(m.psnr, 10.0 * log10(4.0 / (sigma * sigma)), 0.02);
    prw_image_free(&ref);
    prw_image_free(&test);
}

/* relMSE on constant images: (t - r)^2 / (r^2 + 0.01), averaged over the channels. */
static void t_relmse_constant(void)
{
    prw_error e = {{0}};
    prw_image ref, test;
    CHECK_OK(prw_image_alloc(&ref, 8, 5, &e), &e);
    CHECK_OK(prw_image_alloc(&test, 8, 5, &e), &e);
    fill_rgb(&ref, 0.3f, 2.0f, 0.0f);
    fill_rgb(&test, 0.4f, 1.5f, 0.05f);
    prw_basic_metrics m;
    CHECK_OK(prw_metrics_basic(&test, &ref, 0.0, &m, &e), &e);
    double r[3] = {0.3f, 2.0f, 0.0f}, t[3] = {0.4f, 1.5f, 0.05f}, rel = 0, se = 0;
    for (int c = 0; c < 3; c++) {
        rel += (t[c] - r[c]) * (t[c] - r[c]) / (r[c] * r[c] + 0.01);
        se += (t[c] - r[c]) * (t[c] - r[c]);
    }
    CHECK_NEAR(m.relmse, rel / 3.0, 1e-12);
    CHECK_NEAR(m.relmse, (0.01 / 0.1 + 0.25 / 4.01 + 0.0025 / 0.01) / 3.0, 1e-7); /* by hand */
    CHECK_NEAR(m.mse, se / 3.0, 1e-12);
    CHECK_NEAR(m.peak, 2.0, 0.0);
    CHECK_NEAR(m.psnr, 10.0 * log10(4.0 / (se / 3.0)), 1e-9);
    /* alpha is ignored */
    test.rgba[3] = 0.0f;
    prw_basic_metrics m2;
    CHECK_OK(prw_metrics_basic(&test, &ref, 0.0, &m2, &e), &e);
    CHECK(m2.mse == m.mse);
    prw_image_free(&ref);
    prw_image_free(&test);
}

static void t_basic_errors(void)
{
    prw_error e = {{0}};
    prw_image a, b;
    CHECK_OK(prw_image_alloc(&a, 8, 5, &e), &e);
    CHECK_OK(prw_image_alloc(&b, 8, 6, &e), &e);
    prw_basic_metrics m;
    CHECK(!prw_metrics_basic(&a, &b, 0.0, &m, &e));
    CHECK_MSG(strstr(e.msg, "8x5") && strstr(e.msg, "8x6"), "%s", e.msg);
    /* black reference: PSNR undefined with the default peak */
    CHECK_OK(prw_metrics_basic(&a, &a, 0.0, &m, &e), &e);
    CHECK(isnan(m.psnr));
    prw_image_free(&a);
    prw_image_free(&b);
}

static void t_tonemap(void)
{
    prw_error e = {{0}};
    CHECK(PRW_METRIC_TONEMAP_VERSION == 1);
    CHECK_NEAR(prw_metric_tonemap_scale(0.0), 1.0 / 1.2, 1e-15);
    CHECK_NEAR(prw_metric_tonemap_scale(10.0), 1.0 / (1.2 * 1024.0), 1e-15);
    /* sRGB OETF (IEC 61966-2-1) */
    CHECK_NEAR(prw_srgb_oetf(0.0f), 0.0, 0.0);
    CHECK_NEAR(prw_srgb_oetf(1.0f), 1.0, 0.0);
    CHECK_NEAR(prw_srgb_oetf(0.002f), 12.92 * 0.002, 1e-7);
    CHECK_NEAR(prw_srgb_oetf(0.5f), 1.055 * pow(0.5, 1 / 2.4) - 0.055, 1e-6);
    CHECK_NEAR(prw_srgb_oetf(0.18f), 0.4613561295, 1e-6);
    CHECK_NEAR(prw_srgb_oetf(-3.0f), 0.0, 0.0);
    CHECK_NEAR(prw_srgb_oetf(7.0f), 1.0, 0.0);
    for (float v = 0.0f; v <= 1.0f; v += 0.01f) CHECK_NEAR(prw_srgb_eotf(prw_srgb_oetf(v)), v, 2e-6);

    prw_image lin, enc;
    CHECK_OK(prw_image_alloc(&lin, 4, 1, &e), &e);
    const double ev = 6.5, white = 1.2 * pow(2.0, ev);
    float vals[4][3] = {{(float)white, (float)white, (float)white},
                        {(float)(0.18 * white), 0.0f, -5.0f},
                        {(float)(3 * white), (float)(0.001 * white), (float)(0.5 * white)},
                        {0, 0, 0}};
    for (int i = 0; i < 4; i++)
        for (int c = 0; c < 3; c++) lin.rgba[i * 4 + c] = vals[i][c];
    lin.rgba[3] = 0.25f;
    CHECK_OK(prw_metric_tonemap(&lin, ev, &enc, &e), &e);
    CHECK_NEAR(enc.rgba[0], 1.0, 1e-6); /* 1.2 * 2^EV100 cd/m^2 -> 1.0 */
    CHECK_NEAR(enc.rgba[3], 1.0, 0.0);
    CHECK_NEAR(enc.rgba[4], 0.4613561295, 1e-5);
    CHECK_NEAR(enc.rgba[5], 0.0, 0.0);
    CHECK_NEAR(enc.rgba[6], 0.0, 0.0); /* negative clamps to 0 */
    CHECK_NEAR(enc.rgba[8], 1.0, 0.0); /* above white clamps to 1 */
    CHECK_NEAR(enc.rgba[9], 12.92 * 0.001, 1e-6);
    CHECK_NEAR(enc.rgba[10], 1.055 * pow(0.5, 1 / 2.4) - 0.055, 1e-6);
    prw_image_free(&enc);
    CHECK(!prw_metric_tonemap(&lin, NAN, &enc, &e));
    prw_image_free(&lin);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"identical", t_identical},         {"psnr_noise", t_psnr_noise}, {"relmse_constant", t_relmse_constant},
        {"basic_errors", t_basic_errors},   {"tonemap", t_tonemap},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
