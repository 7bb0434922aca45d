/* The heat map (heatmap.c) and what `prw compare` relies on (compare.c): loading with NaN/Inf
 * rejection, the prw:ev100 attribute, size checks, all metrics at once, reference-noise verdicts. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "prw_metrics.h"
#include "prw_test.h"
#include "testutil.h"

static char *tmp_path(const char *name)
{
    static char buf[8][512];
    static int k;
    char *p = buf[k++ % 8];
    snprintf(p, 512, "%s/%s", prw_test_tmpdir(), name);
    return p;
}

static bool exists(const char *p)
{
    struct stat st;
    return stat(p, &st) == 0;
}

static double lum8(const uint8_t *p) { return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]; }

static void t_heatmap(void)
{
    prw_error e = {{0}};
    uint8_t lo[3], hi[3], mid[3];
    prw_magma(0.0, lo);
    prw_magma(1.0, hi);
    prw_magma(0.5, mid);
    CHECK(lo[0] < 5 && lo[1] < 5 && lo[2] < 10);                   /* near black */
    CHECK(hi[0] > 240 && hi[1] > 240 && hi[2] > 170 && hi[2] < 210); /* pale yellow */
    CHECK(mid[0] > mid[1] && mid[0] > mid[2]);                      /* magenta-red middle */
    uint8_t prev[3];
    prw_magma(0.0, prev);
    for (int i = 1; i <= 100; i++) { /* lightness rises monotonically */
        uint8_t c[3];
        prw_magma(i / 100.0, c);
        CHECK_MSG(lum8(c) >= lum8(prev) - 0.5, "t = %.2f", i / 100.0);
        memcpy(prev, c, 3);
    }
    prw_magma(-1.0, mid);
    CHECK(memcmp(mid, lo, 3) == 0);
    prw_magma(NAN, mid);
    CHECK(memcmp(mid, lo, 3) == 0);
    prw_magma(7.0, mid);
    CHECK(memcmp(mid, hi, 3) == 0);

    const int w = 20, h = 10;
    float *map = malloc(sizeof(float) * w * h);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) map[y * w + x] = (float)x / (w - 1);
    const char *path = tmp_path("heat.png");
    remove(path);
    CHECK_OK(prw_heatmap_write_png(path, map, w, h, &e), &e);
    int rw, rh;
    uint8_t *pix;
    CHECK_OK(prw_png_read8(path, &rw, &rh, &pix, &e), &e);
    CHECK(rw == w && rh == h);
    CHECK(memcmp(pix, lo, 3) == 0);                  /* (0,0): error 0 */
    CHECK(memcmp(pix + (w - 1) * 4, hi, 3) == 0);    /* (w-1,0): error 1 */
    CHECK(memcmp(pix + ((h - 1) * w) * 4, lo, 3) == 0);
    free(pix);
    /* an unwritable path fails with the path in the message and leaves nothing */
    const char *bad = tmp_path("no-such-dir/heat.png");
    CHECK(!prw_heatmap_write_png(bad, map, w, h, &e));
    CHECK_MSG(strstr(e.msg, "no-such-dir/heat.png") != NULL, "%s", e.msg);
    CHECK(!exists(bad));
    free(map);
}

static void make_image(prw_image *img, int w, int h, uint64_t seed, double noise)
{
    prw_error e;
    prw_image_alloc(img, w, h, &e);
    trng r = {seed};
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            double base = 100.0 * (0.5 + 0.4 * sin(0.2 * x) * cos(0.15 * y));
            float *p = px(img, x, y);
            p[0] = (float)fmax(0.0, base * (1.0 + noise * trng_normal(&r)));
            p[1] = (float)fmax(0.0, 0.8 * base * (1.0 + noise * trng_normal(&r)));
            p[2] = (float)fmax(0.0, 0.5 * base * (1.0 + noise * trng_normal(&r)));
            p[3] = 1.0f;
        }
}

static void t_load_errors(void)
{
    prw_error e = {{0}};
    prw_image img = {0}, got = {0};
    make_image(&img, 16, 12, 1, 0.0);
    /* unreadable */
    const char *missing = tmp_path("missing.exr");
    CHECK(!prw_compare_load(missing, &got, &e));
    CHECK_MSG(strstr(e.msg, "missing.exr") != NULL, "%s", e.msg);
    CHECK(strchr(e.msg, '\n') == NULL);
    /* not an EXR */
    const char *junk = tmp_path("junk.exr");
    CHECK_OK(prw_write_file_atomic(junk, "hello", 5, &e), &e);
    CHECK(!prw_compare_load(junk, &got, &e));
    CHECK_MSG(strstr(e.msg, "junk.exr") != NULL, "%s", e.msg);
    /* NaN and Inf pixels */
    const char *nanp = tmp_path("nan.exr");
    px(&img, 3, 4)[1] = NAN;
    CHECK_OK(prw_exr_write(nanp, &img, NULL, 0, &e), &e);
    CHECK(!prw_compare_load(nanp, &got, &e));
    CHECK_MSG(strstr(e.msg, "nan.exr") && strstr(e.msg, "NaN"), "%s", e.msg);
    px(&img, 3, 4)[1] = INFINITY;
    const char *infp = tmp_path("inf.exr");
    CHECK_OK(prw_exr_write(infp, &img, NULL, 0, &e), &e);
    CHECK(!prw_compare_load(infp, &got, &e));
    CHECK_MSG(strstr(e.msg, "inf.exr") && strstr(e.msg, "Inf"), "%s", e.msg);
    px(&img, 3, 4)[1] = 1.0f;
    /* ev100 attribute: present, absent, malformed */
    const char *with = tmp_path("with_ev.exr"), *without = tmp_path("without_ev.exr"), *badev = tmp_path("bad_ev.exr");
    prw_kv good[] = {{"prw:ev100", "7.2500"}}, bad[] = {{"prw:ev100", "seven"}};
    CHECK_OK(prw_exr_write(with, &img, good, 1, &e), &e);
    CHECK_OK(prw_exr_write(without, &img, NULL, 0, &e), &e);
    CHECK_OK(prw_exr_write(badev, &img, bad, 1, &e), &e);
    double ev = 0;
    CHECK_OK(prw_compare_read_ev100(with, &ev, &e), &e);
    CHECK_NEAR(ev, 7.25, 0.0);
    e.msg[0] = 'x';
    CHECK(!prw_compare_read_ev100(without, &ev, &e));
    CHECK(e.msg[0] == '\0');
    CHECK(!prw_compare_read_ev100(badev, &ev, &e));
    CHECK_MSG(strstr(e.msg, "bad_ev.exr") && strstr(e.msg, "seven"), "%s", e.msg);
    CHECK(!prw_compare_read_ev100(missing, &ev, &e));
    CHECK(e.msg[0] != '\0');
    /* loads fine */
    CHECK_OK(prw_compare_load(with, &got, &e), &e);
    CHECK(got.width == 16 && got.height == 12);
    /* size mismatch names the file and both sizes */
    prw_image other;
    make_image(&other, 16, 13, 2, 0.0);
    CHECK(!prw_compare_check_sizes(&other, &got, "b.exr", "a.exr", &e));
    CHECK_MSG(strstr(e.msg, "b.exr: size: 16x13 differs from a.exr 16x12") != NULL, "%s", e.msg);
    prw_compare_metrics m;
    prw_compare_opts o = {.ev100 = 6.0};
    CHECK(!prw_compare_images(&other, &got, &o, &m, NULL, NULL, &e));
    prw_image_free(&other);
    prw_image_free(&got);
    prw_image_free(&img);
}

static void t_compare_identical_and_noise(void)
{
    prw_error e = {{0}};
    const int w = 64, h = 48;
    prw_image ref, ref2, good, bad;
    make_image(&ref, w, h, 10, 0.05);
    make_image(&ref2, w, h, 11, 0.05); /* same scene, other seed */
    make_image(&good, w, h, 12, 0.06);  /* a little noisier than the reference: below 2x its noise */
    make_image(&bad, w, h, 13, 0.30);   /* much noisier */
    prw_compare_opts o = {.ev100 = log2(100.0 / 1.2)}; /* 100 cd/m^2 -> 1.0 */
    prw_compare_metrics m, noise, mg, mb;
    float *map = malloc(sizeof(float) * w * h);
    prw_flip_exposures x;
    CHECK_OK(prw_compare_images(&ref, &ref, &o, &m, map, &x, &e), &e);
    CHECK(m.basic.rmse == 0.0 && isinf(m.basic.psnr));
    CHECK_NEAR(m.ssim, 1.0, 1e-12);
    CHECK(m.ldr_flip.mean == 0.0 && m.hdr_flip.mean == 0.0 && m.hdr_flip.max == 0.0);
    CHECK(m.ldr_flip.weighted_median == 0.0);
    CHECK_NEAR(m.basic.peak, prw_image_max_rgb(&ref), 0.0);
    CHECK(x.count >= 2 && x.stop >= x.start);
    for (int i = 0; i < w * h; i++) CHECK(map[i] == 0.0f);

    CHECK_OK(prw_compare_images(&ref2, &ref, &o, &noise, NULL, NULL, &e), &e);
    CHECK_OK(prw_compare_images(&good, &ref, &o, &mg, NULL, NULL, &e), &e);
    CHECK_OK(prw_compare_images(&bad, &ref, &o, &mb, map, NULL, &e), &e);
    CHECK(noise.basic.rmse > 0 && noise.ssim < 1.0 && noise.hdr_flip.mean > 0);
    CHECK(mb.basic.rmse > mg.basic.rmse && mb.ssim < mg.ssim && mb.ldr_flip.mean > mg.ldr_flip.mean &&
          mb.hdr_flip.mean > mg.hdr_flip.mean);
    prw_compare_verdicts v;
    prw_compare_verdict(&mg, &noise, &v);
    CHECK(v.rmse && v.relmse && v.psnr && v.ssim && v.ldr_flip && v.hdr_flip);
    prw_compare_verdict(&mb, &noise, &v);
    CHECK(!v.rmse && !v.relmse && !v.psnr && !v.ssim && !v.ldr_flip && !v.hdr_flip);
    /* identical references: zero noise, nothing is below it */
    prw_compare_verdict(&mg, &m, &v);
    CHECK(!v.rmse && !v.ssim && !v.hdr_flip);
    /* stats are consistent */
    CHECK(mb.hdr_flip.min <= mb.hdr_flip.weighted_q1 && mb.hdr_flip.weighted_q1 <= mb.hdr_flip.weighted_median &&
          mb.hdr_flip.weighted_median <= mb.hdr_flip.weighted_q3 && mb.hdr_flip.weighted_q3 <= mb.hdr_flip.max);
    /* explicit PSNR peak */
    o.peak = 1000.0;
    CHECK_OK(prw_compare_images(&good, &ref, &o, &mg, NULL, NULL, &e), &e);
    CHECK_NEAR(mg.basic.peak, 1000.0, 0.0);
    free(map);
    prw_image_free(&ref);
    prw_image_free(&ref2);
    prw_image_free(&good);
    prw_image_free(&bad);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"heatmap", t_heatmap},
        {"load_errors", t_load_errors},
        {"compare_identical_and_noise", t_compare_identical_and_noise},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
