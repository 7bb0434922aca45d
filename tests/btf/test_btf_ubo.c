/* The Bonn BTF binaries (materials/btf/prw_btf_ubo.h), issue "BTF materials" must-show 1:
 *  - halves:     every half converts to float and back to itself; rounding to nearest even at ties;
 *  - roundtrip:  every format and header variant: encode -> read -> every field equal -> encode gives
 *                the same bytes; also through a file (atomic write);
 *  - tensor:     one closed-form tensor written as DFMF, FMF and BDI (three layouts) reads back as the
 *                closed form at every index (so the three layouts agree on what (c, v, l, x, y) means);
 *  - colour:     DFMF colour model 11 (log Y, U/Y, V/Y) of RGB values computed by the standard YUV
 *                forward transform gives the RGB back (the reader's matrix is its inverse);
 *  - truncated:  every prefix of every sample is refused with one line naming the file, no crash;
 *  - corrupt:    named errors for a wrong signature, PVF, the meta size, differing light sets, matrix
 *                shapes, counts beyond the bytes (a 400 x 400 x 151^2 claim in a small file: refused
 *                before allocating), the memory budget, trailing bytes. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "btf_samples.h"
#include "prw_btf_ubo.h"
#include "prw_test.h"

static void test_halves(void)
{
    int bad = 0;
    for (uint32_t h = 0; h < 65536; h++) {
        float f = prw_btf_half_to_float((uint16_t)h);
        uint16_t back = prw_btf_float_to_half(f);
        if (isnan(f) ? !(back & 0x3ff) || (back & 0x7c00) != 0x7c00 : back != h) bad++;
    }
    CHECK_MSG(bad == 0, "%d halves do not convert back", bad);
    CHECK(prw_btf_half_to_float(0x3c00) == 1.0f);
    CHECK(prw_btf_half_to_float(0x0001) == ldexpf(1, -24));
    CHECK(prw_btf_half_to_float(0x7bff) == 65504.0f);
    CHECK(prw_btf_float_to_half(1.0f + ldexpf(1, -11)) == 0x3c00);     /* tie -> even */
    CHECK(prw_btf_float_to_half(1.0f + 3 * ldexpf(1, -11)) == 0x3c02); /* tie -> even (up) */
    CHECK(prw_btf_float_to_half(65519.0f) == 0x7bff);
    CHECK(prw_btf_float_to_half(65520.0f) == 0x7c00);
    CHECK(prw_btf_float_to_half(ldexpf(1, -25)) == 0x0000);              /* tie -> even (0) */
    CHECK(prw_btf_float_to_half(3 * ldexpf(1, -25)) == 0x0002);
    CHECK(prw_btf_float_to_half(-2.0f) == 0xc000);
}

static bool same_factors(const prw_btf_ubo_factors *a, const prw_btf_ubo_factors *b)
{
    if (a->scalar_size != b->scalar_size || a->components != b->components || a->rows != b->rows || a->cols != b->cols)
        return false;
    return memcmp(a->s, b->s, 8 * a->components) == 0 && memcmp(a->u, b->u, 8 * (size_t)a->rows * a->components) == 0 &&
           memcmp(a->sxv, b->sxv, 8 * (size_t)a->cols * a->components) == 0;
}

/* every field of two BTFs */
static bool same(const prw_btf_ubo *a, const prw_btf_ubo *b)
{
#define EQ(f) (memcmp(&a->f, &b->f, sizeof a->f) == 0)
    if (!EQ(format) || !EQ(rotations_flag) || !EQ(fmf_ext) || !EQ(meta_version) || !EQ(measurement_setup) ||
        !EQ(image_sensor) || !EQ(light_source) || !EQ(ppmm) || !EQ(rgb_scale) || !EQ(cosine_flag) || !EQ(xml_len) ||
        !EQ(channels) || !EQ(views) || !EQ(lights) || !EQ(width) || !EQ(height) || !EQ(rotation_count) ||
        !EQ(dfmf_components) || !EQ(color_model) || !EQ(color_mean) || !EQ(color_transform) ||
        !EQ(fmf_header_version) || !EQ(drr) || !EQ(height_map_w) || !EQ(height_map_h) || !EQ(fmf_components0) ||
        !EQ(scan_lines) || !EQ(compression) || !EQ(stored))
        return false;
#undef EQ
    if (a->xml_len && memcmp(a->xml, b->xml, a->xml_len) != 0) return false;
    if (a->meta_version > 3)
        for (uint32_t c = 0; c < a->channels; c++)
            if (a->channel_len[c] != b->channel_len[c] || memcmp(a->channel_names[c], b->channel_names[c], a->channel_len[c]))
                return false;
    if (memcmp(a->view_dirs, b->view_dirs, 8 * (size_t)a->views) || memcmp(a->light_dirs, b->light_dirs, 8 * (size_t)a->lights))
        return false;
    if (a->rotation_count && memcmp(a->rotations, b->rotations, 36 * (size_t)a->rotation_count)) return false;
    if (a->format == PRW_BTF_UBO_DFMF)
        for (uint32_t c = 0; c < a->channels; c++)
            if (!same_factors(&a->factors[c], &b->factors[c])) return false;
    if (a->format == PRW_BTF_UBO_FMF && !same_factors(a->factors, b->factors)) return false;
    uint64_t hm = (uint64_t)a->height_map_w * a->height_map_h;
    if (hm && memcmp(a->height_map, b->height_map, 2 * hm)) return false;
    if (a->format == PRW_BTF_UBO_BDI) {
        uint64_t xy = (uint64_t)a->width * a->height, n = a->stored * a->views * a->lights * a->channels;
        if (memcmp(a->mask, b->mask, xy) || memcmp(a->bdi, b->bdi, 2 * n)) return false;
    }
    return true;
}

static void test_roundtrip(void)
{
    prw_error e;
    for (int k = 0; k < BTF_SAMPLE_KIND_COUNT; k++) {
        prw_btf_ubo a, b;
        btf_sample((btf_sample_kind)k, 3, 4, 5, 3, 42, &a);
        uint8_t *d1 = NULL, *d2 = NULL;
        size_t n1 = 0, n2 = 0;
        bool ok = prw_btf_ubo_encode(&a, &d1, &n1, &e);
        CHECK_MSG(ok, "sample %d: %s", k, e.msg);
        ok = ok && prw_btf_ubo_read_memory(d1, n1, "mem.btf", &b, &e);
        CHECK_MSG(ok, "sample %d: %s", k, e.msg);
        if (ok) {
            CHECK_MSG(same(&a, &b), "sample %d: fields differ after the round trip", k);
            CHECK_OK(prw_btf_ubo_encode(&b, &d2, &n2, &e), &e);
            CHECK_MSG(n1 == n2 && memcmp(d1, d2, n1) == 0, "sample %d: re-encoding changed the bytes", k);
            /* raw values: the same in both (reads the layouts) and finite */
            for (uint32_t c = 0; c < 3; c++)
                CHECK(prw_btf_ubo_raw(&a, c, 2, 3, 4, 2) == prw_btf_ubo_raw(&b, c, 2, 3, 4, 2));
            /* through a file */
            char name[64];
            snprintf(name, sizeof name, "sample%d.btf", k);
            char *path = prw_test_path(name);
            prw_btf_ubo f;
            CHECK_OK(prw_btf_ubo_write(path, &b, &e), &e);
            CHECK_OK(prw_btf_ubo_read(path, &f, &e), &e);
            CHECK_MSG(same(&a, &f), "sample %d: fields differ after the file round trip", k);
            prw_btf_ubo_free(&f);
            prw_btf_ubo_free(&b);
        }
        free(d1);
        free(d2);
        prw_btf_ubo_free(&a);
    }
}

static void test_tensor(void)
{
    prw_error e;
    const prw_btf_ubo_format fmts[3] = {PRW_BTF_UBO_DFMF, PRW_BTF_UBO_FMF, PRW_BTF_UBO_BDI};
    const uint32_t V = 3, L = 4, W = 5, H = 4;
    for (int i = 0; i < 3; i++) {
        prw_btf_ubo a, b;
        btf_sample_tensor_file(fmts[i], V, L, W, H, &a);
        uint8_t *d = NULL;
        size_t n = 0;
        CHECK_OK(prw_btf_ubo_encode(&a, &d, &n, &e), &e);
        bool ok = prw_btf_ubo_read_memory(d, n, "tensor.btf", &b, &e);
        CHECK_MSG(ok, "%s", e.msg);
        int bad = 0;
        for (uint32_t c = 0; ok && c < 3; c++)
            for (uint32_t v = 0; v < V; v++)
                for (uint32_t l = 0; l < L; l++)
                    for (uint32_t y = 0; y < H; y++)
                        for (uint32_t x = 0; x < W; x++)
                            bad += prw_btf_ubo_raw(&b, c, v, l, x, y) != btf_sample_tensor(c, v, l, x, y);
        CHECK_MSG(bad == 0, "format %d: %d values differ from the closed form", (int)fmts[i], bad);
        printf("format %d: %zu bytes, %d of %u values differ from the closed form\n", (int)fmts[i], n, bad, 3 * V * L * W * H);
        if (ok) prw_btf_ubo_free(&b);
        free(d);
        prw_btf_ubo_free(&a);
    }
}

static void test_colour(void)
{
    prw_error e;
    prw_btf_ubo a;
    btf_sample_tensor_file(PRW_BTF_UBO_DFMF, 1, 1, 2, 1, &a);
    a.color_model = 11;
    a.color_model = 11;
    const double rgb[2][3] = {{0.25, 0.5, 0.125}, {0.8, 0.1, 0.4}};
    /* one component per channel: U = 1 (the one view-light pair), SxV = the channel's value per texel */
    for (int c = 0; c < 3; c++) {
        prw_btf_ubo_factors *f = &a.factors[c];
        f->components = 1, f->scalar_size = 8;
        f->s[0] = 1, f->u[0] = 1;
        for (int t = 0; t < 2; t++) {
            /* the standard (analogue) YUV forward transform, then log Y, U / Y, V / Y with the format's epsilon */
            double R = rgb[t][0], G = rgb[t][1], B = rgb[t][2];
            double Y = 0.299 * R + 0.587 * G + 0.114 * B, U = 0.492 * (B - Y), V = 0.877 * (R - Y);
            double ch[3] = {log(Y + 1e-5), U / (Y + 1e-5), V / (Y + 1e-5)};
            f->sxv[t] = ch[c];
        }
    }
    uint8_t *d = NULL;
    size_t n = 0;
    prw_btf_ubo b;
    CHECK_OK(prw_btf_ubo_encode(&a, &d, &n, &e), &e);
    CHECK_OK(prw_btf_ubo_read_memory(d, n, "colour.btf", &b, &e), &e);
    for (int t = 0; t < 2; t++) {
        double out[3];
        CHECK_OK(prw_btf_ubo_rgb(&b, 0, 0, (uint32_t)t, 0, out, &e), &e);
        for (int c = 0; c < 3; c++) CHECK_NEAR(out[c], rgb[t][c], 2e-4); /* the matrices are 5-6 digit inverses */
        printf("colour model 11: rgb (%.3f %.3f %.3f) -> (%.6f %.6f %.6f)\n", rgb[t][0], rgb[t][1], rgb[t][2], out[0],
               out[1], out[2]);
    }
    b.color_model = 7;
    double out[3];
    CHECK(!prw_btf_ubo_rgb(&b, 0, 0, 0, 0, out, &e) && strstr(e.msg, "colour model 7"));
    prw_btf_ubo_free(&b);
    free(d);
    prw_btf_ubo_free(&a);
}

static void test_truncated(void)
{
    prw_error e;
    int fails = 0, wrong = 0;
    for (int k = 0; k < BTF_SAMPLE_KIND_COUNT; k++) {
        prw_btf_ubo a, b;
        btf_sample((btf_sample_kind)k, 2, 3, 3, 2, 7, &a);
        uint8_t *d = NULL;
        size_t n = 0;
        CHECK_OK(prw_btf_ubo_encode(&a, &d, &n, &e), &e);
        for (size_t len = 0; len < n; len++) {
            uint8_t *copy = malloc(len ? len : 1); /* exact size: ASan sees any read past it */
            memcpy(copy, d, len);
            if (prw_btf_ubo_read_memory(copy, len, "cut.btf", &b, &e)) {
                fails++;
                prw_btf_ubo_free(&b);
            } else if (strncmp(e.msg, "cut.btf: ", 9) != 0 || strchr(e.msg, '\n')) {
                wrong++;
            }
            free(copy);
        }
        free(d);
        prw_btf_ubo_free(&a);
    }
    CHECK_MSG(fails == 0, "%d truncated files were accepted", fails);
    CHECK_MSG(wrong == 0, "%d messages do not start with the file's name", wrong);
}

/* encodes sample k, lets edit() change the bytes, and expects the reader to refuse with `want` in the message */
static void expect(btf_sample_kind k, void (*edit)(uint8_t **d, size_t *n), const char *want)
{
    prw_error e;
    prw_btf_ubo a, b;
    btf_sample(k, 2, 3, 3, 2, 9, &a);
    uint8_t *d = NULL;
    size_t n = 0;
    CHECK_OK(prw_btf_ubo_encode(&a, &d, &n, &e), &e);
    edit(&d, &n);
    bool ok = prw_btf_ubo_read_memory(d, n, "bad.btf", &b, &e);
    CHECK_MSG(!ok, "accepted; expected '%s'", want);
    if (ok) prw_btf_ubo_free(&b);
    else {
        CHECK_MSG(strstr(e.msg, want) != NULL, "message '%s' lacks '%s'", e.msg, want);
        printf("refused: %s\n", e.msg);
    }
    free(d);
    prw_btf_ubo_free(&a);
}

static void put32(uint8_t *p, uint32_t v)
{
    for (int i = 0; i < 4; i++) p[i] = (uint8_t)(v >> (8 * i));
}
/* offsets in a DFMF_V1 / FMF_PLAIN file (no R): signature 9 / 8 bytes, meta block of 264 bytes (v1) */
static void e_sig(uint8_t **d, size_t *n) { (void)n, (*d)[1] = 'X'; }
static void e_pvf(uint8_t **d, size_t *n) { (void)n, memcpy(*d, "!PVF06FC", 8); }
static void e_meta_size(uint8_t **d, size_t *n) { (void)n, put32(*d + 9, 300); }
static void e_trailing(uint8_t **d, size_t *n)
{
    *d = realloc(*d, *n + 3);
    memset(*d + *n, 0, 3);
    *n += 3;
}
/* DFMF_V1: meta 9..273, views at 273 (u32), view 0 (8 + 4 + lights*8) ... */
static void e_light_set(uint8_t **d, size_t *n)
{
    (void)n;
    size_t view1 = 273 + 4 + (8 + 4 + 3 * 8) + 8 + 4; /* view 1's first light direction */
    (*d)[view1] ^= 1;
}
static void e_light_count(uint8_t **d, size_t *n) { (void)n, put32(*d + 273 + 4 + (8 + 4 + 3 * 8) + 8, 2); }
static size_t dfmf_v1_after_dirs(void) { return 273 + 4 + 2 * (8 + 4 + 3 * 8); } /* width */
static void e_huge(uint8_t **d, size_t *n)
{
    (void)n;
    put32(*d + dfmf_v1_after_dirs(), 400), put32(*d + dfmf_v1_after_dirs() + 4, 400);
}
static void e_shape(uint8_t **d, size_t *n)
{
    (void)n;
    size_t ch0 = dfmf_v1_after_dirs() + 8 + 4 + 4 + 12 + 36; /* scalar size of channel 0 */
    put32(*d + ch0 + 1 + 4, 7);                              /* its rows */
}
static void e_scalar(uint8_t **d, size_t *n) { (void)n, (*d)[dfmf_v1_after_dirs() + 8 + 4 + 4 + 12 + 36] = 3; }

static void test_corrupt(void)
{
    expect(BTF_SAMPLE_DFMF_V1, e_sig, "is not a Bonn BTF signature");
    expect(BTF_SAMPLE_DFMF_V1, e_pvf, "PVF");
    expect(BTF_SAMPLE_DFMF_V1, e_meta_size, "the block says 300");
    expect(BTF_SAMPLE_DFMF_V1, e_trailing, "3 bytes after the data");
    expect(BTF_SAMPLE_DFMF_V1, e_light_set, "light directions differ");
    expect(BTF_SAMPLE_DFMF_V1, e_light_count, "view 1 has 2 lights");
    expect(BTF_SAMPLE_DFMF_V1, e_huge, "the directions and texture make 6 x 160000");
    expect(BTF_SAMPLE_DFMF_V1, e_shape, "channel 0 is 7 x 6");
    expect(BTF_SAMPLE_DFMF_V1, e_scalar, "scalar size 3");

    /* a BDI header claiming 400 x 400 texels of 151 x 151 directions (the UBO2014 size, 20 GiB)
     * in a file of a few hundred bytes: refused by the bytes left, before allocating them */
    prw_error e;
    prw_btf_ubo a, b;
    btf_sample(BTF_SAMPLE_BDI_SPARSE, 1, 1, 2, 2, 3, &a);
    free(a.view_dirs), free(a.light_dirs), free(a.mask), free(a.bdi);
    a.views = a.lights = 151, a.width = a.height = 400;
    a.view_dirs = calloc(2 * 151, sizeof(float)), a.light_dirs = calloc(2 * 151, sizeof(float));
    a.mask = calloc(400 * 400, 1);
    a.stored = 0, a.bdi = NULL;
    uint8_t *d = NULL;
    size_t n = 0;
    CHECK_OK(prw_btf_ubo_encode(&a, &d, &n, &e), &e);
    /* mark every texel stored, but keep the file without its data */
    size_t mask_at = n - 4 - 2 * 36 - 400 * 400;
    memset(d + mask_at, 1, 400 * 400);
    prw_mem_set_budget((uint64_t)64 << 20);
    bool ok = prw_btf_ubo_read_memory(d, n, "huge.bdi", &b, &e);
    CHECK(!ok && strstr(e.msg, "left in the file"));
    printf("refused: %s\n", e.msg);
    if (ok) prw_btf_ubo_free(&b);
    free(d);
    prw_btf_ubo_free(&a);

    /* the memory budget: a valid file whose values need more than it */
    btf_sample(BTF_SAMPLE_DFMF_V1, 3, 4, 5, 3, 1, &a);
    CHECK_OK(prw_btf_ubo_encode(&a, &d, &n, &e), &e);
    prw_mem_set_budget(1024);
    ok = prw_btf_ubo_read_memory(d, n, "budget.btf", &b, &e);
    CHECK(!ok && strstr(e.msg, "memory budget") && strncmp(e.msg, "budget.btf", 10) == 0);
    printf("refused: %s\n", e.msg);
    if (ok) prw_btf_ubo_free(&b);
    prw_mem_set_budget(0);
    free(d);
    prw_btf_ubo_free(&a);

    /* the writer refuses an inconsistent struct */
    btf_sample(BTF_SAMPLE_FMF_PLAIN, 2, 2, 2, 2, 1, &a);
    a.factors[0].rows = 5;
    CHECK(!prw_btf_ubo_encode(&a, &d, &n, &e) && strstr(e.msg, "5 x 4"));
    a.factors[0].rows = 12;
    prw_btf_ubo_free(&a);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"halves", test_halves},       {"roundtrip", test_roundtrip}, {"tensor", test_tensor},
        {"colour", test_colour},       {"truncated", test_truncated}, {"corrupt", test_corrupt},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
