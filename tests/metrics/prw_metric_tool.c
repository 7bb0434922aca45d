/* prw_metric_tool — a test helper that prints one metric for two images, for oracles in other
 * languages (ssim_oracle.py).
 *   prw_metric_tool ssim A B [EV100]     A, B: PNG (taken as sRGB-encoded, value / 255) or EXR
 *                                        (linear; metric tone map at EV100, required)
 *   prw_metric_tool ssim-raw W H A B     A, B: raw float32 (native order) single-channel images
 *   prw_metric_tool gen OUT.exr W H SEED NOISE [EV100|-] [nan|inf]
 *                                        a synthetic scene (smooth colour pattern, ~10..190 cd/m^2)
 *                                        with multiplicative Gaussian noise; EV100 is stored as the
 *                                        prw:ev100 attribute; nan/inf poisons one pixel
 * ssim prints the mean SSIM with 12 decimals.  Exit 1 on errors (one line on stderr). */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_metrics.h"
#include "testutil.h"

static bool ends_with(const char *s, const char *suf)
{
    size_t n = strlen(s), m = strlen(suf);
    return n >= m && strcmp(s + n - m, suf) == 0;
}

static bool load_encoded(const char *path, const char *ev, prw_image *out, prw_error *e)
{
    if (ends_with(path, ".png")) {
        int w, h;
        uint8_t *p;
        if (!prw_png_read8(path, &w, &h, &p, e)) return false;
        if (!prw_image_alloc(out, w, h, e)) {
            free(p);
            return false;
        }
        for (size_t i = 0; i < (size_t)w * h * 4; i++) out->rgba[i] = p[i] / 255.0f;
        free(p);
        return true;
    }
    if (!ev) return prw_fail(e, "%s: an EXR needs EV100 for the metric tone map", path);
    prw_image lin;
    if (!prw_compare_load(path, &lin, e)) return false;
    bool ok = prw_metric_tonemap(&lin, atof(ev), out, e);
    prw_image_free(&lin);
    return ok;
}

static bool read_raw(const char *path, size_t n, float **out, prw_error *e)
{
    char *data;
    size_t size;
    if (!prw_read_file(path, &data, &size, e)) return false;
    if (size != n * sizeof(float)) {
        free(data);
        return prw_fail(e, "%s: size: %zu bytes, expected %zu", path, size, n * sizeof(float));
    }
    *out = prw_malloc(size);
    memcpy(*out, data, size);
    free(data);
    return true;
}

static int gen(int argc, char **argv)
{
    prw_error e = {{0}};
    int w = atoi(argv[3]), h = atoi(argv[4]);
    trng r = {(uint64_t)strtoull(argv[5], NULL, 10) * 2654435761ULL + 1};
    double noise = atof(argv[6]);
    prw_image img;
    if (!prw_image_alloc(&img, w, h, &e)) {
        fprintf(stderr, "prw_metric_tool: error: %s\n", e.msg);
        return 1;
    }
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            double base = 100.0 * (1.0 + 0.9 * sin(0.21 * x) * cos(0.13 * y));
            double tint[3] = {1.0, 0.8 + 0.2 * sin(0.05 * y), 0.5 + 0.4 * cos(0.07 * x)};
            for (int c = 0; c < 3; c++) px(&img, x, y)[c] = (float)(base * tint[c] * (1.0 + noise * trng_normal(&r)));
            px(&img, x, y)[3] = 1.0f;
        }
    if (argc > 8) px(&img, w / 2, h / 3)[1] = strcmp(argv[8], "nan") == 0 ? NAN : INFINITY;
    prw_kv kv = {"prw:ev100", argc > 7 ? argv[7] : "-"};
    bool ok = prw_exr_write(argv[2], &img, &kv, strcmp(kv.value, "-") != 0 ? 1 : 0, &e);
    prw_image_free(&img);
    if (!ok) {
        fprintf(stderr, "prw_metric_tool: error: %s\n", e.msg);
        return 1;
    }
    return 0;
}

int main(int argc, char **argv)
{
    prw_error e = {{0}};
    double s = 0;
    if (argc >= 7 && strcmp(argv[1], "gen") == 0) return gen(argc, argv);
    if (argc >= 4 && strcmp(argv[1], "ssim") == 0) {
        prw_image a = {0}, b = {0};
        bool ok = load_encoded(argv[2], argc > 4 ? argv[4] : NULL, &a, &e) &&
                  load_encoded(argv[3], argc > 4 ? argv[4] : NULL, &b, &e) && prw_ssim_encoded(&a, &b, &s, &e);
        prw_image_free(&a);
        prw_image_free(&b);
        if (!ok) {
            fprintf(stderr, "prw_metric_tool: error: %s\n", e.msg);
            return 1;
        }
    } else if (argc == 6 && strcmp(argv[1], "ssim-raw") == 0) {
        int w = atoi(argv[2]), h = atoi(argv[3]);
        float *a = NULL, *b = NULL;
        bool ok = w > 0 && h > 0 && read_raw(argv[4], (size_t)w * h, &a, &e) &&
                  read_raw(argv[5], (size_t)w * h, &b, &e) && prw_ssim_gray(a, b, w, h, &s, NULL, &e);
        free(a);
        free(b);
        if (!ok) {
            fprintf(stderr, "prw_metric_tool: error: %s\n", e.msg[0] ? e.msg : "bad size");
            return 1;
        }
    } else {
        fprintf(stderr, "usage: prw_metric_tool ssim A B [EV100] | ssim-raw W H A.f32 B.f32 | gen OUT.exr W H SEED NOISE [EV100|-] [nan|inf]\n");
        return 2;
    }
    printf("%.12f\n", s);
    return 0;
}
