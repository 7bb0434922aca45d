/* test_image — prw_image: EXR and PNG files. */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <png.h>

#include "exr_gen.h"
#include "prw_image.h"
#include "prw_test.h"

#define tmp_path prw_test_path

static bool file_exists(const char *p)
{
    struct stat st;
    return stat(p, &st) == 0;
}

static bool write_bytes(const char *path, const void *d, size_t n)
{
    FILE *f = fopen(path, "wb");
    if (!f) return false;
    bool ok = fwrite(d, 1, n, f) == n;
    return (fclose(f) == 0) && ok;
}

/* Number of entries in the scratch dir whose name contains ".tmp-". */
static int count_tmp_files(void)
{
    DIR *d = opendir(prw_test_tmpdir());
    int n = 0;
    if (!d) return -1;
    for (struct dirent *de; (de = readdir(d));)
        if (strstr(de->d_name, ".tmp-")) n++;
    closedir(d);
    return n;
}

static uint64_t rng = 0x9E3779B97F4A7C15ull;
static uint32_t rnd(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return (uint32_t)(rng >> 11);
}

/* --------------------------------------------------------------------------------------------- */

static void test_exr_roundtrip(void)
{
    prw_error e = {{0}};
    prw_image img;
    CHECK_OK(prw_image_alloc(&img, 37, 23, &e), &e);
    static const float special[] = {0.0f, -0.0f, 1e-45f /* denormal */, 1.17549435e-38f, -3.0e38f, 3.4028235e38f,
                                    1e-30f, -1e-30f, 65504.0f, 1.0f / 3.0f, -7.25f, 1e20f};
    size_t n = (size_t)img.width * img.height * 4;
    for (size_t i = 0; i < n; i++) {
        if (i < PRW_ARRAY_LEN(special)) {
            img.rgba[i] = special[i];
        } else {
            /* random finite float of any magnitude and sign */
            uint32_t u;
            do u = (uint32_t)rnd() ^ ((uint32_t)rnd() << 21);
            while (((u >> 23) & 0xff) == 0xff);
            memcpy(&img.rgba[i], &u, 4);
        }
    }
    prw_kv attrs[] = {{"prw:spp", "64"}, {"prw:note", "hello, world: \"quoted\" é"}, {"owner", "prw test"}};
    const char *path = tmp_path("roundtrip.exr");
    CHECK_OK(prw_exr_write(path, &img, attrs, 3, &e), &e);
    prw_image back;
    CHECK_OK(prw_exr_read(path, NULL, &back, &e), &e);
    CHECK(back.width == 37 && back.height == 23);
    CHECK_MSG(memcmp(back.rgba, img.rgba, n * sizeof(float)) == 0, "pixels differ after round trip");
    for (int i = 0; i < 3; i++) {
        char v[256];
        CHECK_MSG(prw_exr_read_attr(path, attrs[i].key, v, sizeof v, &e), "%s: %s", attrs[i].key, e.msg);
        CHECK_MSG(strcmp(v, attrs[i].value) == 0, "%s = '%s'", attrs[i].key, v);
    }
    char v[4];
    CHECK(!prw_exr_read_attr(path, "prw:absent", v, sizeof v, &e) && e.msg[0] == '\0');
    CHECK(!prw_exr_read_attr(path, "prw:note", v, sizeof v, &e) && strstr(e.msg, path)); /* too long for v */
    CHECK(!prw_exr_read_attr(path, "dataWindow", v, sizeof v, &e) && strstr(e.msg, path)); /* not a string */

    /* the memory reader gives the same image */
    char *bytes = NULL;
    size_t size = 0;
    CHECK_OK(prw_read_file(path, &bytes, &size, &e), &e);
    prw_image mem;
    CHECK_OK(prw_exr_read_memory(bytes, size, "mem.exr", NULL, &mem, &e), &e);
    CHECK(mem.width == 37 && mem.height == 23 && memcmp(mem.rgba, img.rgba, n * sizeof(float)) == 0);
    prw_image_free(&mem);
    prw_exr_read_opts small = {.max_pixels = 100};
    CHECK(!prw_exr_read_memory(bytes, size, "mem.exr", &small, &mem, &e) && strstr(e.msg, "limit of 100 pixels"));
    CHECK(!prw_exr_read_memory(bytes, 100, "cut.exr", NULL, &mem, &e) && strstr(e.msg, "cut.exr") && !mem.rgba);
    free(bytes);
    prw_image_free(&mem);
    prw_image_free(&back);
    prw_image_free(&img);
    prw_image_free(&img); /* double free is safe */
}

static const float half_values[] = {0.0f, 1.0f, -2.0f, 0.5f, 65504.0f, -65504.0f, 5.9604645e-08f /* 2^-24 */,
                                    6.1035156e-05f /* smallest normal */, 0.333251953125f, 1025.0f, -0.0999755859375f,
                                    3.140625f};
#define NHALF ((int)PRW_ARRAY_LEN(half_values))

static float half_value(int x, int y, char ch, void *u)
{
    (void)u;
    return half_values[(x * 7 + y * 3 + (int)ch) % NHALF];
}

static bool gen_file(const exr_gen_opts *o, exr_gen_value_fn fn, void *ud, const char *path)
{
    uint8_t *d = NULL;
    size_t n = 0;
    char err[512];
    if (!exr_gen_write(o, fn, ud, &d, &n, err, sizeof err)) {
        fprintf(stderr, "exr_gen_write(%s): %s\n", path, err);
        return false;
    }
    bool ok = write_bytes(path, d, n);
    free(d);
    return ok;
}

static void test_exr_half(void)
{
    for (int comp = 0; comp < 2; comp++) {
        exr_gen_opts o = {.width = 9, .height = 5, .type = EXR_PIXEL_HALF, .channels = "RGBA",
                          .compression = comp ? EXR_COMPRESSION_PIZ : EXR_COMPRESSION_NONE};
        const char *path = tmp_path("half.exr");
        CHECK(gen_file(&o, half_value, NULL, path));
        prw_error e = {{0}};
        prw_image img;
        CHECK_OK(prw_exr_read(path, NULL, &img, &e), &e);
        CHECK(img.width == 9 && img.height == 5);
        int bad = 0;
        for (int y = 0; y < 5; y++)
            for (int x = 0; x < 9; x++)
                for (int c = 0; c < 4; c++)
                    if (img.rgba[(y * 9 + x) * 4 + c] != half_value(x, y, "RGBA"[c], NULL)) bad++;
        CHECK_MSG(bad == 0, "%d half samples differ (compression %d)", bad, comp);
        prw_image_free(&img);
    }
}

static float uint_value(int x, int y, char ch, void *u)
{
    (void)u;
    if (x == 2 && y == 1) return 4294967040.0f; /* 0xFFFFFF00: largest float below 2^32 */
    return (float)(x * 1000 + y * 10 + (ch == 'R' ? 1 : ch == 'G' ? 2 : 3));
}

static void test_exr_uint_no_alpha(void)
{
    exr_gen_opts o = {.width = 6, .height = 4, .type = EXR_PIXEL_UINT, .channels = "RGB", .compression = EXR_COMPRESSION_ZIPS};
    const char *path = tmp_path("uint.exr");
    CHECK(gen_file(&o, uint_value, NULL, path));
    prw_error e = {{0}};
    prw_image img;
    CHECK_OK(prw_exr_read(path, NULL, &img, &e), &e);
    int bad = 0;
    for (int y = 0; y < 4; y++)
        for (int x = 0; x < 6; x++) {
            const float *p = img.rgba + (y * 6 + x) * 4;
            for (int c = 0; c < 3; c++)
                if (p[c] != uint_value(x, y, "RGB"[c], NULL)) bad++;
            if (p[3] != 1.0f) bad++;
        }
    CHECK_MSG(bad == 0, "%d uint samples differ", bad);
    prw_image_free(&img);
}

static float coord_value(int x, int y, char ch, void *u)
{
    (void)u;
    return (float)(x * 100 + y) + (ch == 'R' ? 0.25f : ch == 'G' ? 0.5f : ch == 'B' ? 0.75f : ch == 'Y' ? 0.125f : 0.0f);
}

static void test_exr_tiled_offset(void)
{
    /* tiled, partial edge tiles, negative data window origin, RLE; then scanline with offset */
    for (int tiled = 1; tiled >= 0; tiled--) {
        exr_gen_opts o = {.width = 21, .height = 13, .min_x = -5, .min_y = -3, .type = EXR_PIXEL_FLOAT,
                          .channels = "RGBA", .tiled = tiled, .tile_w = 8, .tile_h = 4,
                          .compression = tiled ? EXR_COMPRESSION_RLE : EXR_COMPRESSION_ZIP};
        const char *path = tmp_path("offset.exr");
        CHECK(gen_file(&o, coord_value, NULL, path));
        prw_error e = {{0}};
        prw_image img;
        CHECK_OK(prw_exr_read(path, NULL, &img, &e), &e);
        CHECK(img.width == 21 && img.height == 13);
        int bad = 0;
        for (int y = 0; y < 13; y++)
            for (int x = 0; x < 21; x++)
                for (int c = 0; c < 4; c++)
                    if (img.rgba[(y * 21 + x) * 4 + c] != coord_value(x, y, "RGBA"[c], NULL)) bad++;
        CHECK_MSG(bad == 0, "%d samples differ (tiled %d)", bad, tiled);
        prw_image_free(&img);
    }
}

static void test_exr_grey(void)
{
    exr_gen_opts o = {.width = 5, .height = 3, .type = EXR_PIXEL_HALF, .channels = "Y", .compression = EXR_COMPRESSION_NONE};
    const char *path = tmp_path("grey.exr");
    CHECK(gen_file(&o, half_value, NULL, path));
    prw_error e = {{0}};
    prw_image img;
    CHECK_OK(prw_exr_read(path, NULL, &img, &e), &e);
    int bad = 0;
    for (int y = 0; y < 3; y++)
        for (int x = 0; x < 5; x++) {
            const float *p = img.rgba + (y * 5 + x) * 4;
            float yv = half_value(x, y, 'Y', NULL);
            if (p[0] != yv || p[1] != yv || p[2] != yv || p[3] != 1.0f) bad++;
        }
    CHECK_MSG(bad == 0, "%d grey pixels differ", bad);
    prw_image_free(&img);

    /* no usable channels: clear message naming what was found */
    exr_gen_opts z = {.width = 2, .height = 2, .type = EXR_PIXEL_FLOAT, .channels = "Z", .compression = EXR_COMPRESSION_NONE};
    path = tmp_path("depth.exr");
    CHECK(gen_file(&z, half_value, NULL, path));
    CHECK(!prw_exr_read(path, NULL, &img, &e));
    CHECK_MSG(strstr(e.msg, path) && strstr(e.msg, "found: Z"), "%s", e.msg);
}

typedef struct rgb {
    float c[3];
} rgb;

static float rgb_value(int x, int y, char ch, void *u)
{
    (void)y;
    const rgb *cols = u;
    return ch == 'A' ? 1.0f : cols[x].c[ch == 'R' ? 0 : ch == 'G' ? 1 : 2];
}

static void test_exr_chromaticities(void)
{
    /* Rec.2020 / D65 -> Rec.709: published matrix (ITU-R BT.2087, 4 decimals) */
    static const double m2087[3][3] = {{1.6605, -0.5876, -0.0728}, {-0.1246, 1.1329, -0.0083}, {-0.0182, -0.1006, 1.1187}};
    rgb cols[5] = {{{1, 0, 0}}, {{0, 1, 0}}, {{0, 0, 1}}, {{0.5f, 0.25f, 0.125f}}, {{1, 1, 1}}};
    exr_attr_chromaticities_t rec2020 = {0.708f, 0.292f, 0.170f, 0.797f, 0.131f, 0.046f, 0.3127f, 0.3290f};
    exr_gen_opts o = {.width = 5, .height = 1, .type = EXR_PIXEL_FLOAT, .channels = "RGBA",
                      .compression = EXR_COMPRESSION_NONE, .chroma = &rec2020};
    const char *path = tmp_path("rec2020.exr");
    CHECK(gen_file(&o, rgb_value, cols, path));
    prw_error e = {{0}};
    prw_image img;
    CHECK_OK(prw_exr_read(path, NULL, &img, &e), &e);
    for (int x = 0; x < 5; x++)
        for (int k = 0; k < 3; k++) {
            double want = m2087[k][0] * cols[x].c[0] + m2087[k][1] * cols[x].c[1] + m2087[k][2] * cols[x].c[2];
            CHECK_NEAR(img.rgba[x * 4 + k], want, 2e-4);
        }
    CHECK_NEAR(img.rgba[4 * 4 + 0], 1.0, 1e-5); /* same white: white stays white */
    CHECK_NEAR(img.rgba[4 * 4 + 1], 1.0, 1e-5);
    CHECK_NEAR(img.rgba[4 * 4 + 2], 1.0, 1e-5);
    prw_image_free(&img);

    /* ACES AP0 (blue y < 0, white ~D60): Bradford-adapted; white must map to white, and the
     * matrix must agree with the commonly published AP0 -> linear sRGB (Bradford) to ~1e-3. */
    static const double ap0[3][3] = {{2.52169, -1.13413, -0.38756}, {-0.27648, 1.37272, -0.09624}, {-0.01538, -0.15298, 1.16835}};
    exr_attr_chromaticities_t aces = {0.7347f, 0.2653f, 0.0f, 1.0f, 0.0001f, -0.0770f, 0.32168f, 0.33767f};
    o.chroma = &aces;
    path = tmp_path("aces.exr");
    CHECK(gen_file(&o, rgb_value, cols, path));
    CHECK_OK(prw_exr_read(path, NULL, &img, &e), &e);
    for (int x = 0; x < 4; x++)
        for (int k = 0; k < 3; k++) {
            double want = ap0[k][0] * cols[x].c[0] + ap0[k][1] * cols[x].c[1] + ap0[k][2] * cols[x].c[2];
            CHECK_NEAR(img.rgba[x * 4 + k], want, 1e-3);
        }
    for (int k = 0; k < 3; k++) CHECK_NEAR(img.rgba[4 * 4 + k], 1.0, 1e-5);
    prw_image_free(&img);

    /* degenerate chromaticities are an error, not garbage */
    exr_attr_chromaticities_t bad = {0.3f, 0.3f, 0.3f, 0.3f, 0.3f, 0.3f, 0.3127f, 0.3290f};
    o.chroma = &bad;
    path = tmp_path("badchroma.exr");
    CHECK(gen_file(&o, rgb_value, cols, path));
    CHECK(!prw_exr_read(path, NULL, &img, &e));
    CHECK_MSG(strstr(e.msg, path) && strstr(e.msg, "chromaticities"), "%s", e.msg);
}

static void test_exr_truncated(void)
{
    prw_error e = {{0}};
    prw_image img;
    CHECK_OK(prw_image_alloc(&img, 37, 23, &e), &e);
    for (size_t i = 0; i < (size_t)37 * 23 * 4; i++) img.rgba[i] = (float)(rnd() % 1000) * 0.01f;
    const char *full = tmp_path("full.exr");
    CHECK_OK(prw_exr_write(full, &img, NULL, 0, &e), &e);
    prw_image_free(&img);
    char *bytes = NULL;
    size_t size = 0;
    CHECK_OK(prw_read_file(full, &bytes, &size, &e), &e);
    const char *cut = tmp_path("cut.exr");
    int tried = 0, wrong = 0;
    for (size_t len = 0; len < size; len += (len < 400 ? 7 : 97)) {
        CHECK(write_bytes(cut, bytes, len));
        tried++;
        e.msg[0] = '\0';
        bool ok = prw_exr_read(cut, NULL, &img, &e);
        if (ok || !strstr(e.msg, cut) || img.rgba) {
            wrong++;
            fprintf(stderr, "cut at %zu of %zu: ok=%d msg=%s\n", len, size, ok, e.msg);
            prw_image_free(&img);
        }
    }
    for (size_t len = size - 8; len < size; len++) { /* last chunk incomplete */
        CHECK(write_bytes(cut, bytes, len));
        tried++;
        if (prw_exr_read(cut, NULL, &img, &e) || !strstr(e.msg, cut)) {
            wrong++;
            fprintf(stderr, "cut at %zu of %zu: msg=%s\n", len, size, e.msg);
            prw_image_free(&img);
        }
    }
    CHECK_MSG(wrong == 0, "%d of %d truncated files not rejected properly", wrong, tried);
    free(bytes);
}

static void test_exr_bad_files(void)
{
    prw_error e = {{0}};
    prw_image img;
    const char *txt = tmp_path("not_exr.exr");
    const char *text = "this is not an EXR file, just some text\n";
    CHECK(write_bytes(txt, text, strlen(text)));
    CHECK(!prw_exr_read(txt, NULL, &img, &e));
    CHECK_MSG(strstr(e.msg, txt) && strstr(e.msg, "exr_start_read"), "%s", e.msg);
    printf("  not an EXR: %s\n", e.msg);
    const char *missing = tmp_path("missing.exr");
    CHECK(!prw_exr_read(missing, NULL, &img, &e));
    CHECK_MSG(strstr(e.msg, missing) && strstr(e.msg, "No such file"), "%s", e.msg);
    CHECK(!prw_exr_read_attr(missing, "x", (char[8]){0}, 8, &e) && strstr(e.msg, "No such file"));
    CHECK(!prw_exr_read(prw_test_tmpdir(), NULL, &img, &e) && strstr(e.msg, "not a regular file"));

    /* absurd data window: patch a valid file's dataWindow to 2^20 x 2^20 */
    prw_image small;
    CHECK_OK(prw_image_alloc(&small, 4, 4, &e), &e);
    const char *p = tmp_path("huge.exr");
    CHECK_OK(prw_exr_write(p, &small, NULL, 0, &e), &e);
    prw_image_free(&small);
    char *bytes = NULL;
    size_t size = 0;
    CHECK_OK(prw_read_file(p, &bytes, &size, &e), &e);
    const char key[] = "dataWindow\0box2i";
    char *at = NULL;
    for (size_t i = 0; i + sizeof key + 4 + 16 < size; i++)
        if (memcmp(bytes + i, key, sizeof key) == 0) at = bytes + i + sizeof key + 4;
    CHECK(at != NULL);
    if (at) {
        int32_t box[4] = {0, 0, (1 << 20) - 1, (1 << 20) - 1};
        memcpy(at, box, 16);
        CHECK(write_bytes(p, bytes, size));
        CHECK(!prw_exr_read(p, NULL, &img, &e));
        CHECK_MSG(strstr(e.msg, p) && strstr(e.msg, "exceeds"), "%s", e.msg);
        int32_t box2[4] = {5, 0, 2, 3}; /* max < min */
        memcpy(at, box2, 16);
        CHECK(write_bytes(p, bytes, size));
        CHECK(!prw_exr_read(p, NULL, &img, &e));
        CHECK_MSG(strstr(e.msg, p), "%s", e.msg);
    }
    free(bytes);
}

static void test_image_alloc_limits(void)
{
    prw_error e = {{0}};
    prw_image img;
    CHECK(!prw_image_alloc(&img, 0, 5, &e) && strstr(e.msg, "invalid size") && !img.rgba);
    CHECK(!prw_image_alloc(&img, 5, -1, &e) && strstr(e.msg, "invalid size"));
    CHECK(!prw_image_alloc(&img, 1 << 15, 1 << 14, &e) && strstr(e.msg, "exceeds"));
    CHECK_OK(prw_image_alloc(&img, 3, 2, &e), &e);
    CHECK(img.rgba[0] == 0.0f && img.rgba[23] == 0.0f);
    prw_image_free(&img);
    prw_image bad = {0, 0, NULL};
    CHECK(!prw_exr_write(tmp_path("empty.exr"), &bad, NULL, 0, &e));
}

static void test_exr_atomic(void)
{
    prw_error e = {{0}};
    prw_image img;
    CHECK_OK(prw_image_alloc(&img, 8, 8, &e), &e);
    int tmp_before = count_tmp_files();

    /* missing directory: fails, creates nothing */
    const char *nodir = tmp_path("no/such/dir/out.exr");
    CHECK(!prw_exr_write(nodir, &img, NULL, 0, &e));
    CHECK_MSG(strstr(e.msg, nodir) != NULL, "%s", e.msg);
    CHECK(!file_exists(nodir));

    /* failure mid-way (an attribute clashing with a required one) keeps the old file intact */
    const char *path = tmp_path("atomic.exr");
    img.rgba[0] = 42.0f;
    CHECK_OK(prw_exr_write(path, &img, NULL, 0, &e), &e);
    img.rgba[0] = 7.0f;
    prw_kv clash[] = {{"prw:ok", "1"}, {"channels", "not a chlist"}};
    CHECK(!prw_exr_write(path, &img, clash, 2, &e));
    CHECK_MSG(strstr(e.msg, path) && strstr(e.msg, "channels"), "%s", e.msg);
    printf("  clash: %s\n", e.msg);
    prw_image back;
    CHECK_OK(prw_exr_read(path, NULL, &back, &e), &e);
    CHECK(back.rgba[0] == 42.0f);
    prw_image_free(&back);
    /* and a successful write replaces it */
    CHECK_OK(prw_exr_write(path, &img, NULL, 0, &e), &e);
    CHECK_OK(prw_exr_read(path, NULL, &back, &e), &e);
    CHECK(back.rgba[0] == 7.0f);
    prw_image_free(&back);
    CHECK(count_tmp_files() == tmp_before && tmp_before == 0);
    prw_image_free(&img);
}

static void test_exr_nonfinite(void)
{
    prw_error e = {{0}};
    prw_image img;
    CHECK_OK(prw_image_alloc(&img, 10, 9, &e), &e);
    img.rgba[(7 * 10 + 5) * 4 + 1] = NAN;
    const char *path = tmp_path("nan.exr");
    CHECK_OK(prw_exr_write(path, &img, NULL, 0, &e), &e);
    prw_exr_read_opts strict = {.reject_nonfinite = true};
    prw_image back;
    CHECK(!prw_exr_read(path, &strict, &back, &e) && !back.rgba);
    CHECK_MSG(strstr(e.msg, path) && strstr(e.msg, "(5, 7)") && strstr(e.msg, "NaN") && strstr(e.msg, "channel G"), "%s",
              e.msg);
    prw_exr_read_opts lax = {.reject_nonfinite = false};
    CHECK_OK(prw_exr_read(path, &lax, &back, &e), &e);
    CHECK(isnan(back.rgba[(7 * 10 + 5) * 4 + 1]));
    prw_image_free(&back);

    img.rgba[(7 * 10 + 5) * 4 + 1] = 0.0f;
    img.rgba[(8 * 10 + 9) * 4 + 3] = -INFINITY;
    CHECK_OK(prw_exr_write(path, &img, NULL, 0, &e), &e);
    CHECK(!prw_exr_read(path, &strict, &back, &e));
    CHECK_MSG(strstr(e.msg, "(9, 8)") && strstr(e.msg, "Inf"), "%s", e.msg);
    prw_image_free(&img);
}

/* --------------------------------------------------------------------------------------------- */

static void test_png_roundtrip(void)
{
    const int w = 13, h = 7;
    for (int ch = 1; ch <= 4; ch++) {
        uint8_t *px = malloc((size_t)w * h * ch);
        for (int i = 0; i < w * h * ch; i++) px[i] = (uint8_t)rnd();
        char name[32];
        snprintf(name, sizeof name, "rt%d.png", ch);
        const char *path = tmp_path(name);
        prw_error e = {{0}};
        CHECK_OK(prw_png_write8(path, w, h, ch, px, &e), &e);
        int rw = 0, rh = 0;
        uint8_t *rgba = NULL;
        CHECK_OK(prw_png_read8(path, &rw, &rh, &rgba, &e), &e);
        CHECK(rw == w && rh == h);
        int bad = 0;
        for (int i = 0; i < w * h; i++) {
            const uint8_t *s = px + i * ch, *d = rgba + i * 4;
            uint8_t want[4];
            if (ch <= 2) want[0] = want[1] = want[2] = s[0];
            else memcpy(want, s, 3);
            want[3] = ch == 2 ? s[1] : ch == 4 ? s[3] : 255;
            if (memcmp(want, d, 4) != 0) bad++;
        }
        CHECK_MSG(bad == 0, "%d pixels differ with %d channels", bad, ch);
        free(rgba);
        free(px);
    }
    prw_error e = {{0}};
    uint8_t px[4] = {0};
    CHECK(!prw_png_write8(tmp_path("bad.png"), 1, 1, 5, px, &e) && strstr(e.msg, "channels"));
    CHECK(!prw_png_write8(tmp_path("no/dir/x.png"), 1, 1, 1, px, &e) && strstr(e.msg, "no/dir/x.png"));
    CHECK(!file_exists(tmp_path("no/dir/x.png")));
    CHECK(count_tmp_files() == 0);
}

static void test_png_truncated(void)
{
    const int w = 31, h = 17;
    uint8_t px[31 * 17 * 3];
    for (size_t i = 0; i < sizeof px; i++) px[i] = (uint8_t)rnd();
    prw_error e = {{0}};
    const char *full = tmp_path("full.png");
    CHECK_OK(prw_png_write8(full, w, h, 3, px, &e), &e);
    char *bytes = NULL;
    size_t size = 0;
    CHECK_OK(prw_read_file(full, &bytes, &size, &e), &e);
    const char *cut = tmp_path("cut.png");
    int wrong = 0, tried = 0;
    for (size_t len = 0; len < size; len += 23) {
        CHECK(write_bytes(cut, bytes, len));
        int rw, rh;
        uint8_t *rgba = NULL;
        tried++;
        if (prw_png_read8(cut, &rw, &rh, &rgba, &e) || !strstr(e.msg, cut) || rgba) {
            wrong++;
            fprintf(stderr, "png cut at %zu: %s\n", len, e.msg);
            free(rgba);
        }
    }
    CHECK_MSG(wrong == 0, "%d of %d truncated PNGs not rejected", wrong, tried);
    /* a flipped byte in the image data: CRC error */
    bytes[size / 2] ^= 0x55;
    CHECK(write_bytes(cut, bytes, size));
    int rw, rh;
    uint8_t *rgba = NULL;
    CHECK(!prw_png_read8(cut, &rw, &rh, &rgba, &e) && strstr(e.msg, cut));
    printf("  corrupt png: %s\n", e.msg);
    CHECK(!prw_png_read8(tmp_path("missing.png"), &rw, &rh, &rgba, &e) && strstr(e.msg, "missing.png"));
    const char *txt = tmp_path("text.png");
    CHECK(write_bytes(txt, "hello", 5));
    CHECK(!prw_png_read8(txt, &rw, &rh, &rgba, &e) && strstr(e.msg, "not a PNG"));
    free(bytes);
}

/* PNGs prw_png_write8 never writes, made with libpng directly: 4-bit palette with tRNS, 16-bit RGB. */
static bool write_png_raw(const char *path, int w, int h, int depth, int ctype, const uint8_t *rows, size_t stride,
                          const png_color *pal, int npal, const uint8_t *trns, int ntrns)
{
    FILE *f = fopen(path, "wb");
    if (!f) return false;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        fclose(f);
        return false;
    }
    png_init_io(png, f);
    png_set_IHDR(png, info, (png_uint_32)w, (png_uint_32)h, depth, ctype, PNG_INTERLACE_ADAM7, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    if (pal) png_set_PLTE(png, info, pal, npal);
    if (trns) png_set_tRNS(png, info, trns, ntrns, NULL);
    png_write_info(png, info);
    if (depth == 16) png_set_swap(png); /* rows hold host-order uint16 */
    png_set_interlace_handling(png);
    png_bytep ptrs[16];
    for (int y = 0; y < h && y < 16; y++) ptrs[y] = (png_bytep)(rows + (size_t)y * stride);
    png_write_image(png, ptrs);
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    return fclose(f) == 0;
}

static void test_png_palette_16bit(void)
{
    prw_error e = {{0}};
    const int w = 5, h = 3;
    png_color pal[3] = {{255, 0, 0}, {0, 255, 0}, {10, 20, 30}};
    uint8_t trns[2] = {128, 0}; /* entry 0 half transparent, entry 1 transparent, entry 2 opaque */
    uint8_t rows[3][3];         /* 4-bit indices, 5 px per row -> 3 bytes */
    int idx[3][5];
    for (int y = 0; y < h; y++) {
        memset(rows[y], 0, 3);
        for (int x = 0; x < w; x++) {
            idx[y][x] = (x + y) % 3;
            rows[y][x / 2] |= (uint8_t)(idx[y][x] << (x % 2 ? 0 : 4));
        }
    }
    const char *path = tmp_path("pal.png");
    CHECK(write_png_raw(path, w, h, 4, PNG_COLOR_TYPE_PALETTE, &rows[0][0], 3, pal, 3, trns, 2));
    int rw, rh;
    uint8_t *rgba = NULL;
    CHECK_OK(prw_png_read8(path, &rw, &rh, &rgba, &e), &e);
    CHECK(rw == w && rh == h);
    int bad = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            const uint8_t *p = rgba + (y * w + x) * 4;
            int i = idx[y][x];
            uint8_t a = i < 2 ? trns[i] : 255;
            if (p[0] != pal[i].red || p[1] != pal[i].green || p[2] != pal[i].blue || p[3] != a) bad++;
        }
    CHECK_MSG(bad == 0, "%d palette pixels differ", bad);
    free(rgba);

    uint16_t rgb16[3][5 * 3];
    for (int y = 0; y < h; y++)
        for (int i = 0; i < w * 3; i++) rgb16[y][i] = (uint16_t)(i * 4369 + y * 257); /* k*257 maps exactly to k */
    path = tmp_path("rgb16.png");
    CHECK(write_png_raw(path, w, h, 16, PNG_COLOR_TYPE_RGB, (const uint8_t *)&rgb16[0][0], sizeof rgb16[0], NULL, 0, NULL, 0));
    CHECK_OK(prw_png_read8(path, &rw, &rh, &rgba, &e), &e);
    bad = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            for (int c = 0; c < 3; c++)
                if (rgba[(y * w + x) * 4 + c] != rgb16[y][x * 3 + c] / 257) bad++;
            if (rgba[(y * w + x) * 4 + 3] != 255) bad++;
        }
    CHECK_MSG(bad == 0, "%d 16-bit samples differ", bad);
    free(rgba);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"exr_roundtrip", test_exr_roundtrip},
        {"exr_half", test_exr_half},
        {"exr_uint_no_alpha", test_exr_uint_no_alpha},
        {"exr_tiled_offset", test_exr_tiled_offset},
        {"exr_grey", test_exr_grey},
        {"exr_chromaticities", test_exr_chromaticities},
        {"exr_truncated", test_exr_truncated},
        {"exr_bad_files", test_exr_bad_files},
        {"image_alloc_limits", test_image_alloc_limits},
        {"exr_atomic", test_exr_atomic},
        {"exr_nonfinite", test_exr_nonfinite},
        {"png_roundtrip", test_png_roundtrip},
        {"png_truncated", test_png_truncated},
        {"png_palette_16bit", test_png_palette_16bit},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
