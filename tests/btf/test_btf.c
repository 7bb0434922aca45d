/* The BTF container (materials/btf/prw_btf.h):
 *  - dirs_ubo81: the Bonn set: 81 directions, rings of 1/6/12/18/20/24 at 0..75 deg, whole degrees,
 *                no two alike, phi steps equal within a ring;
 *  - from_ubo:   the closed-form tensor written as DFMF, FMF and BDI decodes to the same container values;
 *  - image_set:  6561 small PNGs named as the UBO2003 sets are (half of the views in tvTTT_pvPPP/
 *                subdirectories), each encoding its own view, light and pixel: every value lands where
 *                the layout says; a missing image and a wrong-sized image are named. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "btf_samples.h"
#include "prw_btf.h"
#include "prw_image.h"
#include "prw_math.h"
#include "prw_test.h"

static void test_dirs(void)
{
    float d[2 * PRW_BTF_UBO81];
    prw_btf_dirs_ubo81(d);
    const int ring_count[6] = {1, 6, 12, 18, 20, 24};
    int seen[6] = {0};
    for (uint32_t i = 0; i < PRW_BTF_UBO81; i++) {
        double t = d[2 * i] * 180.0 / PRW_PI, p = d[2 * i + 1] * 180.0 / PRW_PI;
        int ring = (int)lround(t / 15.0);
        CHECK(ring >= 0 && ring < 6 && fabs(t - 15.0 * ring) < 1e-4);
        CHECK_MSG(fabs(p - lround(p)) < 1e-3, "direction %u: phi %.6f is not whole degrees", i, p);
        if (ring >= 0 && ring < 6) {
            CHECK_NEAR(p, 360.0 / ring_count[ring] * seen[ring], 1e-3);
            seen[ring]++;
        }
        double a[3];
        prw_btf_dir_vector(d[2 * i], d[2 * i + 1], a);
        CHECK_NEAR(a[0] * a[0] + a[1] * a[1] + a[2] * a[2], 1.0, 1e-6);
        for (uint32_t j = 0; j < i; j++) {
            double b[3];
            prw_btf_dir_vector(d[2 * j], d[2 * j + 1], b);
            CHECK_MSG(a[0] * b[0] + a[1] * b[1] + a[2] * b[2] < 0.999, "directions %u and %u coincide", i, j);
        }
    }
    for (int r = 0; r < 6; r++) CHECK_MSG(seen[r] == ring_count[r], "ring %d has %d directions", r, seen[r]);
}

static void test_from_ubo(void)
{
    prw_error e;
    const prw_btf_ubo_format f[3] = {PRW_BTF_UBO_DFMF, PRW_BTF_UBO_FMF, PRW_BTF_UBO_BDI};
    for (int i = 0; i < 3; i++) {
        prw_btf_ubo u;
        prw_btf b;
        btf_sample_tensor_file(f[i], 3, 2, 4, 3, &u);
        CHECK_OK(prw_btf_from_ubo(&u, &b, &e), &e);
        int bad = 0;
        for (uint32_t v = 0; v < 3; v++)
            for (uint32_t l = 0; l < 2; l++)
                for (uint32_t y = 0; y < 3; y++)
                    for (uint32_t x = 0; x < 4; x++)
                        for (uint32_t c = 0; c < 3; c++)
                            bad += b.rgb[prw_btf_at(&b, v, l, x, y) + c] != (float)btf_sample_tensor(c, v, l, x, y);
        CHECK_MSG(bad == 0, "format %d: %d values differ", (int)f[i], bad);
        CHECK(memcmp(b.view_dirs, u.view_dirs, sizeof(float) * 6) == 0);
        prw_btf_free(&b);
        prw_btf_ubo_free(&u);
    }
}

/* the test's image loader: 8-bit PNG values / 255 (no transfer function: the placement is what is checked) */
static bool load_png(void *user, const char *path, uint32_t *w, uint32_t *h, float **rgb, prw_error *e)
{
    (void)user;
    int iw, ih;
    uint8_t *px;
    if (!prw_png_read8(path, &iw, &ih, &px, e)) return false;
    *w = (uint32_t)iw, *h = (uint32_t)ih;
    *rgb = malloc(sizeof(float) * 3 * (size_t)iw * ih);
    for (int i = 0; i < iw * ih; i++)
        for (int c = 0; c < 3; c++) (*rgb)[3 * i + c] = px[4 * i + c] / 255.0f;
    free(px);
    return true;
}

static void image_name(const char *dir, const float *d, uint32_t v, uint32_t l, bool sub, char *buf, size_t cap)
{
    int tv = (int)lround(d[2 * v] * 180 / PRW_PI), pv = (int)lround(d[2 * v + 1] * 180 / PRW_PI);
    int tl = (int)lround(d[2 * l] * 180 / PRW_PI), pl = (int)lround(d[2 * l + 1] * 180 / PRW_PI);
    if (sub) snprintf(buf, cap, "%s/tv%03d_pv%03d/tl%03d_pl%03d_tv%03d_pv%03d.png", dir, tv, pv, tl, pl, tv, pv);
    else snprintf(buf, cap, "%s/tl%03d_pl%03d_tv%03d_pv%03d.png", dir, tl, pl, tv, pv);
}

static void test_image_set(void)
{
    prw_error e;
    char dir[1024];
    snprintf(dir, sizeof dir, "%s/ubo_set", prw_test_tmpdir());
    mkdir(dir, 0755);
    float d[2 * PRW_BTF_UBO81];
    prw_btf_dirs_ubo81(d);
    char path[2048];
    for (uint32_t v = 0; v < PRW_BTF_UBO81; v++) {
        bool sub = v % 2 == 1;
        if (sub) {
            char sd[1200];
            snprintf(sd, sizeof sd, "%s/tv%03d_pv%03d", dir, (int)lround(d[2 * v] * 180 / PRW_PI),
                     (int)lround(d[2 * v + 1] * 180 / PRW_PI));
            mkdir(sd, 0755);
        }
        for (uint32_t l = 0; l < PRW_BTF_UBO81; l++) {
            uint8_t px[2 * 1 * 4];
            for (int x = 0; x < 2; x++) {
                px[4 * x] = (uint8_t)v, px[4 * x + 1] = (uint8_t)l, px[4 * x + 2] = (uint8_t)(100 + x), px[4 * x + 3] = 255;
            }
            image_name(dir, d, v, l, sub, path, sizeof path);
            CHECK_OK(prw_png_write8(path, 2, 1, 4, px, &e), &e);
        }
    }
    static const char *exts[2] = {"exr", "png"};
    prw_btf b;
    CHECK_OK(prw_btf_read_image_set(dir, exts, 2, load_png, NULL, &b, &e), &e);
    int bad = 0;
    for (uint32_t v = 0; v < PRW_BTF_UBO81; v++)
        for (uint32_t l = 0; l < PRW_BTF_UBO81; l++)
            for (uint32_t x = 0; x < 2; x++) {
                const float *p = b.rgb + prw_btf_at(&b, v, l, x, 0);
                bad += p[0] != v / 255.0f || p[1] != l / 255.0f || p[2] != (100 + x) / 255.0f;
            }
    CHECK_MSG(bad == 0 && b.width == 2 && b.height == 1, "%d values misplaced", bad);
    prw_btf_free(&b);

    /* a missing image is named */
    image_name(dir, d, 5, 7, true, path, sizeof path);
    CHECK(unlink(path) == 0);
    CHECK(!prw_btf_read_image_set(dir, exts, 2, load_png, NULL, &b, &e) && strstr(e.msg, "no tl030_pl000_tv015_pv240.(exr|png)") &&
          strstr(e.msg, "tv015_pv240/"));
    printf("refused: %s\n", e.msg);
    /* ... and one of another size */
    uint8_t px[12] = {0};
    CHECK_OK(prw_png_write8(path, 3, 1, 4, px, &e), &e);
    CHECK(!prw_btf_read_image_set(dir, exts, 2, load_png, NULL, &b, &e) && strstr(e.msg, "3 x 1 pixels"));
    printf("refused: %s\n", e.msg);
    CHECK(b.rgb == NULL);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"dirs_ubo81", test_dirs},
        {"from_ubo", test_from_ubo},
        {"image_set", test_image_set},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
