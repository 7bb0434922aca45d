/* btf_ubo_write.c — the Bonn BTF binaries' writer (prw_btf_ubo.h): the layouts the reader takes,
 * field for field.  Values are stored at each factorisation's scalar size (rounded to nearest even
 * for halves and floats: exact for values read from such a file). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "btf_ubo_internal.h"

typedef struct out {
    uint8_t *p;
    size_t n, cap;
} out;

static void put(out *o, const void *src, size_t n)
{
    if (o->n + n > o->cap) {
        size_t cap = o->cap ? o->cap : 4096;
        while (cap < o->n + n) cap *= 2;
        o->p = prw_realloc(o->p, cap);
        o->cap = cap;
    }
    if (n) memcpy(o->p + o->n, src, n);
    o->n += n;
}

static void put_u8(out *o, uint8_t v) { put(o, &v, 1); }

static void put_u32(out *o, uint32_t v)
{
    uint8_t b[4] = {(uint8_t)v, (uint8_t)(v >> 8), (uint8_t)(v >> 16), (uint8_t)(v >> 24)};
    put(o, b, 4);
}

static void put_f32(out *o, float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    put_u32(o, u);
}

static void put_half(out *o, uint16_t h)
{
    uint8_t b[2] = {(uint8_t)h, (uint8_t)(h >> 8)};
    put(o, b, 2);
}

static void put_scalars(out *o, uint8_t size, const double *v, uint64_t n)
{
    for (uint64_t i = 0; i < n; i++) {
        if (size == 2) put_half(o, prw_btf_float_to_half((float)v[i]));
        else if (size == 4) put_f32(o, (float)v[i]);
        else {
            uint64_t u;
            memcpy(&u, &v[i], 8);
            put_u32(o, (uint32_t)u);
            put_u32(o, (uint32_t)(u >> 32));
        }
    }
}

static bool check_factors(const prw_btf_ubo_factors *f, uint64_t rows, uint64_t cols, const char *what, prw_error *e)
{
    if (f->scalar_size != 2 && f->scalar_size != 4 && f->scalar_size != 8)
        return prw_fail(e, "btf write: %s: scalar size %u is not 2, 4 or 8", what, f->scalar_size);
    if (f->components < 1 || !f->s || !f->u || !f->sxv) return prw_fail(e, "btf write: %s: no factors", what);
    if (f->rows != rows || f->cols != cols)
        return prw_fail(e, "btf write: %s: %u x %u, the directions and texture make %llu x %llu", what, f->rows, f->cols,
                        (unsigned long long)rows, (unsigned long long)cols);
    return true;
}

static bool check(const prw_btf_ubo *b, prw_error *e)
{
    if (b->meta_version < 1 || b->meta_version > 4) return prw_fail(e, "btf write: meta version %u is not 1..4", b->meta_version);
    if (b->meta_version < 4 && b->channels != 3)
        return prw_fail(e, "btf write: %u channels need meta version 4 (channel names)", b->channels);
    if (b->channels < 1 || b->channels > PRW_BTF_UBO_MAX_CHANNELS) return prw_fail(e, "btf write: %u channels", b->channels);
    if (b->meta_version >= 4 && (!b->channel_len || !b->channel_names)) return prw_fail(e, "btf write: channel names missing");
    if (b->meta_version >= 3 && b->xml_len && !b->xml) return prw_fail(e, "btf write: XML string missing");
    if (b->views < 1 || b->lights < 1 || b->views > PRW_BTF_UBO_MAX_DIRS || b->lights > PRW_BTF_UBO_MAX_DIRS ||
        !b->view_dirs || !b->light_dirs)
        return prw_fail(e, "btf write: %u views x %u lights", b->views, b->lights);
    if (b->width < 1 || b->height < 1 || b->width > PRW_BTF_UBO_MAX_SIDE || b->height > PRW_BTF_UBO_MAX_SIDE)
        return prw_fail(e, "btf write: %u x %u texels", b->width, b->height);
    if ((b->rotations_flag || b->format == PRW_BTF_UBO_BDI) && b->rotation_count && !b->rotations)
        return prw_fail(e, "btf write: rotations missing");
    if (!b->rotations_flag && b->rotation_count && b->format != PRW_BTF_UBO_BDI)
        return prw_fail(e, "btf write: rotations without the 'R' signature");
    uint64_t lv = (uint64_t)b->views * b->lights, xy = (uint64_t)b->width * b->height;
    switch (b->format) {
    case PRW_BTF_UBO_DFMF:
        if (!b->factors) return prw_fail(e, "btf write: no factors");
        for (uint32_t c = 0; c < b->channels; c++)
            if (!check_factors(&b->factors[c], lv, xy, "DFMF channel", e)) return false;
        return true;
    case PRW_BTF_UBO_FMF:
        if (b->fmf_ext && b->fmf_header_version > 2) return prw_fail(e, "btf write: FMF header version %u", b->fmf_header_version);
        if (b->fmf_ext && b->fmf_header_version >= 2 && (uint64_t)b->height_map_w * b->height_map_h != 0 && !b->height_map)
            return prw_fail(e, "btf write: height map missing");
        return b->factors ? check_factors(b->factors, lv * b->channels, xy, "FMF", e) : prw_fail(e, "btf write: no factors");
    case PRW_BTF_UBO_BDI: {
        if (b->compression != 2) return prw_fail(e, "btf write: BDI compression %u (only 2 is written)", b->compression);
        if (b->scan_lines < 1 || !b->mask) return prw_fail(e, "btf write: BDI without scan lines or mask");
        uint64_t stored = 0;
        for (uint64_t i = 0; i < xy; i++) {
            if (b->mask[i] > 1) return prw_fail(e, "btf write: mask value %u", b->mask[i]);
            stored += b->mask[i];
        }
        if (stored != b->stored || (stored && !b->bdi))
            return prw_fail(e, "btf write: the mask holds %llu texels, stored says %llu", (unsigned long long)stored,
                            (unsigned long long)b->stored);
        return true;
    }
    }
    return prw_fail(e, "btf write: unknown format %d", (int)b->format);
}

static void meta_block(out *o, const prw_btf_ubo *b)
{
    size_t start = o->n;
    put_u32(o, 0); /* the size, patched below */
    put_u32(o, b->meta_version);
    put(o, b->measurement_setup, 80);
    put(o, b->image_sensor, 80);
    put(o, b->light_source, 80);
    put_f32(o, b->ppmm);
    for (int i = 0; i < 3; i++) put_f32(o, b->rgb_scale[i]);
    if (b->meta_version > 1) put_u32(o, b->cosine_flag);
    if (b->meta_version > 2) {
        put_u32(o, b->xml_len);
        put(o, b->xml, b->xml_len);
    }
    if (b->meta_version > 3) {
        put_u32(o, b->channels);
        for (uint32_t c = 0; c < b->channels; c++) {
            put_u32(o, b->channel_len[c]);
            put(o, b->channel_names[c], b->channel_len[c]);
        }
    }
    uint32_t size = (uint32_t)(o->n - start);
    uint8_t s[4] = {(uint8_t)size, (uint8_t)(size >> 8), (uint8_t)(size >> 16), (uint8_t)(size >> 24)};
    memcpy(o->p + start, s, 4);
}

static void directions(out *o, const prw_btf_ubo *b)
{
    put_u32(o, b->views);
    for (uint32_t v = 0; v < b->views; v++) {
        put_f32(o, b->view_dirs[2 * v]);
        put_f32(o, b->view_dirs[2 * v + 1]);
        put_u32(o, b->lights);
        for (uint32_t l = 0; l < 2 * b->lights; l++) put_f32(o, b->light_dirs[l]);
    }
    put_u32(o, b->width);
    put_u32(o, b->height);
}

static void rotations(out *o, const prw_btf_ubo *b)
{
    put_u32(o, b->rotation_count);
    for (uint64_t i = 0; i < 9 * (uint64_t)b->rotation_count; i++) put_f32(o, b->rotations[i]);
}

static void factors(out *o, const prw_btf_ubo_factors *f)
{
    put_scalars(o, f->scalar_size, f->s, f->components);
    put_scalars(o, f->scalar_size, f->u, (uint64_t)f->rows * f->components);
    put_scalars(o, f->scalar_size, f->sxv, (uint64_t)f->cols * f->components);
}

bool prw_btf_ubo_encode(const prw_btf_ubo *b, uint8_t **data, size_t *size, prw_error *e)
{
    *data = NULL;
    *size = 0;
    if (!check(b, e)) return false;
    out o = {0};
    const char *sig = b->format == PRW_BTF_UBO_DFMF ? "!DFMF08FC"
                      : b->format == PRW_BTF_UBO_BDI ? "!BDIF06R2!"
                      : b->fmf_ext                   ? "!FMF12FCE"
                                                     : "!FMF06FC";
    put(&o, sig, strlen(sig));
    if (b->rotations_flag && b->format != PRW_BTF_UBO_BDI) put_u8(&o, 'R');
    meta_block(&o, b);
    directions(&o, b);
    if (b->format == PRW_BTF_UBO_BDI) {
        put_u32(&o, b->scan_lines);
        put_u8(&o, b->compression);
        put(&o, b->mask, (size_t)b->width * b->height);
        rotations(&o, b);
        uint64_t abrdf = (uint64_t)b->views * b->lights * b->channels;
        uint64_t per_chunk = (uint64_t)b->scan_lines * b->width;
        for (uint64_t done = 0; done < b->stored;) {
            uint64_t n = PRW_MIN(per_chunk, b->stored - done);
            if (n * abrdf * 2 > UINT32_MAX) {
                free(o.p);
                return prw_fail(e, "btf write: a chunk of %llu ABRDFs does not fit the 32-bit chunk size; use fewer "
                                "scan lines per chunk", (unsigned long long)n);
            }
            put_u32(&o, (uint32_t)(n * abrdf * 2));
            for (uint64_t i = 0; i < n * abrdf; i++) put_half(&o, b->bdi[done * abrdf + i]);
            done += n;
        }
    } else {
        if (b->rotations_flag) rotations(&o, b);
        if (b->format == PRW_BTF_UBO_DFMF) {
            put_u32(&o, b->dfmf_components);
            put_u32(&o, (uint32_t)b->color_model);
            for (int i = 0; i < 3; i++) put_f32(&o, b->color_mean[i]);
            for (int i = 0; i < 9; i++) put_f32(&o, b->color_transform[i]);
            for (uint32_t c = 0; c < b->channels; c++) {
                const prw_btf_ubo_factors *f = &b->factors[c];
                put_u8(&o, f->scalar_size);
                put_u32(&o, f->components);
                put_u32(&o, f->rows);
                put_u32(&o, f->cols);
                factors(&o, f);
            }
        } else {
            if (b->fmf_ext) {
                put_u8(&o, b->fmf_header_version);
                if (b->fmf_header_version >= 1) put_u32(&o, b->drr);
                if (b->fmf_header_version >= 2) {
                    put_u32(&o, b->height_map_w);
                    put_u32(&o, b->height_map_h);
                    for (uint64_t i = 0; i < (uint64_t)b->height_map_w * b->height_map_h; i++) put_half(&o, b->height_map[i]);
                }
            }
            const prw_btf_ubo_factors *f = b->factors;
            put_u32(&o, b->fmf_components0);
            put_u8(&o, f->scalar_size);
            put_u32(&o, f->components);
            put_u32(&o, f->rows);
            put_u32(&o, f->cols);
            factors(&o, f);
        }
    }
    *data = o.p;
    *size = o.n;
    return true;
}

bool prw_btf_ubo_write(const char *path, const prw_btf_ubo *b, prw_error *e)
{
    uint8_t *data;
    size_t size;
    if (!prw_btf_ubo_encode(b, &data, &size, e)) return prw_fail_wrap(e, "%s", path);
    bool ok = prw_write_file_atomic(path, data, size, e);
    free(data);
    return ok;
}
