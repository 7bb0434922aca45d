/* SSIM (ssim.c): identity, the closed form for constant images, and a direct (non-separable)
 * evaluation of the definition on every window.  The scikit-image oracle is ssim_oracle.py. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_metrics.h"
#include "prw_test.h"
#include "testutil.h"

/* SSIM of the 11x11 window centred at (cx, cy), straight from the definition with 2-D weights. */
static double ssim_direct(const float *a, const float *b, int w, int cx, int cy)
{
    double wsum = 0, mx = 0, my = 0, sxx = 0, syy = 0, sxy = 0;
    for (int dy = -5; dy <= 5; dy++)
        for (int dx = -5; dx <= 5; dx++) wsum += exp(-(dx * dx + dy * dy) / (2 * 1.5 * 1.5));
    for (int dy = -5; dy <= 5; dy++)
        for (int dx = -5; dx <= 5; dx++) {
            double wk = exp(-(dx * dx + dy * dy) / (2 * 1.5 * 1.5)) / wsum;
            double x = a[(cy + dy) * w + cx + dx], y = b[(cy + dy) * w + cx + dx];
            mx += wk * x;
            my += wk * y;
        }
    for (int dy = -5; dy <= 5; dy++)
        for (int dx = -5; dx <= 5; dx++) {
            double wk = exp(-(dx * dx + dy * dy) / (2 * 1.5 * 1.5)) / wsum;
            double x = a[(cy + dy) * w + cx + dx] - mx, y = b[(cy + dy) * w + cx + dx] - my;
            sxx += wk * x * x; /* population (weighted) moments */
            syy += wk * y * y;
            sxy += wk * x * y;
        }
    double c1 = 0.01 * 0.01, c2 = 0.03 * 0.03;
    return (2 * mx * my + c1) * (2 * sxy + c2) / ((mx * mx + my * my + c1) * (sxx + syy + c2));
}

static void t_identical(void)
{
    prw_error e = {{0}};
    int w = 40, h = 31;
    float *a = malloc(sizeof(float) * w * h);
    trng r = {3};
    for (int i = 0; i < w * h; i++) a[i] = (float)trng_uniform(&r);
    double s;
    float *map = malloc(sizeof(float) * (w - 10) * (h - 10));
    CHECK_OK(prw_ssim_gray(a, a, w, h, &s, map, &e), &e);
    CHECK_NEAR(s, 1.0, 1e-12);
    for (int i = 0; i < (w - 10) * (h - 10); i++) CHECK_NEAR(map[i], 1.0, 1e-6);
    free(a);
    free(map);
}

/* Constant images: variances and covariance vanish, SSIM = (2 ma mb + C1) / (ma^2 + mb^2 + C1). */
static void t_constant_closed_form(void)
{
    prw_error e = {{0}};
    int w = 16, h = 12;
    float *a = malloc(sizeof(float) * w * h), *b = malloc(sizeof(float) * w * h);
    const float pairs[][2] = {{0.25f, 0.75f}, {0.0f, 0.1f}, {0.5f, 0.5f}, {0.9f, 0.02f}};
    for (size_t p = 0; p < PRW_ARRAY_LEN(pairs); p++) {
        for (int i = 0; i < w * h; i++) a[i] = pairs[p][0], b[i] = pairs[p][1];
        double ma = pairs[p][0], mb = pairs[p][1], c1 = 1e-4, s;
        CHECK_OK(prw_ssim_gray(a, b, w, h, &s, NULL, &e), &e);
        CHECK_NEAR(s, (2 * ma * mb + c1) / (ma * ma + mb * mb + c1), 1e-9);
    }
    /* colour: luma of the encoded values with the Rec.709 coefficients */
    prw_image ia, ib;
    CHECK_OK(prw_image_alloc(&ia, w, h, &e), &e);
    CHECK_OK(prw_image_alloc(&ib, w, h, &e), &e);
    fill_rgb(&ia, 0.2f, 0.6f, 0.9f);
    fill_rgb(&ib, 0.7f, 0.1f, 0.3f);
    double ya = 0.2126 * 0.2f + 0.7152 * 0.6f + 0.0722 * 0.9f, yb = 0.2126 * 0.7f + 0.7152 * 0.1f + 0.0722 * 0.3f;
    double s;
    CHECK_OK(prw_ssim_encoded(&ia, &ib, &s, &e), &e);
    CHECK_NEAR(s, (2 * ya * yb + 1e-4) / (ya * ya + yb * yb + 1e-4), 1e-6);
    prw_image_free(&ia);
    prw_image_free(&ib);
    free(a);
    free(b);
}

/* Every window of a random pair against the direct definition; the mean over valid windows only. */
static void t_direct_definition(void)
{
    prw_error e = {{0}};
    int w = 23, h = 17;
    float *a = malloc(sizeof(float) * w * h), *b = malloc(sizeof(float) * w * h);
    trng r = {11};
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            double v = 0.5 + 0.4 * sin(0.3 * x + 0.2 * y) + 0.1 * trng_uniform(&r);
            a[y * w + x] = (float)v;
            b[y * w + x] = (float)(0.7 * v + 0.1 + 0.15 * trng_normal(&r));
        }
    double s;
    float *map = malloc(sizeof(float) * (w - 10) * (h - 10));
    CHECK_OK(prw_ssim_gray(a, b, w, h, &s, map, &e), &e);
    double sum = 0;
    for (int cy = 5; cy < h - 5; cy++)
        for (int cx = 5; cx < w - 5; cx++) {
            double d = ssim_direct(a, b, w, cx, cy);
            sum += d;
            CHECK_NEAR(map[(cy - 5) * (w - 10) + (cx - 5)], d, 1e-6);
        }
    CHECK_NEAR(s, sum / ((w - 10) * (h - 10)), 1e-10);
    CHECK(s < 0.9 && s > -1.0);
    /* an 11x11 image has exactly one window */
    float a11[121], b11[121];
    for (int i = 0; i < 121; i++) a11[i] = a[i], b11[i] = b[i];
    CHECK_OK(prw_ssim_gray(a11, b11, 11, 11, &s, NULL, &e), &e);
    CHECK_NEAR(s, ssim_direct(a11, b11, 11, 5, 5), 1e-10);
    /* smaller than the window */
    CHECK(!prw_ssim_gray(a11, b11, 10, 12, &s, NULL, &e));
    CHECK_MSG(strstr(e.msg, "10x12") != NULL, "%s", e.msg);
    free(a);
    free(b);
    free(map);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"identical", t_identical},
        {"constant_closed_form", t_constant_closed_form},
        {"direct_definition", t_direct_definition},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
