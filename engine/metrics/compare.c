/* compare.c — what `prw compare` computes: loading and checking the inputs, every metric of a
 * test image against a reference, and the verdicts against the reference's own noise. */
#define _POSIX_C_SOURCE 200809L
#include "prw_metrics.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>

bool prw_compare_load(const char *path, prw_image *out, prw_error *e)
{
    prw_exr_read_opts o = {.reject_nonfinite = true};
    return prw_exr_read(path, &o, out, e);
}

bool prw_compare_read_ev100(const char *path, double *ev100, prw_error *e)
{
    char buf[64];
    if (!prw_exr_read_attr(path, "prw:ev100", buf, sizeof buf, e)) return false;
    char *end;
    errno = 0;
    double v = strtod(buf, &end);
    if (errno || end == buf || *end != '\0' || !isfinite(v) || v < -40.0 || v > 60.0)
        return prw_fail(e, "%s: attribute prw:ev100: '%s' is not a number in -40..60", path, buf);
    *ev100 = v;
    return true;
}

bool prw_compare_check_sizes(const prw_image *test, const prw_image *ref, const char *test_name,
                             const char *ref_name, prw_error *e)
{
    if (test->width != ref->width || test->height != ref->height)
        return prw_fail(e, "%s: size: %dx%d differs from %s %dx%d", test_name, test->width, test->height, ref_name,
                        ref->width, ref->height);
    return true;
}

bool prw_compare_images(const prw_image *test, const prw_image *ref, const prw_compare_opts *opts,
                        prw_compare_metrics *out, float *hdr_map, prw_flip_exposures *exposures, prw_error *e)
{
    double ppd = opts->ppd > 0.0 ? opts->ppd : PRW_FLIP_DEFAULT_PPD;
    if (!prw_compare_check_sizes(test, ref, "test", "reference", e)) return false;
    if (!prw_metrics_basic(test, ref, opts->peak, &out->basic, e)) return false;
    size_t n = (size_t)ref->width * (size_t)ref->height;
    prw_image te = {0}, re = {0};
    float *map = prw_malloc(n * sizeof(float));
    bool ok = prw_metric_tonemap(test, opts->ev100, &te, e) && prw_metric_tonemap(ref, opts->ev100, &re, e) &&
              prw_ssim_encoded(&te, &re, &out->ssim, e) && prw_flip_ldr_encoded(&te, &re, ppd, map, e);
    if (ok) {
        prw_flip_pool(map, n, &out->ldr_flip);
        float *hm = hdr_map ? hdr_map : map;
        ok = prw_flip_hdr(test, ref, ppd, hm, exposures, e);
        if (ok) prw_flip_pool(hm, n, &out->hdr_flip);
    }
    prw_image_free(&te);
    prw_image_free(&re);
    free(map);
    return ok;
}

static bool below(double err, double noise) { return err < 2.0 * noise; }

void prw_compare_verdict(const prw_compare_metrics *err, const prw_compare_metrics *noise,
                         prw_compare_verdicts *out)
{
    out->rmse = below(err->basic.rmse, noise->basic.rmse);
    out->relmse = below(err->basic.relmse, noise->basic.relmse);
    out->psnr = out->rmse; /* same peak: PSNR_err > PSNR_noise - 20 log10 2  <=>  RMSE_err < 2 RMSE_noise */
    out->ssim = below(1.0 - err->ssim, 1.0 - noise->ssim);
    out->ldr_flip = below(err->ldr_flip.mean, noise->ldr_flip.mean);
    out->hdr_flip = below(err->hdr_flip.mean, noise->hdr_flip.mean);
}
