/* btf_packed_io.c — the file of our compressed BTF form (prw_btf_codec.h):
 *   "PRWBTFC1", u32 version (1, or 2 with the average), u32 codec, u32 width, height, views, lights, components, clusters,
 *   f32 view (theta, phi) x views, f32 light (theta, phi) x lights, then the codec's arrays:
 *   FMF u (D x k halves), w (N x k); CLUSTER u32 index (N), mean (c x D), basis (c x k x D),
 *   w (N x k); PVF mean (V x 3L), basis (V x k x 3L), w (V x N x k); SPARSE u32 M (residual entries),
 *   u16 index (N), mean, basis, w as CLUSTER, u16 entries per texel (N, summing to M), u16 pair (M),
 *   residual (M x 3 halves); version 2 then the scale rule's average: f32 base r, g, b, metallic,
 *   roughness, specular, fit rms % (prw_btf_average); little-endian, nothing after. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "btf_ubo_internal.h"
#include "prw_btf_codec.h"

#define MAGIC "PRWBTFC1"
#define AVG_BYTES 28u

typedef struct sizes {
    uint64_t u, w, mean, basis, index; /* element counts */
    uint64_t index_bytes;              /* per index: 4, SPARSE 2 */
    uint64_t sparse_bytes;             /* SPARSE: M, the counts, pairs and residuals */
} sizes;

static bool sizes_of(const prw_btf_packed *p, sizes *s)
{
    uint64_t D = prw_mul_sat((uint64_t)p->views * p->lights, 3), N = (uint64_t)p->width * p->height, k = p->components;
    memset(s, 0, sizeof *s);
    switch (p->codec) {
    case PRW_BTF_CODEC_FMF: s->u = prw_mul_sat(D, k), s->w = prw_mul_sat(N, k); return k >= 1;
    case PRW_BTF_CODEC_CLUSTER:
        s->index = N, s->mean = prw_mul_sat(p->clusters, D), s->basis = prw_mul_sat(prw_mul_sat(p->clusters, k), D),
        s->w = prw_mul_sat(N, k);
        s->index_bytes = 4;
        return p->clusters >= 1;
    case PRW_BTF_CODEC_SPARSE:
        s->index = N, s->mean = prw_mul_sat(p->clusters, D), s->basis = prw_mul_sat(prw_mul_sat(p->clusters, k), D),
        s->w = prw_mul_sat(N, k), s->index_bytes = 2;
        s->sparse_bytes = prw_add_sat(4 + 2 * N, prw_mul_sat(p->sparse_count, 8));
        return p->clusters >= 1 && p->clusters <= 65535 && (uint64_t)p->views * p->lights <= 65535;
    case PRW_BTF_CODEC_PVF: {
        uint64_t E = (uint64_t)p->lights * 3;
        s->mean = prw_mul_sat(p->views, E), s->basis = prw_mul_sat(prw_mul_sat(p->views, k), E),
        s->w = prw_mul_sat(prw_mul_sat(p->views, N), k);
        return k >= 1 && p->clusters == p->views;
    }
    }
    return false;
}

uint64_t prw_btf_packed_bytes(const prw_btf_packed *p)
{
    sizes s;
    sizes_of(p, &s);
    uint64_t b = 8 + 9 * 4 + 8 * ((uint64_t)p->views + p->lights) + (p->has_average ? AVG_BYTES : 0);
    return prw_add_sat(prw_add_sat(b, s.sparse_bytes),
                       prw_add_sat(prw_mul_sat(prw_add_sat(prw_add_sat(s.u, s.w), prw_add_sat(s.mean, s.basis)), 2),
                                   prw_mul_sat(s.index, s.index_bytes)));
}

static void put(uint8_t **o, const void *src, size_t n)
{
    memcpy(*o, src, n);
    *o += n;
}

static void put_u32(uint8_t **o, uint32_t v)
{
    uint8_t b[4] = {(uint8_t)v, (uint8_t)(v >> 8), (uint8_t)(v >> 16), (uint8_t)(v >> 24)};
    put(o, b, 4);
}

static void put_halves(uint8_t **o, const uint16_t *h, uint64_t n)
{
    for (uint64_t i = 0; i < n; i++) {
        uint8_t b[2] = {(uint8_t)h[i], (uint8_t)(h[i] >> 8)};
        put(o, b, 2);
    }
}

bool prw_btf_packed_write(const char *path, const prw_btf_packed *p, prw_error *e)
{
    sizes s;
    if (!sizes_of(p, &s)) return prw_fail(e, "%s: not a consistent compressed BTF (codec %d)", path, (int)p->codec);
    uint64_t bytes = prw_btf_packed_bytes(p);
    if (!prw_mem_check(bytes, path, "the compressed BTF file", e)) return false;
    uint8_t *buf = prw_malloc((size_t)bytes), *o = buf;
    put(&o, MAGIC, 8);
    uint32_t hdr[9] = {p->has_average ? 2u : 1u, (uint32_t)p->codec, p->width, p->height, p->views, p->lights, p->components, p->clusters, 0};
    for (int i = 0; i < 8; i++) put_u32(&o, hdr[i]);
    put_u32(&o, 0); /* reserved */
    for (uint64_t i = 0; i < 2 * (uint64_t)p->views; i++) {
        uint32_t u;
        memcpy(&u, &p->view_dirs[i], 4);
        put_u32(&o, u);
    }
    for (uint64_t i = 0; i < 2 * (uint64_t)p->lights; i++) {
        uint32_t u;
        memcpy(&u, &p->light_dirs[i], 4);
        put_u32(&o, u);
    }
    if (p->codec == PRW_BTF_CODEC_FMF) {
        put_halves(&o, p->u, s.u);
        put_halves(&o, p->w, s.w);
    } else if (p->codec == PRW_BTF_CODEC_SPARSE) {
        put_u32(&o, p->sparse_count);
        for (uint64_t i = 0; i < s.index; i++) put_halves(&o, &(uint16_t){(uint16_t)p->index[i]}, 1);
        put_halves(&o, p->mean, s.mean);
        put_halves(&o, p->basis, s.basis);
        put_halves(&o, p->w, s.w);
        for (uint64_t t = 0; t < s.index; t++) put_halves(&o, &(uint16_t){(uint16_t)(p->sp_start[t + 1] - p->sp_start[t])}, 1);
        put_halves(&o, p->sp_pair, p->sparse_count);
        put_halves(&o, p->sp_val, 3 * (uint64_t)p->sparse_count);
    } else {
        for (uint64_t i = 0; i < s.index; i++) put_u32(&o, p->index[i]);
        put_halves(&o, p->mean, s.mean);
        put_halves(&o, p->basis, s.basis);
        put_halves(&o, p->w, s.w);
    }
    if (p->has_average) {
        const float *av = p->average.base;
        float f[7] = {av[0], av[1], av[2], p->average.metallic, p->average.roughness, p->average.specular, p->average.rms_pct};
        for (int i = 0; i < 7; i++) {
            uint32_t u;
            memcpy(&u, &f[i], 4);
            put_u32(&o, u);
        }
    }
    bool ok = prw_write_file_atomic(path, buf, (size_t)bytes, e);
    free(buf);
    return ok;
}

typedef btf_cur cur;

static uint32_t get_u32(cur *c)
{
    uint32_t v = prw_btf_le32(c->p + c->at);
    c->at += 4;
    return v;
}

static void u16s(cur *c, uint16_t *dst, uint64_t n)
{
    for (uint64_t i = 0; i < n; i++, c->at += 2) dst[i] = (uint16_t)(c->p[c->at] | (c->p[c->at + 1] << 8));
}

static bool halves(cur *c, uint16_t **dst, uint64_t n, const char *what)
{
    if (!btf_cur_need(c, n, 2, what)) return false;
    *dst = prw_malloc(n ? (size_t)n * 2 : 2);
    for (uint64_t i = 0; i < n; i++) {
        uint16_t h = (uint16_t)(c->p[c->at] | (c->p[c->at + 1] << 8));
        if ((h & 0x7c00u) == 0x7c00u) return btf_cur_fail(c, what, "element %llu is not finite", (unsigned long long)i);
        (*dst)[i] = h;
        c->at += 2;
    }
    return true;
}

bool prw_btf_packed_read_memory(const void *data, size_t size, const char *name, prw_btf_packed *out, prw_error *e)
{
    memset(out, 0, sizeof *out);
    cur c = {.p = data, .n = size, .name = name ? name : "(btf)", .e = e};
    bool ok = btf_cur_need(&c, 1, 8 + 9 * 4, "header");
    if (ok && memcmp(c.p, MAGIC, 8) != 0) ok = btf_cur_fail(&c, "signature", "not a prw compressed BTF (PRWBTFC1)");
    if (ok) {
        c.at = 8;
        uint32_t version = get_u32(&c);
        out->codec = (prw_btf_codec)get_u32(&c);
        out->width = get_u32(&c), out->height = get_u32(&c), out->views = get_u32(&c), out->lights = get_u32(&c);
        out->components = get_u32(&c), out->clusters = get_u32(&c);
        uint32_t reserved = get_u32(&c);
        out->has_average = version == 2;
        if (reserved != 0) ok = btf_cur_fail(&c, "reserved", "%u where version 1 has 0", reserved);
        else if (version != 1 && version != 2) ok = btf_cur_fail(&c, "version", "version %u (this reader knows 1 and 2)", version);
        else if (out->codec < PRW_BTF_CODEC_FMF || out->codec > PRW_BTF_CODEC_SPARSE)
            ok = btf_cur_fail(&c, "codec", "unknown codec %d", (int)out->codec);
        else if (!out->width || !out->height || !out->views || !out->lights || out->width > PRW_BTF_UBO_MAX_SIDE ||
                 out->height > PRW_BTF_UBO_MAX_SIDE || out->views > PRW_BTF_UBO_MAX_DIRS || out->lights > PRW_BTF_UBO_MAX_DIRS)
            ok = btf_cur_fail(&c, "size", "%u x %u texels, %u views, %u lights", out->width, out->height, out->views, out->lights);
    }
    uint64_t dirs_end = 8 + 9 * 4 + 8 * ((uint64_t)out->views + out->lights);
    if (ok && out->codec == PRW_BTF_CODEC_SPARSE) { /* M leads the codec's arrays */
        if (c.n < dirs_end + 4) ok = btf_cur_fail(&c, "residual count", "the file ends before it");
        else out->sparse_count = prw_btf_le32(c.p + dirs_end);
    }
    sizes s;
    if (ok && !sizes_of(out, &s))
        ok = btf_cur_fail(&c, "codec", "%u components, %u clusters do not fit codec %d", out->components, out->clusters,
                     (int)out->codec);
    /* the decode (prw_btf_decode.h) indexes with 32 bits, the GPU's */
    if (ok && (s.u > UINT32_MAX || s.w > UINT32_MAX || s.mean > UINT32_MAX || s.basis > UINT32_MAX || s.index > UINT32_MAX ||
               3ull * out->sparse_count > UINT32_MAX))
        ok = btf_cur_fail(&c, "size", "an array of more than 2^32 elements (the decode indexes with 32 bits)");
    if (ok) {
        uint64_t all = prw_add_sat(prw_mul_sat(prw_add_sat(prw_add_sat(s.u, s.w), prw_add_sat(s.mean, s.basis)), 2),
                                   prw_add_sat(prw_mul_sat(s.index, s.index_bytes), prw_mul_sat(8, (uint64_t)out->views + out->lights)));
        all = prw_add_sat(all, s.sparse_bytes);
        ok = btf_cur_need(&c, all, 1, "data") && prw_mem_check(all, c.name, "the compressed BTF", e);
    }
    if (ok) {
        out->view_dirs = prw_malloc(sizeof(float) * 2 * out->views);
        out->light_dirs = prw_malloc(sizeof(float) * 2 * out->lights);
        for (uint64_t i = 0; i < 2 * (uint64_t)out->views; i++) {
            uint32_t u = get_u32(&c);
            memcpy(&out->view_dirs[i], &u, 4);
        }
        for (uint64_t i = 0; i < 2 * (uint64_t)out->lights; i++) {
            uint32_t u = get_u32(&c);
            memcpy(&out->light_dirs[i], &u, 4);
        }
        for (uint64_t i = 0; ok && i < 2 * (uint64_t)out->views; i++)
            if (!isfinite(out->view_dirs[i])) ok = btf_cur_fail(&c, "view directions", "direction %llu is not finite", (unsigned long long)i / 2);
        for (uint64_t i = 0; ok && i < 2 * (uint64_t)out->lights; i++)
            if (!isfinite(out->light_dirs[i])) ok = btf_cur_fail(&c, "light directions", "direction %llu is not finite", (unsigned long long)i / 2);
    }
    if (ok && out->codec == PRW_BTF_CODEC_FMF) {
        ok = halves(&c, &out->u, s.u, "U") && halves(&c, &out->w, s.w, "W");
    } else if (ok && out->codec == PRW_BTF_CODEC_SPARSE) {
        uint64_t N = s.index, M = out->sparse_count, P = (uint64_t)out->views * out->lights;
        c.at += 4;
        out->index = prw_malloc(sizeof(uint32_t) * (size_t)N);
        for (uint64_t i = 0; ok && i < N; i++, c.at += 2) {
            out->index[i] = (uint32_t)(c.p[c.at] | (c.p[c.at + 1] << 8));
            if (out->index[i] >= out->clusters)
                ok = btf_cur_fail(&c, "cluster index", "texel %llu: cluster %u of %u", (unsigned long long)i, out->index[i], out->clusters);
        }
        if (ok) ok = halves(&c, &out->mean, s.mean, "means") && halves(&c, &out->basis, s.basis, "bases") &&
                     halves(&c, &out->w, s.w, "weights");
        if (ok) {
            out->sp_start = prw_malloc(sizeof(uint32_t) * (size_t)(N + 1));
            out->sp_start[0] = 0;
            for (uint64_t t = 0; ok && t < N; t++, c.at += 2) {
                uint64_t next = (uint64_t)out->sp_start[t] + (uint32_t)(c.p[c.at] | (c.p[c.at + 1] << 8));
                if (next > M) ok = btf_cur_fail(&c, "residual counts", "texel %llu: more than the %llu entries", (unsigned long long)t, (unsigned long long)M);
                else out->sp_start[t + 1] = (uint32_t)next;
            }
            if (ok && out->sp_start[N] != M)
                ok = btf_cur_fail(&c, "residual counts", "they sum to %u, not %llu", out->sp_start[N], (unsigned long long)M);
        }
        if (ok) {
            out->sp_pair = prw_malloc(sizeof(uint16_t) * (size_t)(M ? M : 1));
            u16s(&c, out->sp_pair, M);
            for (uint64_t t = 0; ok && t < N; t++)
                for (uint32_t j = out->sp_start[t]; ok && j < out->sp_start[t + 1]; j++)
                    if (out->sp_pair[j] >= P || (j > out->sp_start[t] && out->sp_pair[j] <= out->sp_pair[j - 1]))
                        ok = btf_cur_fail(&c, "residual pairs", "texel %llu entry %u: pair %u out of range or order", (unsigned long long)t,
                                          j, out->sp_pair[j]);
        }
        if (ok) ok = halves(&c, &out->sp_val, 3 * M, "residuals");
    } else if (ok) {
        out->index = prw_malloc(sizeof(uint32_t) * (size_t)(s.index ? s.index : 1));
        for (uint64_t i = 0; ok && i < s.index; i++) {
            out->index[i] = get_u32(&c);
            if (out->index[i] >= out->clusters)
                ok = btf_cur_fail(&c, "cluster index", "texel %llu: cluster %u of %u", (unsigned long long)i, out->index[i], out->clusters);
        }
        if (ok) ok = halves(&c, &out->mean, s.mean, "means") && halves(&c, &out->basis, s.basis, "bases") &&
                     halves(&c, &out->w, s.w, "weights");
    }
    if (ok && out->has_average && (ok = btf_cur_need(&c, 7, 4, "average"))) {
        float f[7];
        for (int i = 0; i < 7; i++) {
            uint32_t u = get_u32(&c);
            memcpy(&f[i], &u, 4);
        }
        bool in = true;
        for (int i = 0; i < 6; i++) in = in && f[i] >= 0 && f[i] <= 1;
        if (!in || !(f[6] >= 0 && f[6] <= 1e6))
            ok = btf_cur_fail(&c, "average", "base, metallic, roughness, specular outside [0, 1] or a bad rms");
        memcpy(out->average.base, f, sizeof(float) * 3);
        out->average.metallic = f[3], out->average.roughness = f[4], out->average.specular = f[5], out->average.rms_pct = f[6];
    }
    if (ok && c.at != c.n) ok = btf_cur_fail(&c, "end", "%zu bytes after the data", c.n - c.at);
    if (!ok) prw_btf_packed_free(out);
    return ok;
}

bool prw_btf_packed_read(const char *path, prw_btf_packed *out, prw_error *e)
{
    memset(out, 0, sizeof *out);
    char *data = NULL;
    size_t size = 0;
    if (!prw_read_file_bounded(path, 0, 1, "a compressed BTF", &data, &size, e)) return false;
    bool ok = prw_btf_packed_read_memory(data, size, path, out, e);
    free(data);
    return ok;
}
