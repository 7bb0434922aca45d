/* basic.c — RMSE, relMSE and PSNR on linear RGB (alpha ignored).
 *
 * MSE    = mean over N pixels and the 3 channels of (t - r)^2
 * relMSE = mean over N pixels and the 3 channels of (t - r)^2 / (r^2 + eps), eps = 0.01, r the
 *          reference (Rousselle et al. 2011 convention)
 * PSNR   = 10 log10(peak^2 / MSE) dB; peak defaults to the reference's largest R/G/B value.
 * Sums are accumulated in double.
 */
#include "prw_metrics.h"

#include <math.h>

double prw_image_max_rgb(const prw_image *img)
{
    size_t n = (size_t)img->width * (size_t)img->height;
    double m = 0.0;
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++)
            if (img->rgba[i * 4 + c] > m) m = img->rgba[i * 4 + c];
    return m;
}

bool prw_metrics_basic(const prw_image *test, const prw_image *ref, double peak, prw_basic_metrics *out,
                       prw_error *e)
{
    if (test->width != ref->width || test->height != ref->height)
        return prw_fail(e, "metrics: basic: test %dx%d differs from reference %dx%d", test->width, test->height,
                        ref->width, ref->height);
    size_t n = (size_t)ref->width * (size_t)ref->height;
    if (n == 0) return prw_fail(e, "metrics: basic: empty image");
    double se = 0.0, rel = 0.0;
    for (size_t i = 0; i < n; i++) {
        for (int c = 0; c < 3; c++) {
            double r = ref->rgba[i * 4 + c], t = test->rgba[i * 4 + c];
            double d2 = (t - r) * (t - r);
            se += d2;
            rel += d2 / (r * r + PRW_RELMSE_EPSILON);
        }
    }
    double count = 3.0 * (double)n;
    out->mse = se / count;
    out->rmse = sqrt(out->mse);
    out->relmse = rel / count;
    out->peak = peak > 0.0 ? peak : prw_image_max_rgb(ref);
    if (!(out->peak > 0.0)) out->psnr = NAN;
    else if (out->mse == 0.0) out->psnr = INFINITY;
    else out->psnr = 10.0 * log10(out->peak * out->peak / out->mse);
    return true;
}
