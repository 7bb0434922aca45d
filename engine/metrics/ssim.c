/* ssim.c — SSIM (Wang, Bovik, Sheikh, Simoncelli 2004, "Image quality assessment: from error
 * visibility to structural similarity"), in the configuration of scikit-image's
 * structural_similarity(gaussian_weights=True, sigma=1.5, use_sample_covariance=False,
 * data_range=1):
 *  - window: Gaussian, sigma 1.5, truncated at radius 5 (scipy's truncate 3.5: int(3.5*1.5 + 0.5)),
 *    weights exp(-k^2 / (2 sigma^2)) normalised to sum 1, applied separably -> 11x11;
 *  - local means mu, population (weighted, not sample-corrected) variances and covariance:
 *    var = E[x^2] - mu^2, cov = E[xy] - mu_x mu_y;
 *  - C1 = (K1 L)^2, C2 = (K2 L)^2 with K1 = 0.01, K2 = 0.03 (the paper's values), L = 1;
 *  - SSIM = (2 mu_x mu_y + C1)(2 cov + C2) / ((mu_x^2 + mu_y^2 + C1)(var_x + var_y + C2));
 *  - no downsampling; the mean is over the windows that lie inside the image (centres
 *    [5, w-6] x [5, h-6]), which is what skimage's crop of (win_size - 1) / 2 = 5 pixels takes.
 * Computed in double.  For colour, the input is the luma of the metric-tone-mapped image:
 * Y' = 0.2126 R' + 0.7152 G' + 0.0722 B' on the sRGB-encoded values (Rec.709 luma coefficients).
 */
#include "prw_metrics.h"

#include <math.h>
#include <stdlib.h>

void prw_luma709(const prw_image *enc, float *out)
{
    size_t n = (size_t)enc->width * (size_t)enc->height;
    for (size_t i = 0; i < n; i++) {
        const float *p = enc->rgba + i * 4;
        out[i] = (float)(0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]);
    }
}

bool prw_ssim_gray(const float *test, const float *ref, int w, int h, double *mean, float *map, prw_error *e)
{
    const int r = PRW_SSIM_RADIUS, taps = 2 * PRW_SSIM_RADIUS + 1;
    if (w < taps || h < taps)
        return prw_fail(e, "ssim: image size: %dx%d is smaller than the %dx%d window", w, h, taps, taps);
    double g[2 * PRW_SSIM_RADIUS + 1], gs = 0.0;
    for (int k = -r; k <= r; k++) gs += g[k + r] = exp(-0.5 * (double)(k * k) / (PRW_SSIM_SIGMA * PRW_SSIM_SIGMA));
    for (int k = 0; k < taps; k++) g[k] /= gs;

    const int wv = w - 2 * r, hv = h - 2 * r;
    /* horizontal pass: 5 moments for every row, at the valid columns */
    double *hm = prw_malloc((size_t)h * (size_t)wv * 5 * sizeof(double));
    for (int y = 0; y < h; y++) {
        const float *x0 = test + (size_t)y * (size_t)w, *y0 = ref + (size_t)y * (size_t)w;
        for (int cx = 0; cx < wv; cx++) {
            double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
            for (int k = 0; k < taps; k++) {
                double a = x0[cx + k], b = y0[cx + k], wk = g[k];
                sx += wk * a;
                sy += wk * b;
                sxx += wk * a * a;
                syy += wk * b * b;
                sxy += wk * a * b;
            }
            double *o = hm + ((size_t)y * (size_t)wv + (size_t)cx) * 5;
            o[0] = sx, o[1] = sy, o[2] = sxx, o[3] = syy, o[4] = sxy;
        }
    }
    const double c1 = (PRW_SSIM_K1 * 1.0) * (PRW_SSIM_K1 * 1.0), c2 = (PRW_SSIM_K2 * 1.0) * (PRW_SSIM_K2 * 1.0);
    double total = 0.0;
    for (int cy = 0; cy < hv; cy++) {
        for (int cx = 0; cx < wv; cx++) {
            double m[5] = {0, 0, 0, 0, 0};
            for (int k = 0; k < taps; k++) {
                const double *p = hm + ((size_t)(cy + k) * (size_t)wv + (size_t)cx) * 5;
                for (int j = 0; j < 5; j++) m[j] += g[k] * p[j];
            }
            double mx = m[0], my = m[1];
            double vx = m[2] - mx * mx, vy = m[3] - my * my, cxy = m[4] - mx * my;
            double s = ((2.0 * mx * my + c1) * (2.0 * cxy + c2)) / ((mx * mx + my * my + c1) * (vx + vy + c2));
            total += s;
            if (map) map[(size_t)cy * (size_t)wv + (size_t)cx] = (float)s;
        }
    }
    free(hm);
    *mean = total / ((double)wv * (double)hv);
    return true;
}

bool prw_ssim_encoded(const prw_image *test_enc, const prw_image *ref_enc, double *mean, prw_error *e)
{
    if (test_enc->width != ref_enc->width || test_enc->height != ref_enc->height)
        return prw_fail(e, "ssim: size: test %dx%d differs from reference %dx%d", test_enc->width,
                        test_enc->height, ref_enc->width, ref_enc->height);
    size_t n = (size_t)ref_enc->width * (size_t)ref_enc->height;
    float *a = prw_malloc(n * sizeof(float)), *b = prw_malloc(n * sizeof(float));
    prw_luma709(test_enc, a);
    prw_luma709(ref_enc, b);
    bool ok = prw_ssim_gray(a, b, ref_enc->width, ref_enc->height, mean, NULL, e);
    free(a);
    free(b);
    return ok;
}
