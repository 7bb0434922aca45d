/* Temporal glare (prw_glare.h; issue 6, optional pass before tone mapping), unit:
 *  - pupil:  Moon & Spencer closed form (4.9 mm at 0.1 cd/m^2, 4.9 -+ 3 tanh(...) at 1e9 and 1e-6,
 *            the guard), decreasing;
 *            hippus stays in [1, 9] mm and moves with time.
 *  - psf:    every band sums to 1, is finite, non-negative, point-symmetric (real aperture) and
 *            peaks at the centre; a wider pupil concentrates more energy in the centre pixel, and
 *            red (longer wavelength) spreads wider than blue.
 *  - apply:  light is conserved (an image with a dark border of the PSF radius keeps its sum per
 *            channel within 1e-3) and a constant image stays constant away from the border; the
 *            extremes (1e9 sun, NaN/Inf input) give finite non-negative pixels.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_glare.h"
#include "prw_test.h"

static void test_pupil(void)
{
    CHECK_NEAR(prw_glare_pupil_mm(0.1), 4.9, 1e-12);
    CHECK_NEAR(prw_glare_pupil_mm(1e9), 4.9 - 3.0 * tanh(4.0), 1e-12);   /* log10 = 9 */
    CHECK_NEAR(prw_glare_pupil_mm(1e-6), 4.9 + 3.0 * tanh(2.0), 1e-12);  /* log10 = -6 */
    CHECK(prw_glare_pupil_mm(1e-9) == prw_glare_pupil_mm(1e-6));          /* guarded at 1e-6 cd/m^2 */
    double prev = 1e9;
    for (double l = 1e-4; l < 1e6; l *= 3) {
        double p = prw_glare_pupil_mm(l);
        CHECK(p < prev);
        prev = p;
    }
    CHECK(isfinite(prw_glare_pupil_mm(NAN)) && isfinite(prw_glare_pupil_mm(INFINITY)) && isfinite(prw_glare_pupil_mm(0)));
    double lo = 1e9, hi = 0;
    for (double t = 0; t < 10; t += 0.05) {
        double h = prw_glare_pupil_hippus_mm(2.0, t, 3);
        lo = fmin(lo, h);
        hi = fmax(hi, h);
    }
    printf("pupil at 2 cd/m^2: %.3f mm, with hippus %.3f .. %.3f mm\n", prw_glare_pupil_mm(2.0), lo, hi);
    CHECK(lo >= 1.0 && hi <= 9.0 && hi - lo > 0.01);
}

static double centre_fraction(const float *psf, int R, int band)
{
    size_t side = 2 * (size_t)R + 1;
    return psf[(size_t)band * side * side + (size_t)R * side + (size_t)R];
}

/* Spectral bands: weights are a partition of each channel; each channel's mean wavelength lies near
 * the dominant wavelength of its Rec.709 primary (R 611, G 549, B 464 nm: from the primaries'
 * chromaticities and D65), so the colour-matching fit and the XYZ -> RGB step are the right way round. */
static void test_spectral(void)
{
    double l[PRW_GLARE_BANDS], w[PRW_GLARE_BANDS][3];
    prw_glare_spectral_weights(l, w);
    const double dominant[3] = {611, 549, 464};
    for (int c = 0; c < 3; c++) {
        double sum = 0, mean = 0;
        for (int m = 0; m < PRW_GLARE_BANDS; m++) {
            CHECK(w[m][c] >= 0 && isfinite(w[m][c]));
            sum += w[m][c];
            mean += w[m][c] * l[m];
        }
        CHECK_NEAR(sum, 1.0, 1e-12);
        printf("channel %d: mean wavelength %.1f nm\n", c, mean);
        CHECK_MSG(fabs(mean - dominant[c]) < 20, "channel %d mean wavelength %.1f nm", c, mean);
    }
    for (int m = 1; m < PRW_GLARE_BANDS; m++) CHECK(l[m] > l[m - 1]);
    CHECK(l[0] > PRW_GLARE_LAMBDA_MIN_NM && l[PRW_GLARE_BANDS - 1] < PRW_GLARE_LAMBDA_MAX_NM);
}

static void test_psf(void)
{
    prw_error e;
    prw_glare_settings s = {.n = 256, .ppd = 40, .seed = 7};
    float *psf[2] = {NULL, NULL};
    int R[2];
    const double pupils[2] = {3.0, 7.0};
    for (int k = 0; k < 2; k++) {
        CHECK_OK(prw_glare_psf(&s, pupils[k], &psf[k], &R[k], &e), &e);
        size_t side = 2 * (size_t)R[k] + 1;
        for (int b = 0; b < 3; b++) {
            const float *p = psf[k] + (size_t)b * side * side;
            double sum = 0, asym = 0, peak = 0;
            int bad = 0;
            for (size_t i = 0; i < side * side; i++) {
                bad += !(isfinite(p[i]) && p[i] >= 0);
                sum += p[i];
                asym = fmax(asym, fabs((double)p[i] - (double)p[side * side - 1 - i]));
                peak = fmax(peak, p[i]);
            }
            printf("pupil %.0f mm band %d: radius %d px, sum %.9f, centre %.4f, max asymmetry %.2g\n", pupils[k], b,
                   R[k], sum, centre_fraction(psf[k], R[k], b), asym);
            CHECK(bad == 0);
            CHECK_NEAR(sum, 1.0, 1e-5);
            CHECK(asym <= 1e-5 * peak);
            CHECK(centre_fraction(psf[k], R[k], b) == peak);
        }
        CHECK(centre_fraction(psf[k], R[k], 0) < centre_fraction(psf[k], R[k], 2)); /* red wider than blue */
    }
    CHECK(R[0] == R[1]);
    for (int b = 0; b < 3; b++) CHECK(centre_fraction(psf[1], R[1], b) > centre_fraction(psf[0], R[0], b));
    free(psf[0]);
    free(psf[1]);
    s.n = 100;
    float *p = NULL;
    int r;
    CHECK(!prw_glare_psf(&s, 4.0, &p, &r, &e) && p == NULL);
}

static void test_apply(void)
{
    prw_error e;
    prw_glare_settings s = {.n = 256, .ppd = 40, .seed = 1};
    float *psf = NULL;
    int R;
    CHECK_OK(prw_glare_psf(&s, 5.0, &psf, &R, &e), &e);
    int w = 96 + 2 * R, h = 80 + 2 * R;
    prw_image img;
    CHECK_OK(prw_image_alloc(&img, w, h, &e), &e);
    double before[3] = {0, 0, 0};
    for (int y = R; y < h - R; y++)
        for (int x = R; x < w - R; x++)
            for (int c = 0; c < 3; c++) {
                float v = (float)((x * 7 + y * 3 + c * 11) % 17) * (x == w / 2 && y == h / 2 ? 1e4f : 1.0f);
                img.rgba[4 * (y * w + x) + c] = v;
                before[c] += v;
            }
    CHECK_OK(prw_glare_apply(&img, psf, R, &e), &e);
    for (int c = 0; c < 3; c++) {
        double after = 0;
        for (int i = 0; i < w * h; i++) after += img.rgba[4 * i + c];
        printf("channel %d: sum before %.6g after %.6g\n", c, before[c], after);
        CHECK_NEAR(after, before[c], 1e-3 * before[c]);
    }
    /* constant image */
    for (int i = 0; i < w * h; i++)
        for (int c = 0; c < 3; c++) img.rgba[4 * i + c] = 2.5f;
    CHECK_OK(prw_glare_apply(&img, psf, R, &e), &e);
    double worst = 0;
    for (int y = R; y < h - R; y++)
        for (int x = R; x < w - R; x++)
            for (int c = 0; c < 3; c++) worst = fmax(worst, fabs(img.rgba[4 * (y * w + x) + c] - 2.5));
    CHECK_MSG(worst <= 1e-3 * 2.5, "constant image changes by %.3g", worst);
    /* extremes */
    for (int i = 0; i < w * h; i++)
        for (int c = 0; c < 3; c++) img.rgba[4 * i + c] = i % 13 == 0 ? NAN : i % 13 == 1 ? INFINITY : i % 13 == 2 ? -3.0f : 0.01f;
    img.rgba[4 * (h / 2 * w + w / 2)] = 1e9f;
    CHECK_OK(prw_glare_apply(&img, psf, R, &e), &e);
    int bad = 0;
    for (int i = 0; i < w * h * 4; i++) bad += !(isfinite(img.rgba[i]) && img.rgba[i] >= 0);
    CHECK_MSG(bad == 0, "%d non-finite or negative values", bad);
    prw_image_free(&img);
    free(psf);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"pupil", test_pupil},
        {"spectral", test_spectral},
        {"psf", test_psf},
        {"apply", test_apply},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
