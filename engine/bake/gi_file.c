/* gi_file.c — the light-map file and its cache entry (prw_gi.h).
 *
 * File (little-endian), version 2 (1 had no visibility):
 *   0   char[8]  "PRWGI001"
 *   8   u32      version (2);  12 u32 header size (72)
 *   16  char[32] cache key (hex; zeros when none)
 *   48  f64      texel size (metres);  56 u32 samples;  60 u32 atlas count;  64 u32 instance count;
 *   68  u32      reserved (0)
 *   72  atlases:   u32 width, u32 height, f32 rgb[3 w h], f32 var[3 w h], f32 vis[w h] (in [0, 1]),
 *                  f32 cone[4 w h] (b finite, f in [0, 1]), u8 state[w h]
 *       instances: u32 node, mesh, mode, atlas, triangle count, vertex count;
 *                  ATLAS: f32 uv[6 triangles];  VERTEX: f32 rgb[3 vertices], f32 var[3 vertices], f32 vis[vertices],
 *                  f32 cone[4 vertices]
 *   end u64      prw_hash64 (seed 0) of every byte before it
 * The reader checks each count against its limit and the bytes left before it allocates, refuses
 * non-finite or negative values, unknown modes and states, and trailing bytes. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "bake_entry.h"
#include "prw_cache.h"
#include "prw_gi.h"
#include "prw_reference.h"

#define GI_VERSION 2u
#define GI_HDR 72u
#define MAX_SIDE 4096u
#define MAX_INSTANCES (1u << 20)
#define MAX_ELEMS (1u << 26)
static const char k_magic[8] = {'P', 'R', 'W', 'G', 'I', '0', '0', '1'};

/* ---- content hash and key ---- */

typedef struct hasher {
    uint64_t h;
} hasher;
static void hadd(hasher *x, const void *p, size_t n) { x->h = prw_hash64(p, n, x->h); }
static void hu64(hasher *x, uint64_t v) { hadd(x, &v, 8); }
static void hf64(hasher *x, double v) { hadd(x, &v, 8); }
static void hf32(hasher *x, float v) { hadd(x, &v, 4); }

static void hash_material(hasher *x, const prw_material *m)
{
    hu64(x, (uint64_t)m->kind);
    for (int c = 0; c < 4; c++) hf32(x, m->base_color[c]);
    hu64(x, (uint64_t)(int64_t)m->base_color_tex);
    hf32(x, m->metallic), hf32(x, m->roughness), hf32(x, m->specular);
    hu64(x, (uint64_t)(int64_t)m->metal_rough_tex), hu64(x, (uint64_t)(int64_t)m->normal_tex);
    hf32(x, m->normal_scale);
    for (int c = 0; c < 3; c++) hf32(x, m->emission[c]);
    hu64(x, (uint64_t)(int64_t)m->emissive_tex);
    hu64(x, m->double_sided), hu64(x, (uint64_t)m->alpha_mode);
    hf32(x, m->alpha_cutoff);
    for (int sl = 0; sl < PRW_TEX_SLOT_COUNT; sl++) {
        const prw_tex_transform *t = &m->tex_xf[sl];
        hf32(x, t->offset[0]), hf32(x, t->offset[1]), hf32(x, t->rotation), hf32(x, t->scale[0]), hf32(x, t->scale[1]);
        hu64(x, (uint64_t)(int64_t)t->tex_coord);
    }
    hf32(x, m->clearcoat), hf32(x, m->clearcoat_roughness), hf32(x, m->clearcoat_normal_scale);
    hu64(x, (uint64_t)(int64_t)m->clearcoat_tex), hu64(x, (uint64_t)(int64_t)m->clearcoat_roughness_tex);
    hu64(x, (uint64_t)(int64_t)m->clearcoat_normal_tex);
}

uint64_t prw_gi_content_hash(const prw_scene *s)
{
    hasher x = {0x6769626b65ull};
    for (uint32_t n = 0; n < s->node_count; n++) {
        const prw_node *nd = &s->nodes[n];
        if (nd->mesh_group < 0 && nd->light < 0) continue;
        hu64(&x, n);
        hadd(&x, nd->world.m, sizeof nd->world.m);
        if (nd->mesh_group >= 0) {
            const prw_mesh_group *g = &s->groups[nd->mesh_group];
            for (uint32_t mi = g->first; mi < g->first + g->count; mi++) {
                const prw_mesh *m = &s->meshes[mi];
                hu64(&x, mi), hu64(&x, m->vertex_count), hu64(&x, m->index_count), hu64(&x, (uint64_t)m->material);
                hadd(&x, m->positions, (size_t)m->vertex_count * 12);
                hadd(&x, m->normals, (size_t)m->vertex_count * 12);
                hadd(&x, m->uvs, (size_t)m->vertex_count * 8);
                if (m->tangents) hadd(&x, m->tangents, (size_t)m->vertex_count * 16);
                if (m->uvs1) hadd(&x, m->uvs1, (size_t)m->vertex_count * 8);
                hadd(&x, m->indices, (size_t)m->index_count * 4);
            }
        }
    }
    for (uint32_t i = 0; i < s->material_count; i++) hash_material(&x, &s->materials[i]);
    for (uint32_t i = 0; i < s->texture_count; i++) {
        const prw_texture *t = &s->textures[i];
        hu64(&x, (uint64_t)t->width), hu64(&x, (uint64_t)t->height), hu64(&x, t->srgb);
        if (t->rgba8) hadd(&x, t->rgba8, (size_t)t->width * t->height * 4);
    }
    for (uint32_t i = 0; i < s->light_count; i++) {
        const prw_light *l = &s->lights[i];
        hu64(&x, (uint64_t)l->type);
        for (int c = 0; c < 3; c++) hf32(&x, l->color[c]);
        hf64(&x, l->intensity), hf64(&x, l->range), hf64(&x, l->inner_cone), hf64(&x, l->outer_cone);
        hf64(&x, l->width), hf64(&x, l->height), hu64(&x, l->cast_shadows);
        if (l->node >= 0 && (uint32_t)l->node < s->node_count)
            hadd(&x, s->nodes[l->node].world.m, sizeof s->nodes[l->node].world.m);
    }
    const prw_environment *en = &s->environment;
    hu64(&x, en->present);
    if (en->present) {
        hu64(&x, en->file_hash), hu64(&x, en->file[0] != 0), hf64(&x, en->scale), hf64(&x, en->rotation);
        for (int c = 0; c < 3; c++) hf32(&x, en->uniform[c]);
    }
    for (uint32_t i = 0; i < s->nurbs_count; i++) { /* they occlude and reflect in the gather */
        const prw_scene_nurbs *nb = &s->nurbs[i];
        hadd(&x, nb->file, strlen(nb->file)), hadd(&x, nb->procedural, strlen(nb->procedural));
        hu64(&x, (uint64_t)nb->material), hu64(&x, (uint64_t)nb->grid[0]), hu64(&x, (uint64_t)nb->grid[1]);
        hf64(&x, nb->spacing[0]), hf64(&x, nb->spacing[1]), hf64(&x, nb->chord_rel), hf64(&x, nb->finest_rel);
        if (nb->node >= 0 && (uint32_t)nb->node < s->node_count)
            hadd(&x, s->nodes[nb->node].world.m, sizeof s->nodes[nb->node].world.m);
    }
    return x.h;
}

void prw_gi_key(const prw_scene *s, const prw_gi_options *o, char key[33])
{
    prw_cache_key k;
    prw_cache_key_begin(&k, "prw-gi-key");
    prw_cache_key_add_str(&k, PRW_GI_ALGO_VERSION);
    prw_cache_key_add_u64(&k, GI_VERSION);
    prw_cache_key_add_u64(&k, o->radiosity_size ? o->radiosity_size : PRW_GI_DEFAULT_RADIOSITY_SIZE);
    prw_cache_key_add_u64(&k, o->samples ? o->samples : PRW_GI_DEFAULT_SAMPLES);
    prw_cache_key_add_u64(&k, o->seed);
    prw_cache_key_add_u64(&k, o->filter_radius);
    prw_cache_key_add_u64(&k, prw_ref_material_hash());
    prw_cache_key_add_u64(&k, prw_gi_content_hash(s));
    prw_cache_key_finish(&k, NULL, 0, key);
}

/* ---- encoding ---- */

typedef struct wbuf {
    uint8_t *p;
    size_t n, cap;
} wbuf;
static void wput(wbuf *w, const void *d, size_t n)
{
    if (w->n + n > w->cap) {
        while (w->n + n > w->cap) w->cap = w->cap ? 2 * w->cap : 4096;
        w->p = realloc(w->p, w->cap);
        if (!w->p) abort();
    }
    memcpy(w->p + w->n, d, n);
    w->n += n;
}
static void w32(wbuf *w, uint32_t v)
{
    uint8_t b[4];
    for (int i = 0; i < 4; i++) b[i] = (uint8_t)(v >> (8 * i));
    wput(w, b, 4);
}
static void w64(wbuf *w, uint64_t v)
{
    uint8_t b[8];
    for (int i = 0; i < 8; i++) b[i] = (uint8_t)(v >> (8 * i));
    wput(w, b, 8);
}
static void wf32s(wbuf *w, const float *f, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        uint32_t u;
        memcpy(&u, &f[i], 4);
        w32(w, u);
    }
}

bool prw_gi_encode(const prw_gi_bake *b, const char *key, uint8_t **data, size_t *size, prw_error *e)
{
    (void)e;
    wbuf w = {0};
    wput(&w, k_magic, 8);
    w32(&w, GI_VERSION), w32(&w, GI_HDR);
    char k[32] = {0};
    if (key) memcpy(k, key, strnlen(key, 32));
    wput(&w, k, 32);
    uint64_t tb;
    memcpy(&tb, &b->texel_size, 8);
    w64(&w, tb);
    w32(&w, b->samples), w32(&w, b->atlas_count), w32(&w, b->instance_count), w32(&w, 0);
    for (uint32_t a = 0; a < b->atlas_count; a++) {
        const prw_gi_atlas *A = &b->atlases[a];
        size_t t = (size_t)A->width * A->height;
        w32(&w, A->width), w32(&w, A->height);
        wf32s(&w, A->rgb, 3 * t);
        wf32s(&w, A->var, 3 * t);
        wf32s(&w, A->vis, t);
        wf32s(&w, A->cone, 4 * t);
        wput(&w, A->state, t);
    }
    for (uint32_t i = 0; i < b->instance_count; i++) {
        const prw_gi_instance *in = &b->inst[i];
        w32(&w, in->node), w32(&w, in->mesh), w32(&w, in->mode), w32(&w, in->atlas);
        w32(&w, in->mode == PRW_GI_ATLAS ? in->triangle_count : 0);
        w32(&w, in->mode == PRW_GI_VERTEX ? in->vertex_count : 0);
        if (in->mode == PRW_GI_ATLAS) wf32s(&w, in->uv, (size_t)in->triangle_count * 6);
        if (in->mode == PRW_GI_VERTEX) {
            wf32s(&w, in->vertex_rgb, (size_t)in->vertex_count * 3);
            wf32s(&w, in->vertex_var, (size_t)in->vertex_count * 3);
            wf32s(&w, in->vertex_vis, in->vertex_count);
            wf32s(&w, in->vertex_cone, (size_t)in->vertex_count * 4);
        }
    }
    w64(&w, prw_hash64(w.p, w.n, 0));
    *data = w.p;
    *size = w.n;
    return true;
}

/* ---- strict reader ---- */

typedef struct rbuf {
    const uint8_t *p;
    size_t n, at;
    const char *name;
    prw_error *e;
} rbuf;

static bool need(rbuf *r, uint64_t n, const char *what)
{
    if (n > r->n - r->at) return prw_fail(r->e, "%s: truncated at byte %zu (%s needs %llu bytes, %zu left)", r->name, r->at,
                                         what, (unsigned long long)n, r->n - r->at);
    return true;
}
static uint32_t r32(rbuf *r)
{
    uint32_t v = 0;
    for (int i = 0; i < 4; i++) v |= (uint32_t)r->p[r->at + i] << (8 * i);
    r->at += 4;
    return v;
}
static uint64_t r64(rbuf *r)
{
    uint64_t v = 0;
    for (int i = 0; i < 8; i++) v |= (uint64_t)r->p[r->at + i] << (8 * i);
    r->at += 8;
    return v;
}
/* n floats, finite (and >= 0 when nonneg); the caller checked the bytes. */
static bool rf32s(rbuf *r, float *out, size_t n, bool nonneg, const char *what)
{
    for (size_t i = 0; i < n; i++) {
        uint32_t u = r32(r);
        memcpy(&out[i], &u, 4);
        if (!isfinite(out[i]) || (nonneg && out[i] < 0))
            return prw_fail(r->e, "%s: %s: value %zu is %s", r->name, what, i, isfinite(out[i]) ? "negative" : "not finite");
    }
    return true;
}

/* visibilities are fractions */
static bool vis_in_range(rbuf *r, const float *v, size_t n, const char *what)
{
    for (size_t i = 0; i < n; i++)
        if (v[i] > 1.0f) return prw_fail(r->e, "%s: %s: visibility %zu is %g (0..1)", r->name, what, i, v[i]);
    return true;
}

/* open cones: |b| <= 1 (a mean of unit vectors) up to rounding, f a fraction */
static bool cone_in_range(rbuf *r, const float *c, size_t n, const char *what)
{
    for (size_t i = 0; i < n; i++) {
        const float *q = c + 4 * i;
        if (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] > 1.0001f || q[3] < 0.0f || q[3] > 1.0f)
            return prw_fail(r->e, "%s: %s: open cone %zu (%g %g %g, %g) out of range", r->name, what, i, q[0], q[1],
                            q[2], q[3]);
    }
    return true;
}

bool prw_gi_decode(const void *data, size_t size, const char *name, prw_gi_bake **out, char key[33], prw_error *e)
{
    *out = NULL;
    rbuf r = {data, size, 0, name, e};
    if (size < GI_HDR + 8 || memcmp(data, k_magic, 8) != 0)
        return prw_fail(e, "%s: not a prw light-map file (PRWGI001)", name);
    uint64_t sum = 0;
    for (int i = 0; i < 8; i++) sum |= (uint64_t)r.p[size - 8 + i] << (8 * i);
    if (sum != prw_hash64(data, size - 8, 0)) return prw_fail(e, "%s: checksum mismatch (damaged file)", name);
    r.n = size - 8;
    r.at = 8;
    uint32_t ver = r32(&r), hdr = r32(&r);
    if (ver != GI_VERSION || hdr != GI_HDR) return prw_fail(e, "%s: version %u / header size %u (expected %u / %u)", name, ver, hdr, GI_VERSION, GI_HDR);
    bool zeros = true, hex = true;
    for (int i = 0; i < 32; i++) {
        uint8_t ch = r.p[r.at + i];
        zeros = zeros && ch == 0;
        hex = hex && ((ch >= '0' && ch <= '9') || (ch >= 'a' && ch <= 'f'));
    }
    if (!zeros && !hex) return prw_fail(e, "%s: header: the cache key is not 32 lowercase hex digits", name);
    if (key) {
        memcpy(key, r.p + r.at, 32);
        key[32] = 0;
    }
    r.at += 32;
    uint64_t tb = r64(&r);
    double texel;
    memcpy(&texel, &tb, 8);
    uint32_t samples = r32(&r), na = r32(&r), ni = r32(&r), reserved = r32(&r);
    if (reserved != 0) return prw_fail(e, "%s: header: reserved field is %u (must be 0)", name, reserved);
    if (!(isfinite(texel) && texel > 0)) return prw_fail(e, "%s: header: texel size is not a positive number", name);
    if (samples < 1 || samples > 65536) return prw_fail(e, "%s: header: samples %u outside 1..65536", name, samples);
    if (na > PRW_GI_MAX_ATLASES) return prw_fail(e, "%s: header: %u atlases (at most %d)", name, na, PRW_GI_MAX_ATLASES);
    if (ni > MAX_INSTANCES) return prw_fail(e, "%s: header: %u instances (at most %u)", name, ni, MAX_INSTANCES);
    /* every instance needs 24 bytes at least, every atlas 8 */
    if (!need(&r, (uint64_t)na * 8 + (uint64_t)ni * 24, "the atlas and instance records")) return false;
    prw_gi_bake *b = prw_calloc(1, sizeof *b);
    b->texel_size = texel;
    b->samples = samples;
    b->atlases = prw_calloc(na ? na : 1, sizeof *b->atlases);
    b->inst = prw_calloc(ni ? ni : 1, sizeof *b->inst);
    bool ok = true;
    for (uint32_t a = 0; a < na && ok; a++) {
        char what[64];
        snprintf(what, sizeof what, "atlas %u", a);
        if (!(ok = need(&r, 8, what))) break;
        uint32_t w = r32(&r), h = r32(&r);
        if (w < 1 || h < 1 || w > MAX_SIDE || h > MAX_SIDE) {
            ok = prw_fail(e, "%s: atlas %u: size %ux%u outside 1..%u", name, a, w, h, MAX_SIDE);
            break;
        }
        size_t t = (size_t)w * h;
        if (!(ok = need(&r, (uint64_t)t * 45, what))) break;
        prw_gi_atlas *A = &b->atlases[b->atlas_count++];
        A->width = w, A->height = h;
        A->rgb = prw_calloc(3 * t, sizeof(float));
        A->var = prw_calloc(3 * t, sizeof(float));
        A->vis = prw_calloc(t, sizeof(float));
        A->cone = prw_calloc(4 * t, sizeof(float));
        A->state = prw_calloc(t, 1);
        ok = rf32s(&r, A->rgb, 3 * t, true, what) && rf32s(&r, A->var, 3 * t, true, what) &&
             rf32s(&r, A->vis, t, true, what) && vis_in_range(&r, A->vis, t, what) &&
             rf32s(&r, A->cone, 4 * t, false, what) && cone_in_range(&r, A->cone, t, what);
        if (!ok) break;
        memcpy(A->state, r.p + r.at, t);
        r.at += t;
        for (size_t i = 0; i < t && ok; i++)
            if (A->state[i] > 2) ok = prw_fail(e, "%s: atlas %u: texel %zu has state %u (0..2)", name, a, i, A->state[i]);
    }
    for (uint32_t i = 0; i < ni && ok; i++) {
        char what[64];
        snprintf(what, sizeof what, "instance %u", i);
        if (!(ok = need(&r, 24, what))) break;
        prw_gi_instance *in = &b->inst[b->instance_count++];
        in->node = r32(&r), in->mesh = r32(&r), in->mode = r32(&r), in->atlas = r32(&r);
        uint32_t nt = r32(&r), nv = r32(&r);
        if (in->mode > PRW_GI_VERTEX) {
            ok = prw_fail(e, "%s: instance %u: unknown mode %u", name, i, in->mode);
            break;
        }
        if (nt > MAX_ELEMS || nv > MAX_ELEMS || (in->mode != PRW_GI_ATLAS && nt) || (in->mode != PRW_GI_VERTEX && nv) ||
            (in->mode == PRW_GI_ATLAS && in->atlas >= b->atlas_count)) {
            ok = prw_fail(e, "%s: instance %u: counts (%u triangles, %u vertices, atlas %u) do not fit its mode %u", name,
                          i, nt, nv, in->atlas, in->mode);
            break;
        }
        if (in->mode == PRW_GI_ATLAS) {
            if (!(ok = need(&r, (uint64_t)nt * 24, what))) break;
            in->triangle_count = nt;
            in->uv = prw_calloc((size_t)nt * 6 + 1, sizeof(float));
            ok = rf32s(&r, in->uv, (size_t)nt * 6, false, what);
        } else if (in->mode == PRW_GI_VERTEX) {
            if (!(ok = need(&r, (uint64_t)nv * 44, what))) break;
            in->vertex_count = nv;
            in->vertex_rgb = prw_calloc((size_t)nv * 3 + 1, sizeof(float));
            in->vertex_var = prw_calloc((size_t)nv * 3 + 1, sizeof(float));
            in->vertex_vis = prw_calloc((size_t)nv + 1, sizeof(float));
            in->vertex_cone = prw_calloc((size_t)nv * 4 + 1, sizeof(float));
            ok = rf32s(&r, in->vertex_rgb, (size_t)nv * 3, true, what) && rf32s(&r, in->vertex_var, (size_t)nv * 3, true, what) &&
                 rf32s(&r, in->vertex_vis, nv, true, what) && vis_in_range(&r, in->vertex_vis, nv, what) &&
                 rf32s(&r, in->vertex_cone, (size_t)nv * 4, false, what) && cone_in_range(&r, in->vertex_cone, nv, what);
        }
    }
    if (ok && r.at != r.n) ok = prw_fail(e, "%s: %zu bytes after the last instance", name, r.n - r.at);
    if (!ok) {
        prw_gi_bake_destroy(b);
        return false;
    }
    *out = b;
    return true;
}

/* ---- cache ---- */

bool prw_gi_run(const prw_scene *s, const prw_gi_options *o, bool no_cache, prw_gi_progress_fn progress,
                void *user, prw_gi_bake **out, prw_gi_result *res, prw_error *e)
{
    memset(res, 0, sizeof *res);
    *out = NULL;
    double t0 = prw_now();
    prw_gi_key(s, o, res->key);
    if (!no_cache) {
        char *data = NULL;
        size_t n = 0;
        if (prw_bake_entry_read(PRW_GI_CACHE_KIND, res->key, "gi", res->cache_path, sizeof res->cache_path, &data, &n,
                                res->warning, sizeof res->warning)) {
            prw_error ce = {{0}};
            char k[33];
            prw_gi_bake *b = NULL;
            if (prw_gi_decode(data, n, res->cache_path, &b, k, &ce) && strcmp(k, res->key) == 0) {
                free(data);
                res->cache_hit = true;
                res->seconds_total = prw_now() - t0;
                *out = b;
                return true;
            }
            if (b) {
                snprintf(ce.msg, sizeof ce.msg, "%.900s holds another key", res->cache_path);
                prw_gi_bake_destroy(b);
            }
            free(data);
            prw_bake_entry_rejected(&ce, res->warning, sizeof res->warning);
        }
    }
    prw_gi_bake *b = NULL;
    if (!prw_gi_build(s, o, progress, user, &b, e)) return false;
    res->built = true;
    if (!no_cache && res->cache_path[0]) {
        uint8_t *data = NULL;
        size_t n = 0;
        prw_error we = {{0}};
        if (prw_gi_encode(b, res->key, &data, &n, &we))
            res->cache_written = prw_bake_entry_store(PRW_GI_CACHE_KIND, res->key, "gi", data, n, res->cache_path,
                                                      sizeof res->cache_path, res->warning, sizeof res->warning);
        else
            snprintf(res->warning, sizeof res->warning, "cache not written: %.900s", we.msg);
        free(data);
    }
    if (no_cache) res->cache_path[0] = 0;
    res->seconds_total = prw_now() - t0;
    *out = b;
    return true;
}
