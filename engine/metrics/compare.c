/* compare.c — what `prw compare` computes: loading and checking the inputs, every metric of a
 * test image against a reference, and the verdicts against the reference's own noise. */
#define _POSIX_C_SOURCE 200809L
#include "prw_metrics.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

bool prw_compare_load(const char *path, prw_image *out, prw_error *e)
{
    prw_exr_read_opts o = {.reject_nonfinite = true};
    return prw_exr_read(path, &o, out, e);
}

bool prw_compare_sniff(const char *path, prw_compare_kind *kind, prw_error *e)
{
    static const unsigned char exr[4] = {0x76, 0x2f, 0x31, 0x01};
    static const unsigned char png[8] = {0x89, 'P', 'N', 'G', 0x0d, 0x0a, 0x1a, 0x0a};
    FILE *f = fopen(path, "rb");
    if (!f) return prw_fail(e, "%s: cannot open: %s", path, strerror(errno));
    unsigned char head[8] = {0};
    size_t n = fread(head, 1, sizeof head, f);
    fclose(f);
    if (n >= 4 && memcmp(head, exr, 4) == 0) *kind = PRW_COMPARE_EXR;
    else if (n >= 8 && memcmp(head, png, 8) == 0) *kind = PRW_COMPARE_PNG;
    else return prw_fail(e, "%s: not an OpenEXR or PNG file (unknown signature)", path);
    return true;
}

bool prw_compare_load_png(const char *path, prw_image *out, prw_error *e)
{
    int w = 0, h = 0;
    uint8_t *px = NULL;
    out->width = out->height = 0;
    out->rgba = NULL;
    if (!prw_png_read8(path, &w, &h, &px, e)) return false;
    bool ok = prw_image_alloc(out, w, h, e);
    if (ok) {
        size_t n = (size_t)w * (size_t)h;
        for (size_t i = 0; i < n; i++) {
            for (int c = 0; c < 3; c++) out->rgba[4 * i + c] = (float)px[4 * i + c] / 255.0f;
            out->rgba[4 * i + 3] = 1.0f;
        }
    } else {
        prw_fail_wrap(e, "%s", path);
    }
    free(px);
    return ok;
}

/* linear display values of encoded ones (alpha kept) */
static bool decode_srgb(const prw_image *enc, prw_image *lin, prw_error *e)
{
    if (!prw_image_alloc(lin, enc->width, enc->height, e)) return false;
    size_t n = (size_t)enc->width * (size_t)enc->height * 4;
    for (size_t i = 0; i < n; i++) lin->rgba[i] = (i % 4 == 3) ? enc->rgba[i] : prw_srgb_eotf(enc->rgba[i]);
    return true;
}

bool prw_compare_images_ldr(const prw_image *test_enc, const prw_image *ref_enc, const prw_compare_opts *opts,
                            prw_compare_metrics *out, float *ldr_map, prw_error *e)
{
    double ppd = opts->ppd > 0.0 ? opts->ppd : PRW_FLIP_DEFAULT_PPD;
    if (!prw_compare_check_sizes(test_enc, ref_enc, "test", "reference", e)) return false;
    size_t n = (size_t)ref_enc->width * (size_t)ref_enc->height;
    prw_image tl = {0}, rl = {0};
    float *map = ldr_map ? ldr_map : prw_malloc(n * sizeof(float));
    bool ok = decode_srgb(test_enc, &tl, e) && decode_srgb(ref_enc, &rl, e) &&
              prw_metrics_basic(&tl, &rl, opts->peak > 0 ? opts->peak : 1.0, &out->basic, e) &&
              prw_ssim_encoded(test_enc, ref_enc, &out->ssim, e) && prw_flip_ldr_linear(&tl, &rl, ppd, map, e);
    if (ok) prw_flip_pool(map, n, &out->ldr_flip);
    out->hdr_flip = (prw_flip_stats){NAN, NAN, NAN, NAN, NAN, NAN};
    prw_image_free(&tl);
    prw_image_free(&rl);
    if (!ldr_map) free(map);
    return ok;
}

double prw_compare_derive_ev100(const prw_image *ref, double *log_avg)
{
    size_t n = (size_t)ref->width * (size_t)ref->height;
    double sum = 0;
    for (size_t i = 0; i < n; i++) {
        const float *p = ref->rgba + 4 * i;
        double y = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
        if (!(y > 0) || !isfinite(y)) y = 0;
        sum += log(PRW_COMPARE_EV_DELTA + y);
    }
    double la = n ? exp(sum / (double)n) : PRW_COMPARE_EV_DELTA;
    if (log_avg) *log_avg = la;
    double ev = log2(la / (1.2 * PRW_COMPARE_EV_KEY));
    ev = round(ev * 1e4) / 1e4;
    return ev < -20 ? -20 : ev > 40 ? 40 : ev;
}

bool prw_compare_read_ev100(const char *path, double *ev100, prw_error *e)
{
    char buf[64];
    if (!prw_exr_read_attr(path, "prw:ev100", buf, sizeof buf, e)) return false;
    char *end;
    errno = 0;
    double v = strtod(buf, &end);
    if (errno || end == buf || *end != '\0' || !isfinite(v) || v < -40.0 || v > 60.0) {
        for (char *p = buf; *p; p++) /* quoted from the file: one clean line */
            if ((unsigned char)*p < 0x20 || *p == 0x7f) *p = '?';
        return prw_fail(e, "%s: attribute prw:ev100: '%s' is not a number in -40..60", path, buf);
    }
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
