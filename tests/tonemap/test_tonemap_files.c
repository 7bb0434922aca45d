/* Output files of display-aware tone mapping (issue 6): HDR10 PNG and display-referred EXR (unit).
 *  - hdr10_png:   prw_tm_write_hdr10_png on a PQ signal: the file's chunks, walked here byte by byte,
 *                 are IHDR (16-bit RGB), then cICP = 09 10 00 01 before the first IDAT, each with a CRC
 *                 that matches an independent CRC-32 (table built here); the 16-bit samples (decoded
 *                 with libpng) are round(65535 V); the sidecar <file>.json holds MaxCLL / MaxFALL equal
 *                 to an independent PQ decode (ST 2084 constants written out here).
 *  - hdr10_bad:   a non-PQ display is refused with a message naming the file; no file is left.
 *  - display_exr: the display-referred EXR of hdr10-1000 carries the Rec.2020 chromaticities; read
 *                 back (the reader converts to Rec.709), its luminance equals the displayed luminance
 *                 of the signal through the display model within 1e-4 relative.
 */
#define _POSIX_C_SOURCE 200809L
#include <cjson/cJSON.h>
#include <math.h>
#include <png.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "prw_test.h"
#include "tm_scenes.h"

static uint32_t crc32_ref(const uint8_t *p, size_t n)
{
    static uint32_t table[256];
    if (!table[1])
        for (uint32_t i = 0; i < 256; i++) {
            uint32_t c = i;
            for (int k = 0; k < 8; k++) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
            table[i] = c;
        }
    uint32_t c = 0xFFFFFFFFu;
    for (size_t i = 0; i < n; i++) c = table[(c ^ p[i]) & 0xFF] ^ (c >> 8);
    return c ^ 0xFFFFFFFFu;
}

static uint32_t be32(const uint8_t *p) { return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3]; }

static double pq_eotf_ref(double v)
{
    const double m1 = 2610.0 / 16384.0, m2 = 2523.0 / 32.0, c1 = 3424.0 / 4096.0, c2 = 2413.0 / 128.0,
                 c3 = 2392.0 / 128.0;
    double p = pow(v, 1.0 / m2);
    return 10000.0 * pow(fmax(p - c1, 0.0) / (c2 - c3 * p), 1.0 / m1);
}

/* The PQ signal of a 4-decade field on hdr10-1000 (C reference, adaptive operator). */
static void make_signal(prw_image *sig, prw_display *d)
{
    prw_error e;
    prw_image hdr;
    double exposure = tm_scene_field(&hdr, 48, 40, 4.0, 5);
    prw_display_builtin("hdr10-1000", d);
    prw_tonemap_settings s = {.op = PRW_TM_ADAPTIVE};
    prw_tm_params p;
    prw_tm_prepare(&s, d, exposure, &p);
    CHECK(prw_tm_apply(&p, NULL, &hdr, sig, NULL, &e));
    prw_image_free(&hdr);
}

static void test_hdr10_png(void)
{
    prw_display d;
    prw_image sig = {0};
    prw_error e;
    make_signal(&sig, &d);
    const char *path = prw_test_path("hdr10.png");
    CHECK_OK(prw_tm_write_hdr10_png(path, &d, &sig, &e), &e);
    char *data = NULL;
    size_t size = 0;
    CHECK_OK(prw_read_file(path, &data, &size, &e), &e);
    const uint8_t *b = (const uint8_t *)data;
    static const uint8_t sigbytes[8] = {137, 80, 78, 71, 13, 10, 26, 10};
    CHECK(size > 8 && memcmp(b, sigbytes, 8) == 0);
    size_t pos = 8;
    int idx = 0, cicp_at = -1, idat_at = -1, bad_crc = 0;
    while (pos + 12 <= size) {
        uint32_t n = be32(b + pos);
        if (pos + 12 + n > size) break;
        const uint8_t *type = b + pos + 4, *body = b + pos + 8;
        if (crc32_ref(type, 4 + (size_t)n) != be32(body + n)) bad_crc++;
        if (idx == 0) {
            CHECK(memcmp(type, "IHDR", 4) == 0 && n == 13);
            CHECK(be32(body) == 48 && be32(body + 4) == 40 && body[8] == 16 && body[9] == 2); /* 16-bit RGB */
        }
        if (memcmp(type, "cICP", 4) == 0) {
            cicp_at = idx;
            CHECK(n == 4 && body[0] == 9 && body[1] == 16 && body[2] == 0 && body[3] == 1);
        }
        if (memcmp(type, "IDAT", 4) == 0 && idat_at < 0) idat_at = idx;
        pos += 12 + n;
        idx++;
    }
    CHECK_MSG(bad_crc == 0, "%d chunks with a wrong CRC", bad_crc);
    CHECK_MSG(cicp_at > 0 && idat_at > cicp_at, "cICP chunk %d, first IDAT %d", cicp_at, idat_at);
    CHECK(pos == size);
    free(data);

    /* samples: decoded with libpng (16-bit, big endian in the file) */
    FILE *f = fopen(path, "rb");
    CHECK(f != NULL);
    if (f) {
        png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
        png_infop info = png_create_info_struct(png);
        png_init_io(png, f);
        png_read_png(png, info, PNG_TRANSFORM_IDENTITY, NULL);
        png_bytepp rows = png_get_rows(png, info);
        int worst = 0;
        for (int y = 0; y < 40; y++)
            for (int x = 0; x < 48; x++)
                for (int c = 0; c < 3; c++) {
                    int got = rows[y][6 * x + 2 * c] << 8 | rows[y][6 * x + 2 * c + 1];
                    int want = (int)lrint(65535.0 * sig.rgba[4 * (y * 48 + x) + c]);
                    worst = PRW_MAX(worst, abs(got - want));
                }
        CHECK_MSG(worst == 0, "16-bit samples differ by up to %d", worst);
        png_destroy_read_struct(&png, &info, NULL);
        fclose(f);
    }

    /* sidecar */
    char jpath[512];
    snprintf(jpath, sizeof jpath, "%s.json", path);
    CHECK_OK(prw_read_file(jpath, &data, &size, &e), &e);
    cJSON *j = cJSON_ParseWithLength(data, size);
    CHECK(j != NULL);
    double cll = 0, fall = 0;
    for (int k = 0; k < 48 * 40; k++) {
        double m = 0;
        for (int c = 0; c < 3; c++) m = fmax(m, pq_eotf_ref(sig.rgba[4 * k + c]));
        cll = fmax(cll, m);
        fall += m / (48 * 40);
    }
    const cJSON *a = cJSON_GetObjectItemCaseSensitive(j, "MaxCLL"), *bf = cJSON_GetObjectItemCaseSensitive(j, "MaxFALL");
    const cJSON *ae = cJSON_GetObjectItemCaseSensitive(j, "MaxCLL_exact"),
                *be = cJSON_GetObjectItemCaseSensitive(j, "MaxFALL_exact");
    CHECK(cJSON_IsNumber(a) && cJSON_IsNumber(bf) && cJSON_IsNumber(ae) && cJSON_IsNumber(be));
    if (cJSON_IsNumber(a) && cJSON_IsNumber(bf) && cJSON_IsNumber(ae) && cJSON_IsNumber(be)) {
        printf("MaxCLL %.4f (file %g), MaxFALL %.4f (file %g)\n", cll, ae->valuedouble, fall, be->valuedouble);
        CHECK(a->valuedouble == (double)lround(cll) && bf->valuedouble == (double)lround(fall));
        CHECK_NEAR(ae->valuedouble, cll, 1e-3 * cll + 1e-3);
        CHECK_NEAR(be->valuedouble, fall, 1e-3 * fall + 1e-3);
        CHECK(cll <= d.peak + 1e-6 && cll > 0);
    }
    cJSON_Delete(j);
    free(data);
    prw_image_free(&sig);
}

static void test_hdr10_bad(void)
{
    prw_display d;
    prw_image sig = {0};
    prw_error e = {{0}};
    make_signal(&sig, &d);
    prw_display_builtin("default-lcd", &d);
    const char *path = prw_test_path("not-hdr10.png");
    unlink(path);
    CHECK(!prw_tm_write_hdr10_png(path, &d, &sig, &e));
    CHECK_MSG(strstr(e.msg, path) && strstr(e.msg, "PQ"), "message: %s", e.msg);
    CHECK(access(path, F_OK) != 0);
    prw_image_free(&sig);
}

static void test_display_exr(void)
{
    prw_display d;
    prw_image sig = {0}, light = {0}, back = {0};
    prw_error e;
    make_signal(&sig, &d);
    float chroma[8];
    prw_tm_display_chroma(&d, chroma);
    const char *path = prw_test_path("display.exr");
    CHECK_OK(prw_tm_display_light(&d, &sig, &light, &e), &e);
    prw_kv attrs[] = {{"prw:units", "cd/m^2 displayed"}};
    CHECK_OK(prw_exr_write_chroma(path, &light, chroma, attrs, 1, &e), &e);
    float got[8];
    CHECK_OK(prw_exr_read_chroma(path, got, &e), &e);
    const float rec2020[8] = {0.708f, 0.292f, 0.170f, 0.797f, 0.131f, 0.046f, 0.3127f, 0.3290f};
    for (int i = 0; i < 8; i++) CHECK(got[i] == rec2020[i]);
    CHECK_OK(prw_exr_read(path, NULL, &back, &e), &e);
    double worst = 0;
    for (int k = 0; k < 48 * 40; k++) {
        double y = 0.2126 * back.rgba[4 * k] + 0.7152 * back.rgba[4 * k + 1] + 0.0722 * back.rgba[4 * k + 2];
        double want = tm_displayed_lum(&d, sig.rgba + 4 * k);
        worst = fmax(worst, fabs(y - want) / want);
    }
    printf("display EXR: luminance (read back as Rec.709) vs displayed luminance: max rel. diff %.3g\n", worst);
    CHECK(worst <= 1e-4);
    prw_image_free(&sig);
    prw_image_free(&light);
    prw_image_free(&back);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"hdr10_png", test_hdr10_png},
        {"hdr10_bad", test_hdr10_bad},
        {"display_exr", test_display_exr},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
