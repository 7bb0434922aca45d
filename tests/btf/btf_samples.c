/* btf_samples.c — see btf_samples.h. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "btf_samples.h"

static uint64_t next(uint64_t *s)
{
    *s += 0x9E3779B97F4A7C15ull;
    uint64_t z = *s;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* uniform in [-2, 2), rounded to the scalar size so that the file holds it exactly */
static double value(uint64_t *s, uint8_t size)
{
    double u = (double)(next(s) >> 11) * 0x1.0p-53 * 4.0 - 2.0;
    if (size == 2) return prw_btf_half_to_float(prw_btf_float_to_half((float)u));
    if (size == 4) return (float)u;
    return u;
}

static void *zalloc(size_t n) { return calloc(n ? n : 1, 1); }

static void factors(prw_btf_ubo_factors *f, uint8_t size, uint32_t k, uint32_t rows, uint32_t cols, uint64_t *s)
{
    f->scalar_size = size, f->components = k, f->rows = rows, f->cols = cols;
    f->s = zalloc(sizeof(double) * k);
    f->u = zalloc(sizeof(double) * k * rows);
    f->sxv = zalloc(sizeof(double) * k * cols);
    for (uint32_t i = 0; i < k; i++) f->s[i] = value(s, size);
    for (uint64_t i = 0; i < (uint64_t)k * rows; i++) f->u[i] = value(s, size);
    for (uint64_t i = 0; i < (uint64_t)k * cols; i++) f->sxv[i] = value(s, size);
}

static void common(prw_btf_ubo *b, prw_btf_ubo_format f, uint32_t version, bool rot, uint32_t views, uint32_t lights,
                   uint32_t w, uint32_t h, uint64_t *s)
{
    memset(b, 0, sizeof *b);
    b->format = f;
    b->rotations_flag = rot || f == PRW_BTF_UBO_BDI;
    b->meta_version = version;
    strcpy(b->measurement_setup, "prw test: synthetic");
    strcpy(b->image_sensor, "none");
    memcpy(b->light_source, "all 80 bytes used: no terminating zero .........................................", 80);
    b->ppmm = 12.5f, b->rgb_scale[0] = 1, b->rgb_scale[1] = 0.5f, b->rgb_scale[2] = 2;
    b->cosine_flag = version > 1 ? 1 : 0;
    if (version > 2) {
        const char *xml = "<measurement><note>synthetic</note></measurement>";
        b->xml_len = (uint32_t)strlen(xml);
        b->xml = zalloc(b->xml_len + 1);
        memcpy(b->xml, xml, b->xml_len);
    }
    b->channels = 3;
    if (version > 3) {
        b->channel_len = zalloc(sizeof(uint32_t) * 3);
        b->channel_names = zalloc(sizeof(char *) * 3);
        const char *names[3] = {"R", "Green", ""};
        for (int c = 0; c < 3; c++) {
            b->channel_len[c] = (uint32_t)strlen(names[c]);
            b->channel_names[c] = zalloc(b->channel_len[c] + 1);
            memcpy(b->channel_names[c], names[c], b->channel_len[c]);
        }
    }
    b->views = views, b->lights = lights;
    b->view_dirs = zalloc(sizeof(float) * 2 * views);
    b->light_dirs = zalloc(sizeof(float) * 2 * lights);
    for (uint32_t i = 0; i < 2 * views; i++) b->view_dirs[i] = (float)value(s, 4) + 2.0f;
    for (uint32_t i = 0; i < 2 * lights; i++) b->light_dirs[i] = (float)value(s, 4) + 2.0f;
    b->width = w, b->height = h;
    if (b->rotations_flag) {
        b->rotation_count = 2;
        b->rotations = zalloc(sizeof(float) * 18);
        for (int i = 0; i < 18; i++) b->rotations[i] = (float)value(s, 4);
    }
}

void btf_sample(btf_sample_kind kind, uint32_t views, uint32_t lights, uint32_t w, uint32_t h, uint64_t seed,
                prw_btf_ubo *b)
{
    uint64_t s = seed * 7919u + (uint64_t)kind;
    uint32_t lv = views * lights, xy = w * h;
    switch (kind) {
    case BTF_SAMPLE_DFMF_R_V4:
    case BTF_SAMPLE_DFMF_V1: {
        bool v4 = kind == BTF_SAMPLE_DFMF_R_V4;
        common(b, PRW_BTF_UBO_DFMF, v4 ? 4 : 1, v4, views, lights, w, h, &s);
        b->dfmf_components = 3;
        b->color_model = v4 ? 11 : 0;
        for (int i = 0; i < 3; i++) b->color_mean[i] = (float)value(&s, 4);
        for (int i = 0; i < 9; i++) b->color_transform[i] = (float)value(&s, 4);
        b->factors = zalloc(sizeof *b->factors * 3);
        static const uint8_t sizes[3] = {2, 4, 8};
        for (uint32_t c = 0; c < 3; c++) factors(&b->factors[c], v4 ? sizes[c] : 4, 1 + c, lv, xy, &s);
        break;
    }
    case BTF_SAMPLE_FMF_EXT:
    case BTF_SAMPLE_FMF_PLAIN: {
        bool ext = kind == BTF_SAMPLE_FMF_EXT;
        common(b, PRW_BTF_UBO_FMF, ext ? 3 : 2, ext, views, lights, w, h, &s);
        b->fmf_ext = ext;
        if (ext) {
            b->fmf_header_version = 2;
            b->drr = 1;
            b->height_map_w = 3, b->height_map_h = 2;
            b->height_map = zalloc(sizeof(uint16_t) * 6);
            for (int i = 0; i < 6; i++) b->height_map[i] = prw_btf_float_to_half((float)value(&s, 2));
        }
        b->fmf_components0 = 4;
        b->factors = zalloc(sizeof *b->factors);
        factors(b->factors, ext ? 8 : 2, 4, lv * 3, xy, &s);
        break;
    }
    case BTF_SAMPLE_BDI_SPARSE: {
        common(b, PRW_BTF_UBO_BDI, 3, true, views, lights, w, h, &s);
        b->scan_lines = 2, b->compression = 2;
        b->mask = zalloc(xy);
        for (uint32_t i = 0; i < xy; i++) {
            b->mask[i] = (next(&s) % 4) != 0;
            b->stored += b->mask[i];
        }
        b->bdi = zalloc(sizeof(uint16_t) * b->stored * lv * 3);
        for (uint64_t i = 0; i < b->stored * lv * 3; i++) b->bdi[i] = prw_btf_float_to_half((float)value(&s, 2));
        break;
    }
    default: memset(b, 0, sizeof *b); break;
    }
}

/* two separable terms per channel: a(c, v, l) g(x, y) + b(c, v, l) h(x, y), small dyadic numbers */
static double ta(uint32_t c, uint32_t v, uint32_t l) { return (double)((c + 1) * (v + 2) + l) / 8.0; }
static double tb(uint32_t c, uint32_t v, uint32_t l) { return (double)((int)(3 * c + l) - (int)v) / 16.0; }
static double tg(uint32_t x, uint32_t y) { return (double)(x + 2 * y + 1) / 4.0; }
static double th(uint32_t x, uint32_t y) { return (double)((int)x - (int)y) / 2.0; }

double btf_sample_tensor(uint32_t c, uint32_t v, uint32_t l, uint32_t x, uint32_t y)
{
    return ta(c, v, l) * tg(x, y) + tb(c, v, l) * th(x, y);
}

void btf_sample_tensor_file(prw_btf_ubo_format format, uint32_t views, uint32_t lights, uint32_t w, uint32_t h,
                            prw_btf_ubo *b)
{
    uint64_t s = 1;
    common(b, format, 2, false, views, lights, w, h, &s);
    uint32_t lv = views * lights, xy = w * h;
    if (format == PRW_BTF_UBO_BDI) {
        b->scan_lines = 3, b->compression = 2, b->stored = xy;
        b->mask = zalloc(xy);
        memset(b->mask, 1, xy);
        b->bdi = zalloc(sizeof(uint16_t) * xy * lv * 3);
        for (uint32_t y = 0; y < h; y++)
            for (uint32_t x = 0; x < w; x++)
                for (uint32_t v = 0; v < views; v++)
                    for (uint32_t l = 0; l < lights; l++)
                        for (uint32_t c = 0; c < 3; c++)
                            b->bdi[((uint64_t)(y * w + x) * lv + v * lights + l) * 3 + c] =
                                prw_btf_float_to_half((float)btf_sample_tensor(c, v, l, x, y));
        return;
    }
    uint32_t nf = format == PRW_BTF_UBO_DFMF ? 3 : 1;
    b->factors = zalloc(sizeof *b->factors * nf);
    b->dfmf_components = 2, b->fmf_components0 = 2;
    for (uint32_t f = 0; f < nf; f++) {
        prw_btf_ubo_factors *F = &b->factors[f];
        uint32_t rows = format == PRW_BTF_UBO_DFMF ? lv : lv * 3;
        F->scalar_size = 4, F->components = 2, F->rows = rows, F->cols = xy;
        F->s = zalloc(sizeof(double) * 2);
        F->u = zalloc(sizeof(double) * 2 * rows);
        F->sxv = zalloc(sizeof(double) * 2 * xy);
        F->s[0] = 1, F->s[1] = 1;
        for (uint32_t r = 0; r < rows; r++) {
            uint32_t c = format == PRW_BTF_UBO_DFMF ? f : r % 3, vl = format == PRW_BTF_UBO_DFMF ? r : r / 3;
            F->u[2 * r] = ta(c, vl / lights, vl % lights);
            F->u[2 * r + 1] = tb(c, vl / lights, vl % lights);
        }
        for (uint32_t y = 0; y < h; y++)
            for (uint32_t x = 0; x < w; x++) {
                F->sxv[2 * (y * w + x)] = tg(x, y);
                F->sxv[2 * (y * w + x) + 1] = th(x, y);
            }
    }
}
