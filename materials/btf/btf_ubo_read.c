/* btf_ubo_read.c — the Bonn BTF binaries' reader (prw_btf_ubo.h).  Every count is checked against
 * the bytes left before anything is allocated, and the allocations against the memory budget. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "btf_ubo_internal.h"

/* the reader's cursor and what it has allocated so far (for the budget) */
typedef struct cur {
    btf_cur b;
    uint64_t allocated;
} cur;

static bool f32s(cur *c, const char *what, float *v, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!btf_cur_f32(&c->b, what, &v[i])) return false;
    return true;
}

/* Allocates count x size bytes after the budget check (counting what this read holds already). */
static void *alloc(cur *c, uint64_t count, uint64_t size, const char *what)
{
    uint64_t bytes = prw_mul_sat(count, size);
    uint64_t total = prw_add_sat(c->allocated, bytes);
    char held[300];
    snprintf(held, sizeof held, "its data up to the %s", what);
    if (!prw_mem_check(total, c->b.name, held, c->b.e)) return NULL;
    c->allocated = total;
    return prw_calloc(bytes ? (size_t)bytes : 1, 1);
}

/* n scalars of the file's size into doubles. */
static bool scalars(cur *c, uint8_t size, double *dst, uint64_t n, const char *what)
{
    if (!btf_cur_need(&c->b, n, size, what)) return false;
    const uint8_t *p = c->b.p + c->b.at;
    for (uint64_t i = 0; i < n; i++, p += size) {
        if (size == 2) {
            dst[i] = prw_btf_half_to_float((uint16_t)(p[0] | (p[1] << 8)));
        } else if (size == 4) {
            uint32_t u = prw_btf_le32(p);
            float f;
            memcpy(&f, &u, 4);
            dst[i] = f;
        } else {
            uint64_t u = (uint64_t)prw_btf_le32(p) | ((uint64_t)prw_btf_le32(p + 4) << 32);
            memcpy(&dst[i], &u, 8);
        }
        /* beyond float no renderer can use it, and within it every dot product stays finite in double */
        if (!(fabs(dst[i]) <= FLT_MAX))
            return btf_cur_fail(&c->b, what, "element %llu (%g) is not a finite float value", (unsigned long long)i, dst[i]);
    }
    c->b.at += (size_t)(n * size);
    return true;
}

static bool meta_block(cur *c, prw_btf_ubo *b)
{
    size_t start = c->b.at;
    uint32_t size;
    if (!btf_cur_u32(&c->b, "meta block size", &size) || !btf_cur_u32(&c->b, "meta block version", &b->meta_version)) return false;
    if (b->meta_version < 1 || b->meta_version > 4)
        return btf_cur_fail(&c->b, "meta block version", "version %u is not 1..4", b->meta_version);
    if (!btf_cur_take(&c->b, b->measurement_setup, 80, "measurement setup") || !btf_cur_take(&c->b, b->image_sensor, 80, "image sensor") ||
        !btf_cur_take(&c->b, b->light_source, 80, "light source") || !btf_cur_f32(&c->b, "pixels per mm", &b->ppmm) ||
        !f32s(c, "RGB scale", b->rgb_scale, 3))
        return false;
    if (b->meta_version > 1 && !btf_cur_u32(&c->b, "cosine flag", &b->cosine_flag)) return false;
    if (b->meta_version > 2) {
        if (!btf_cur_u32(&c->b, "XML length", &b->xml_len) || !btf_cur_need(&c->b, b->xml_len, 1, "XML string")) return false;
        b->xml = alloc(c, (uint64_t)b->xml_len + 1, 1, "XML string");
        if (!b->xml || !btf_cur_take(&c->b, b->xml, b->xml_len, "XML string")) return false;
    }
    b->channels = 3;
    if (b->meta_version > 3) {
        if (!btf_cur_u32(&c->b, "channel count", &b->channels)) return false;
        if (b->channels < 1 || b->channels > PRW_BTF_UBO_MAX_CHANNELS)
            return btf_cur_fail(&c->b, "channel count", "%u channels (1..%u supported)", b->channels, PRW_BTF_UBO_MAX_CHANNELS);
        if (!btf_cur_need(&c->b, b->channels, 4, "channel names")) return false;
        b->channel_len = alloc(c, b->channels, sizeof *b->channel_len, "channel names");
        b->channel_names = b->channel_len ? alloc(c, b->channels, sizeof *b->channel_names, "channel names") : NULL;
        if (!b->channel_names) return false;
        for (uint32_t i = 0; i < b->channels; i++) {
            if (!btf_cur_u32(&c->b, "channel name length", &b->channel_len[i]) || !btf_cur_need(&c->b, b->channel_len[i], 1, "channel name"))
                return false;
            b->channel_names[i] = alloc(c, (uint64_t)b->channel_len[i] + 1, 1, "channel name");
            if (!b->channel_names[i] || !btf_cur_take(&c->b, b->channel_names[i], b->channel_len[i], "channel name")) return false;
        }
    }
    if (c->b.at - start != size)
        return btf_cur_fail(&c->b, "meta block", "its fields take %zu bytes, the block says %u", c->b.at - start, size);
    return true;
}

static bool directions(cur *c, prw_btf_ubo *b)
{
    if (!btf_cur_u32(&c->b, "view count", &b->views)) return false;
    if (b->views < 1 || b->views > PRW_BTF_UBO_MAX_DIRS)
        return btf_cur_fail(&c->b, "view count", "%u views (1..%u supported)", b->views, PRW_BTF_UBO_MAX_DIRS);
    /* every view holds at least 12 bytes */
    if (!btf_cur_need(&c->b, b->views, 12, "views")) return false;
    b->view_dirs = alloc(c, b->views, 2 * sizeof(float), "view directions");
    if (!b->view_dirs) return false;
    for (uint32_t v = 0; v < b->views; v++) {
        uint32_t nl;
        if (!f32s(c, "view direction", &b->view_dirs[2 * v], 2) || !btf_cur_u32(&c->b, "light count", &nl)) return false;
        if (v == 0) {
            if (nl < 1 || nl > PRW_BTF_UBO_MAX_DIRS)
                return btf_cur_fail(&c->b, "light count", "%u lights (1..%u supported)", nl, PRW_BTF_UBO_MAX_DIRS);
            if (!btf_cur_need(&c->b, nl, 8, "light directions")) return false;
            b->lights = nl;
            b->light_dirs = alloc(c, nl, 2 * sizeof(float), "light directions");
            if (!b->light_dirs || !f32s(c, "light direction", b->light_dirs, 2 * (size_t)nl)) return false;
        } else {
            if (nl != b->lights)
                return btf_cur_fail(&c->b, "light count", "view %u has %u lights, view 0 has %u (one light set for all views "
                               "is supported)", v, nl, b->lights);
            if (!btf_cur_need(&c->b, nl, 8, "light directions")) return false;
            if (memcmp(c->b.p + c->b.at, b->light_dirs, (size_t)nl * 8) != 0) /* little-endian hosts only */
                return btf_cur_fail(&c->b, "light directions", "view %u's light directions differ from view 0's (one light "
                               "set for all views is supported)", v);
            c->b.at += (size_t)nl * 8;
        }
    }
    for (uint32_t i = 0; i < 2 * b->views; i++)
        if (!isfinite(b->view_dirs[i])) return btf_cur_fail(&c->b, "view directions", "view %u is not finite", i / 2);
    for (uint32_t i = 0; i < 2 * b->lights; i++)
        if (!isfinite(b->light_dirs[i])) return btf_cur_fail(&c->b, "light directions", "light %u is not finite", i / 2);
    if (!btf_cur_u32(&c->b, "width", &b->width) || !btf_cur_u32(&c->b, "height", &b->height)) return false;
    if (b->width < 1 || b->height < 1 || b->width > PRW_BTF_UBO_MAX_SIDE || b->height > PRW_BTF_UBO_MAX_SIDE)
        return btf_cur_fail(&c->b, "texture size", "%u x %u texels (1..%u a side supported)", b->width, b->height,
                       PRW_BTF_UBO_MAX_SIDE);
    return true;
}

static bool rotations(cur *c, prw_btf_ubo *b)
{
    if (!b->rotations_flag) return true;
    if (!btf_cur_u32(&c->b, "rotation count", &b->rotation_count) || !btf_cur_need(&c->b, b->rotation_count, 36, "rotations")) return false;
    if (!b->rotation_count) return true;
    b->rotations = alloc(c, b->rotation_count, 36, "rotations");
    return b->rotations && f32s(c, "rotation", b->rotations, 9 * (size_t)b->rotation_count);
}

static bool scalar_size_ok(cur *c, uint8_t s, const char *what)
{
    if (s == 2 || s == 4 || s == 8) return true;
    return btf_cur_fail(&c->b, what, "scalar size %u is not 2, 4 or 8", s);
}

/* S, U, SxV of one factorisation whose header has been read into f. */
static bool factor_data(cur *c, prw_btf_ubo_factors *f)
{
    if (f->components < 1) return btf_cur_fail(&c->b, "component count", "0 components");
    uint64_t total = prw_add_sat(prw_add_sat(1, f->rows), f->cols);
    if (!btf_cur_need(&c->b, prw_mul_sat(total, f->components), f->scalar_size, "factors")) return false;
    f->s = alloc(c, f->components, 8, "singular values");
    f->u = f->s ? alloc(c, prw_mul_sat(f->rows, f->components), 8, "U") : NULL;
    f->sxv = f->u ? alloc(c, prw_mul_sat(f->cols, f->components), 8, "SxV") : NULL;
    return f->sxv && scalars(c, f->scalar_size, f->s, f->components, "singular values") &&
           scalars(c, f->scalar_size, f->u, (uint64_t)f->rows * f->components, "U") &&
           scalars(c, f->scalar_size, f->sxv, (uint64_t)f->cols * f->components, "SxV");
}

static bool dfmf(cur *c, prw_btf_ubo *b)
{
    if (!btf_cur_u32(&c->b, "component count", &b->dfmf_components)) return false;
    uint32_t cm;
    if (!btf_cur_u32(&c->b, "colour model", &cm) || !f32s(c, "colour mean", b->color_mean, 3) ||
        !f32s(c, "colour transform", b->color_transform, 9))
        return false;
    b->color_model = (int32_t)cm;
    b->factors = alloc(c, b->channels, sizeof *b->factors, "channels");
    if (!b->factors) return false;
    uint64_t rows = (uint64_t)b->views * b->lights, cols = (uint64_t)b->width * b->height;
    for (uint32_t ch = 0; ch < b->channels; ch++) {
        prw_btf_ubo_factors *f = &b->factors[ch];
        if (!btf_cur_u8(&c->b, "scalar size", &f->scalar_size) || !scalar_size_ok(c, f->scalar_size, "scalar size") ||
            !btf_cur_u32(&c->b, "component count", &f->components) || !btf_cur_u32(&c->b, "rows", &f->rows) || !btf_cur_u32(&c->b, "columns", &f->cols))
            return false;
        if (f->rows != rows || f->cols != cols)
            return btf_cur_fail(&c->b, "matrix shape", "channel %u is %u x %u, the directions and texture make %llu x %llu", ch,
                           f->rows, f->cols, (unsigned long long)rows, (unsigned long long)cols);
        if (!factor_data(c, f)) return false;
    }
    return true;
}

static bool fmf(cur *c, prw_btf_ubo *b)
{
    if (b->fmf_ext) {
        if (!btf_cur_u8(&c->b, "FMF header version", &b->fmf_header_version)) return false;
        if (b->fmf_header_version > 2)
            return btf_cur_fail(&c->b, "FMF header version", "version %u is not 0..2", b->fmf_header_version);
        if (b->fmf_header_version >= 1 && !btf_cur_u32(&c->b, "dynamic-range flag", &b->drr)) return false;
        if (b->fmf_header_version >= 2) {
            if (!btf_cur_u32(&c->b, "height-map width", &b->height_map_w) || !btf_cur_u32(&c->b, "height-map height", &b->height_map_h))
                return false;
            uint64_t n = prw_mul_sat(b->height_map_w, b->height_map_h);
            if (!btf_cur_need(&c->b, n, 2, "height map")) return false;
            if (n) {
                b->height_map = alloc(c, n, 2, "height map");
                if (!b->height_map) return false;
                for (uint64_t i = 0; i < n; i++) b->height_map[i] = (uint16_t)(c->b.p[c->b.at + 2 * i] | (c->b.p[c->b.at + 2 * i + 1] << 8));
                c->b.at += (size_t)(2 * n);
            }
        }
    }
    b->factors = alloc(c, 1, sizeof *b->factors, "factors");
    if (!b->factors) return false;
    prw_btf_ubo_factors *f = b->factors;
    if (!btf_cur_u32(&c->b, "component count", &b->fmf_components0) || !btf_cur_u8(&c->b, "scalar size", &f->scalar_size) ||
        !scalar_size_ok(c, f->scalar_size, "scalar size") || !btf_cur_u32(&c->b, "component count", &f->components) ||
        !btf_cur_u32(&c->b, "rows", &f->rows) || !btf_cur_u32(&c->b, "columns", &f->cols))
        return false;
    uint64_t rows = (uint64_t)b->views * b->lights * b->channels, cols = (uint64_t)b->width * b->height;
    if (f->rows != rows || f->cols != cols)
        return btf_cur_fail(&c->b, "matrix shape", "%u x %u, the directions, channels and texture make %llu x %llu", f->rows,
                       f->cols, (unsigned long long)rows, (unsigned long long)cols);
    return factor_data(c, f);
}

static bool bdi(cur *c, prw_btf_ubo *b)
{
    if (!btf_cur_u32(&c->b, "scan lines per chunk", &b->scan_lines) || !btf_cur_u8(&c->b, "compression", &b->compression)) return false;
    if (b->scan_lines < 1) return btf_cur_fail(&c->b, "scan lines per chunk", "0 scan lines");
    if (b->compression != 2)
        return btf_cur_fail(&c->b, "compression", "kind %u: only sparse uncompressed BDI (2) is supported", b->compression);
    uint64_t texels = (uint64_t)b->width * b->height;
    if (!btf_cur_need(&c->b, texels, 1, "mask")) return false;
    b->mask = alloc(c, texels, 1, "mask");
    b->bdi_slot = b->mask ? alloc(c, texels, 8, "mask") : NULL;
    if (!b->bdi_slot || !btf_cur_take(&c->b, b->mask, (size_t)texels, "mask")) return false;
    b->stored = 0;
    for (uint64_t i = 0; i < texels; i++) {
        if (b->mask[i] > 1) return btf_cur_fail(&c->b, "mask", "texel %llu has mask value %u", (unsigned long long)i, b->mask[i]);
        b->bdi_slot[i] = b->stored;
        b->stored += b->mask[i];
    }
    if (!rotations(c, b)) return false;
    uint64_t abrdf = (uint64_t)b->views * b->lights * b->channels;
    uint64_t per_chunk = (uint64_t)b->scan_lines * b->width;
    if (!btf_cur_need(&c->b, prw_mul_sat(b->stored, abrdf), 2, "ABRDFs")) return false;
    b->bdi = alloc(c, prw_mul_sat(b->stored, abrdf), 2, "ABRDFs");
    if (!b->bdi) return false;
    for (uint64_t done = 0; done < b->stored;) {
        uint64_t n = PRW_MIN(per_chunk, b->stored - done);
        uint32_t bytes;
        if (!btf_cur_u32(&c->b, "chunk size", &bytes)) return false;
        if (bytes != n * abrdf * 2)
            return btf_cur_fail(&c->b, "chunk size", "%u bytes, %llu ABRDFs of %llu halves make %llu", bytes,
                           (unsigned long long)n, (unsigned long long)abrdf, (unsigned long long)(n * abrdf * 2));
        if (!btf_cur_need(&c->b, bytes, 1, "chunk")) return false;
        const uint8_t *p = c->b.p + c->b.at;
        uint16_t *dst = b->bdi + done * abrdf;
        for (uint64_t i = 0; i < n * abrdf; i++) dst[i] = (uint16_t)(p[2 * i] | (p[2 * i + 1] << 8));
        for (uint64_t i = 0; i < n * abrdf; i++)
            if (!isfinite(prw_btf_half_to_float(dst[i])))
                return btf_cur_fail(&c->b, "chunk", "value %llu is not finite", (unsigned long long)i);
        c->b.at += bytes;
        done += n;
    }
    return true;
}

/* The signature: sets format, rotations_flag and fmf_ext. */
static bool signature(cur *c, prw_btf_ubo *b)
{
    static const struct {
        const char *s;
        prw_btf_ubo_format f;
        bool r, ext;
    } sig[] = {
        {"!DFMF08FCR", PRW_BTF_UBO_DFMF, true, false}, {"!DFMF08FC", PRW_BTF_UBO_DFMF, false, false},
        {"!FMF12FCER", PRW_BTF_UBO_FMF, true, true},   {"!FMF12FCE", PRW_BTF_UBO_FMF, false, true},
        {"!FMF06FCR", PRW_BTF_UBO_FMF, true, false},   {"!FMF06FC", PRW_BTF_UBO_FMF, false, false},
        {"!BDIF06R2!", PRW_BTF_UBO_BDI, true, false},
    };
    for (size_t i = 0; i < PRW_ARRAY_LEN(sig); i++) {
        size_t n = strlen(sig[i].s);
        /* each "R" variant comes before the signature it extends, as the public readers decide: a
         * file without rotations whose meta size starts with the byte 'R' reads as one with them */
        if (c->b.n >= n && memcmp(c->b.p, sig[i].s, n) == 0) {
            b->format = sig[i].f;
            b->rotations_flag = sig[i].r;
            b->fmf_ext = sig[i].ext;
            c->b.at = n;
            return true;
        }
    }
    if (c->b.n >= 5 && (memcmp(c->b.p, "!PVF0", 5) == 0))
        return prw_fail(c->b.e, "%s: byte 0 (signature): per-view factorised BTFs (PVF) are not supported", c->b.name);
    char shown[12] = {0};
    for (size_t i = 0; i < 10 && i < c->b.n; i++) shown[i] = (c->b.p[i] >= 0x20 && c->b.p[i] < 0x7f) ? (char)c->b.p[i] : '?';
    return prw_fail(c->b.e, "%s: byte 0 (signature): '%s' is not a Bonn BTF signature (DFMF, FMF, BDI)", c->b.name, shown);
}

bool prw_btf_ubo_read_memory(const void *data, size_t size, const char *name, prw_btf_ubo *out, prw_error *e)
{
    memset(out, 0, sizeof *out);
    cur c = {.b = {.p = data, .n = size, .name = name ? name : "(btf)", .e = e}};
    bool ok = signature(&c, out) && meta_block(&c, out) && directions(&c, out);
    if (ok) {
        if (out->format == PRW_BTF_UBO_DFMF) ok = rotations(&c, out) && dfmf(&c, out);
        else if (out->format == PRW_BTF_UBO_FMF) ok = rotations(&c, out) && fmf(&c, out);
        else ok = bdi(&c, out);
    }
    if (ok && c.b.at != c.b.n) ok = btf_cur_fail(&c.b, "end", "%zu bytes after the data", c.b.n - c.b.at);
    if (!ok) prw_btf_ubo_free(out);
    return ok;
}

bool prw_btf_ubo_read(const char *path, prw_btf_ubo *out, prw_error *e)
{
    memset(out, 0, sizeof *out);
    char *data = NULL;
    size_t size = 0;
    /* halves become doubles: up to 4 bytes held per byte read, besides the file itself */
    if (!prw_read_file_bounded(path, 0, 5, "a BTF file", &data, &size, e)) return false;
    bool ok = prw_btf_ubo_read_memory(data, size, path, out, e);
    free(data);
    return ok;
}
