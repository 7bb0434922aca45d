/* probe_bake.c — the reflection-probe baker, its file and cache entry (prw_probe.h).
 *
 * File (little-endian), version 1:
 *   0   char[8]  "PRWPRB01"
 *   8   u32      version (1);  12 u32 count;  16 u32 size;  20 u32 samples;  24 u32 levels;  28 u32 level height
 *   32  char[32] cache key (hex; zeros when none)
 *   64  f64[6]   parallax box min, max
 *   112 probes:  u32 node, mesh; i32 material; u32 reserved; f64 centre[3], box_min[3], box_max[3], tnear
 *       f32      levels_rgb (count x levels x H x 2H x 3; finite, >= 0)
 *   end u64      prw_hash64 (seed 0) of every byte before it
 */
#define _POSIX_C_SOURCE 200809L
#include "prw_probe.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "bake_entry.h"
#include "prw_cache.h"
#include "prw_env.h"
#include "prw_gi.h"
#include "prw_math.h"
#include "prw_reference.h"

#define PROBE_VERSION 1u
#define PROBE_HDR 112u
#define PROBE_REC 96u
#define PLANARITY 1e-3
static const char k_magic[8] = {'P', 'R', 'W', 'P', 'R', 'B', '0', '1'};

void prw_probe_bake_destroy(prw_probe_bake *b)
{
    if (!b) return;
    free(b->levels_rgb);
    free(b);
}

static uint32_t resolved_samples(const prw_probe_options *o) { return o->samples ? o->samples : PRW_PROBE_DEFAULT_SAMPLES; }
static double resolved_roughness(const prw_probe_options *o)
{
    return o->max_roughness > 0 ? o->max_roughness : PRW_PROBE_DEFAULT_MAX_ROUGHNESS;
}
static uint32_t level_height(uint32_t size) { return size / 2 > 4 ? size / 2 : 4; }

static bool wants_probe(const prw_material *m, double max_r)
{
    return m->kind == PRW_MATERIAL_GLTF_MR && m->alpha_mode == PRW_ALPHA_OPAQUE && m->clearcoat <= 0 &&
           (m->metallic > 0 || m->specular > 0) && m->roughness <= max_r;
}

/* World bounds of mesh k drawn by node nd, and whether its vertices are coplanar. */
static bool mesh_planar(const prw_node *nd, const prw_mesh *me, prw_dvec3 *lo, prw_dvec3 *hi)
{
    *lo = prw_v3(DBL_MAX, DBL_MAX, DBL_MAX), *hi = prw_v3(-DBL_MAX, -DBL_MAX, -DBL_MAX);
    prw_dvec3 n = prw_v3(0, 0, 0), p0 = prw_v3(0, 0, 0);
    double best = 0;
    for (uint32_t t = 0; t + 2 < me->index_count; t += 3) {
        prw_dvec3 p[3];
        for (int j = 0; j < 3; j++) {
            const float *q = &me->positions[3 * me->indices[t + j]];
            p[j] = prw_dm4_point(nd->world, prw_v3(q[0], q[1], q[2]));
            *lo = prw_v3_min(*lo, p[j]), *hi = prw_v3_max(*hi, p[j]);
        }
        prw_dvec3 c = prw_v3_cross(prw_v3_sub(p[1], p[0]), prw_v3_sub(p[2], p[0]));
        double a = prw_v3_len(c);
        if (a > best) best = a, n = prw_v3_scale(c, 1.0 / a), p0 = p[0];
    }
    if (best <= 0) return true;
    double tol = PLANARITY * fmax(prw_v3_len(prw_v3_sub(*hi, *lo)), 1e-9);
    for (uint32_t v = 0; v < me->vertex_count; v++) {
        const float *q = &me->positions[3 * v];
        prw_dvec3 p = prw_dm4_point(nd->world, prw_v3(q[0], q[1], q[2]));
        if (fabs(prw_v3_dot(n, prw_v3_sub(p, p0))) > tol) return false;
    }
    return true;
}

static double box_diag(const prw_probe_info *p)
{
    double d2 = 0;
    for (int c = 0; c < 3; c++) d2 += (p->box_max[c] - p->box_min[c]) * (p->box_max[c] - p->box_min[c]);
    return sqrt(d2);
}

void prw_probe_select(const prw_scene *s, const prw_probe_options *o, prw_probe_bake *b)
{
    b->count = 0;
    b->size = o->size;
    b->samples = resolved_samples(o);
    b->levels = PRW_PROBE_LEVELS;
    b->level_height = level_height(o->size);
    double lo[3] = {s->bounds_min.x, s->bounds_min.y, s->bounds_min.z};
    double hi[3] = {s->bounds_max.x, s->bounds_max.y, s->bounds_max.z};
    for (int c = 0; c < 3; c++) b->parallax_min[c] = s->has_bounds ? lo[c] : -1e6, b->parallax_max[c] = s->has_bounds ? hi[c] : 1e6;
    double max_r = resolved_roughness(o);
    prw_probe_info *cand = NULL;
    uint32_t nc = 0, cap = 0;
    uint32_t limit = o->count < PRW_PROBE_MAX ? o->count : PRW_PROBE_MAX;
    for (uint32_t ni = 0; ni < s->node_count && limit; ni++) {
        const prw_node *nd = &s->nodes[ni];
        if (nd->mesh_group < 0) continue;
        const prw_mesh_group *g = &s->groups[nd->mesh_group];
        for (uint32_t k = g->first; k < g->first + g->count; k++) {
            const prw_mesh *me = &s->meshes[k];
            if (me->material < 0 || (uint32_t)me->material >= s->material_count || me->index_count < 3) continue;
            if (!wants_probe(&s->materials[me->material], max_r)) continue;
            prw_dvec3 a, z;
            if (mesh_planar(nd, me, &a, &z)) continue; /* pass_mirror's */
            prw_probe_info p;
            memset(&p, 0, sizeof p);
            p.node = ni, p.mesh = k, p.material = me->material;
            double d = prw_v3_len(prw_v3_sub(z, a)), grow = 0.01 * d + 1e-3;
            double av[3] = {a.x, a.y, a.z}, zv[3] = {z.x, z.y, z.z};
            for (int c = 0; c < 3; c++) {
                p.centre[c] = 0.5 * (av[c] + zv[c]);
                p.box_min[c] = av[c] - grow, p.box_max[c] = zv[c] + grow;
            }
            double rmax = 0;
            for (uint32_t v = 0; v < me->vertex_count; v++) {
                const float *q = &me->positions[3 * v];
                prw_dvec3 w = prw_dm4_point(nd->world, prw_v3(q[0], q[1], q[2]));
                rmax = fmax(rmax, prw_v3_len(prw_v3_sub(w, prw_v3(p.centre[0], p.centre[1], p.centre[2]))));
            }
            p.tnear = s->materials[me->material].double_sided ? rmax * 1.0001 + 1e-5 : 0.0;
            if (nc == cap) cap = cap ? 2 * cap : 8, cand = prw_realloc(cand, cap * sizeof *cand);
            cand[nc++] = p;
        }
    }
    /* the largest first (diagonal of the influence box), scene order among equals: a stable insertion sort */
    for (uint32_t i = 1; i < nc; i++) {
        prw_probe_info x = cand[i];
        double dx = box_diag(&x);
        uint32_t j = i;
        while (j > 0 && box_diag(&cand[j - 1]) < dx) cand[j] = cand[j - 1], j--;
        cand[j] = x;
    }
    if (nc > limit) nc = limit;
    for (uint32_t i = 0; i < nc; i++) b->probes[i] = cand[i];
    b->count = nc;
    free(cand);
}

static uint64_t mix64(uint64_t x)
{
    x ^= x >> 30, x *= 0xbf58476d1ce4e5b9ull, x ^= x >> 27, x *= 0x94d049bb133111ebull, x ^= x >> 31;
    return x;
}

static bool check_options(const prw_probe_options *o, prw_error *e)
{
    if (o->count > PRW_PROBE_MAX) return prw_fail(e, "probe bake: count %u above %d", o->count, PRW_PROBE_MAX);
    if (o->size < 8 || o->size > 512) return prw_fail(e, "probe bake: size %u outside 8..512", o->size);
    if (resolved_samples(o) > 4096) return prw_fail(e, "probe bake: samples %u above 4096", o->samples);
    if (!(resolved_roughness(o) <= 1)) return prw_fail(e, "probe bake: max roughness %g above 1", o->max_roughness);
    return true;
}

bool prw_probe_build(const prw_scene *s, const prw_probe_options *o, prw_probe_progress_fn progress, void *user,
                     prw_probe_bake **out, prw_error *e)
{
    *out = NULL;
    if (!check_options(o, e)) return false;
    prw_probe_bake *b = prw_calloc(1, sizeof *b);
    prw_probe_select(s, o, b);
    if (b->count == 0) {
        *out = b;
        return true;
    }
    uint32_t H = b->size, W = 2 * H, M = b->samples, LH = b->level_height;
    size_t texels = (size_t)W * H, level_floats = (size_t)LH * 2 * LH * 3;
    b->levels_rgb = prw_calloc((size_t)b->count * b->levels * level_floats, sizeof(float));
    prw_dvec3 origin = prw_v3(b->probes[0].centre[0], b->probes[0].centre[1], b->probes[0].centre[2]);
    prw_ref_renderer *r = NULL;
    if (!prw_ref_create(s, origin, o->threads, &r, e)) {
        prw_probe_bake_destroy(b);
        return prw_fail_wrap(e, "probe bake");
    }
    uint32_t side = (uint32_t)floor(sqrt((double)M));
    while (side * side > M) side--;
    size_t chunk_texels = 256; /* rays per call: chunk_texels x M */
    prw_ref_ray *rays = prw_calloc(chunk_texels * M, sizeof *rays);
    prw_ref_ray_result *res = prw_calloc(chunk_texels * M, sizeof *res);
    float *map = prw_calloc(texels * 3, sizeof(float));
    double t0 = prw_now();
    bool ok = true;
    for (uint32_t p = 0; p < b->count && ok; p++) {
        const prw_probe_info *pi = &b->probes[p];
        for (size_t c0 = 0; c0 < texels && ok; c0 += chunk_texels) {
            size_t c1 = c0 + chunk_texels < texels ? c0 + chunk_texels : texels;
            for (size_t t = c0; t < c1; t++) {
                uint32_t i = (uint32_t)(t % W), j = (uint32_t)(t / W);
                uint64_t h = mix64(o->seed ^ mix64(((uint64_t)p << 40) ^ t));
                for (uint32_t k = 0; k < M; k++) {
                    /* stratified in the texel: a side x side grid, the rest jittered anywhere */
                    uint64_t hk = mix64(h + k);
                    double ju = (hk >> 11) * 0x1.0p-53, jv = (mix64(hk) >> 11) * 0x1.0p-53;
                    double su, sv;
                    if (k < side * side) su = ((k % side) + ju) / side, sv = ((k / side) + jv) / side;
                    else su = ju, sv = jv;
                    double d[3];
                    prw_env_uv_to_dir((i + su) / W, (j + sv) / H, d);
                    prw_ref_ray *q = &rays[(t - c0) * M + k];
                    q->origin = prw_v3(pi->centre[0], pi->centre[1], pi->centre[2]);
                    q->dir = prw_v3(d[0], d[1], d[2]);
                    q->tnear = pi->tnear;
                }
            }
            prw_ref_ray_desc d = {.first_index = ((uint64_t)p * texels + c0) * M, .s0 = 0, .s1 = 1, .seed = o->seed,
                                  .filter = {PRW_REF_MIN_DEPTH, 1}, .camera = true, .threads = o->threads};
            ok = prw_ref_trace_rays(r, rays, (c1 - c0) * M, &d, res, NULL, NULL, e);
            for (size_t t = c0; t < c1 && ok; t++)
                for (int c = 0; c < 3; c++) {
                    double sum = 0;
                    for (uint32_t k = 0; k < M; k++) sum += res[(t - c0) * M + k].mean[c];
                    map[3 * t + c] = (float)fmax(0.0, sum / M);
                }
            if (progress && ok) {
                char line[160];
                double el = prw_now() - t0, f = ((double)p * texels + c1) / ((double)b->count * texels);
                snprintf(line, sizeof line, "probes: %u of %u, %zu of %zu texels, %.1f s, eta %.1f s", p + 1, b->count,
                         c1, texels, el, el / f - el);
                progress(user, f, line);
            }
        }
        ok = ok && prw_env_prefilter(map, W, H, LH, b->levels, PRW_PROBE_PREFILTER_SAMPLES,
                                     b->levels_rgb + (size_t)p * b->levels * level_floats, e);
    }
    b->seconds_gather = prw_now() - t0;
    free(rays);
    free(res);
    free(map);
    prw_ref_destroy(r);
    if (!ok) {
        prw_probe_bake_destroy(b);
        return prw_fail_wrap(e, "probe bake");
    }
    *out = b;
    return true;
}

void prw_probe_key(const prw_scene *s, const prw_probe_options *o, char key[33])
{
    prw_cache_key k;
    prw_cache_key_begin(&k, "prw-probe-key");
    prw_cache_key_add_str(&k, PRW_PROBE_ALGO_VERSION);
    prw_cache_key_add_u64(&k, PROBE_VERSION);
    prw_cache_key_add_u64(&k, o->count);
    prw_cache_key_add_u64(&k, o->size);
    prw_cache_key_add_u64(&k, resolved_samples(o));
    prw_cache_key_add_u64(&k, o->seed);
    prw_cache_key_add_f64(&k, resolved_roughness(o));
    prw_cache_key_add_u64(&k, prw_ref_material_hash());
    prw_cache_key_add_u64(&k, prw_gi_content_hash(s));
    prw_cache_key_finish(&k, NULL, 0, key);
}

/* ---- file ---- */

typedef struct wbuf {
    uint8_t *p;
    size_t n;
} wbuf;
static void wput(wbuf *w, const void *d, size_t n)
{
    memcpy(w->p + w->n, d, n);
    w->n += n;
}
static void w32(wbuf *w, uint32_t v) { wput(w, &v, 4); }
static void wf64(wbuf *w, double v) { wput(w, &v, 8); }

static size_t level_bytes(const prw_probe_bake *b)
{
    return (size_t)b->count * b->levels * b->level_height * 2 * b->level_height * 3 * sizeof(float);
}

bool prw_probe_encode(const prw_probe_bake *b, const char *key, uint8_t **data, size_t *size, prw_error *e)
{
    if (b->count > PRW_PROBE_MAX) return prw_fail(e, "probe file: %u probes", b->count);
    size_t n = PROBE_HDR + (size_t)b->count * PROBE_REC + level_bytes(b) + 8;
    wbuf w = {prw_malloc(n), 0};
    wput(&w, k_magic, 8);
    w32(&w, PROBE_VERSION), w32(&w, b->count), w32(&w, b->size), w32(&w, b->samples), w32(&w, b->levels);
    w32(&w, b->level_height);
    char k[32];
    memset(k, 0, sizeof k);
    if (key) memcpy(k, key, strnlen(key, 32));
    wput(&w, k, 32);
    for (int c = 0; c < 3; c++) wf64(&w, b->parallax_min[c]);
    for (int c = 0; c < 3; c++) wf64(&w, b->parallax_max[c]);
    for (uint32_t i = 0; i < b->count; i++) {
        const prw_probe_info *p = &b->probes[i];
        w32(&w, p->node), w32(&w, p->mesh), w32(&w, (uint32_t)p->material), w32(&w, 0);
        for (int c = 0; c < 3; c++) wf64(&w, p->centre[c]);
        for (int c = 0; c < 3; c++) wf64(&w, p->box_min[c]);
        for (int c = 0; c < 3; c++) wf64(&w, p->box_max[c]);
        wf64(&w, p->tnear);
    }
    if (b->count) wput(&w, b->levels_rgb, level_bytes(b));
    uint64_t h = prw_hash64(w.p, w.n, 0);
    wput(&w, &h, 8);
    *data = w.p;
    *size = w.n;
    return true;
}

typedef struct rbuf {
    const uint8_t *p;
    size_t n, at;
} rbuf;
static bool rget(rbuf *r, void *d, size_t n)
{
    if (r->n - r->at < n) return false;
    memcpy(d, r->p + r->at, n);
    r->at += n;
    return true;
}

bool prw_probe_decode(const void *data, size_t size, const char *name, prw_probe_bake **out, char key[33], prw_error *e)
{
    *out = NULL;
    rbuf r = {data, size, 0};
    char magic[8];
    uint32_t v[6] = {0, 0, 0, 0, 0, 0};
    if (size < PROBE_HDR + 8 || !rget(&r, magic, 8) || memcmp(magic, k_magic, 8) != 0)
        return prw_fail(e, "%s: not a probe file (PRWPRB01)", name);
    uint64_t h;
    memcpy(&h, (const uint8_t *)data + size - 8, 8);
    if (prw_hash64(data, size - 8, 0) != h) return prw_fail(e, "%s: checksum mismatch", name);
    r.n = size - 8;
    for (int i = 0; i < 6; i++) rget(&r, &v[i], 4);
    if (v[0] != PROBE_VERSION) return prw_fail(e, "%s: version %u (expected %u)", name, v[0], PROBE_VERSION);
    if (v[1] > PRW_PROBE_MAX || v[2] < 8 || v[2] > 512 || v[3] < 1 || v[3] > 4096 || v[4] != PRW_PROBE_LEVELS ||
        v[5] != level_height(v[2]))
        return prw_fail(e, "%s: header out of range (count %u, size %u, samples %u, levels %u, height %u)", name, v[1],
                        v[2], v[3], v[4], v[5]);
    prw_probe_bake *b = prw_calloc(1, sizeof *b);
    b->count = v[1], b->size = v[2], b->samples = v[3], b->levels = v[4], b->level_height = v[5];
    char k[33];
    rget(&r, k, 32);
    k[32] = 0;
    bool hex = true, zero = true;
    for (int i = 0; i < 32; i++) {
        hex = hex && ((k[i] >= '0' && k[i] <= '9') || (k[i] >= 'a' && k[i] <= 'f'));
        zero = zero && k[i] == 0;
    }
    if (!hex && !zero) {
        prw_probe_bake_destroy(b);
        return prw_fail(e, "%s: cache key is neither 32 hex digits nor zeros", name);
    }
    if (key) memcpy(key, k, 33);
    bool ok = true;
    for (int c = 0; c < 3; c++) ok = ok && rget(&r, &b->parallax_min[c], 8);
    for (int c = 0; c < 3; c++) ok = ok && rget(&r, &b->parallax_max[c], 8);
    for (uint32_t i = 0; i < b->count && ok; i++) {
        prw_probe_info *p = &b->probes[i];
        uint32_t u[4] = {0, 0, 0, 0};
        for (int j = 0; j < 4; j++) ok = ok && rget(&r, &u[j], 4);
        p->node = u[0], p->mesh = u[1], p->material = (int32_t)u[2];
        double f[10] = {0};
        for (int j = 0; j < 10; j++) ok = ok && rget(&r, &f[j], 8);
        for (int j = 0; j < 10 && ok; j++) ok = isfinite(f[j]) && fabs(f[j]) <= 1e30; /* the GPU takes floats */
        ok = ok && u[3] == 0; /* reserved */
        for (int c = 0; c < 3; c++) p->centre[c] = f[c], p->box_min[c] = f[3 + c], p->box_max[c] = f[6 + c];
        p->tnear = f[9];
        ok = ok && p->tnear >= 0 && p->material >= 0;
    }
    for (int c = 0; c < 3 && ok; c++)
        ok = isfinite(b->parallax_min[c]) && isfinite(b->parallax_max[c]) && fabs(b->parallax_min[c]) <= 1e30 &&
             fabs(b->parallax_max[c]) <= 1e30;
    size_t lb = level_bytes(b);
    if (ok && r.n - r.at != lb) ok = false;
    if (ok && b->count) {
        b->levels_rgb = prw_malloc(lb);
        rget(&r, b->levels_rgb, lb);
        for (size_t i = 0; i < lb / 4 && ok; i++) ok = isfinite(b->levels_rgb[i]) && b->levels_rgb[i] >= 0;
    }
    if (!ok) {
        prw_probe_bake_destroy(b);
        return prw_fail(e, "%s: truncated, trailing bytes, a non-zero reserved field or a non-finite / negative / "
                        "out-of-range value", name);
    }
    *out = b;
    return true;
}

/* A cache entry names scene nodes, meshes and materials: it is used only when they are the ones this scene
 * and these options select (the placement is a pure function of both), so a stale or forged entry cannot
 * index past the scene or put a probe on a material the renderer does not probe. */
static bool selection_matches(const prw_scene *s, const prw_probe_options *o, const prw_probe_bake *b)
{
    prw_probe_bake sel;
    memset(&sel, 0, sizeof sel);
    prw_probe_select(s, o, &sel);
    if (sel.count != b->count) return false;
    for (uint32_t i = 0; i < b->count; i++)
        if (sel.probes[i].node != b->probes[i].node || sel.probes[i].mesh != b->probes[i].mesh ||
            sel.probes[i].material != b->probes[i].material)
            return false;
    return true;
}

bool prw_probe_run(const prw_scene *s, const prw_probe_options *o, bool no_cache, prw_probe_progress_fn progress,
                   void *user, prw_probe_bake **out, prw_probe_result *res, prw_error *e)
{
    memset(res, 0, sizeof *res);
    *out = NULL;
    if (!check_options(o, e)) return false;
    double t0 = prw_now();
    prw_probe_key(s, o, res->key);
    if (!no_cache) {
        char *data = NULL;
        size_t n = 0;
        if (prw_bake_entry_read(PRW_PROBE_CACHE_KIND, res->key, "probe", res->cache_path, sizeof res->cache_path, &data, &n,
                                res->warning, sizeof res->warning)) {
            prw_error ce = {{0}};
            char k[33];
            prw_probe_bake *b = NULL;
            if (prw_probe_decode(data, n, res->cache_path, &b, k, &ce) && strcmp(k, res->key) == 0 &&
                selection_matches(s, o, b)) {
                free(data);
                res->cache_hit = true;
                res->seconds_total = prw_now() - t0;
                *out = b;
                return true;
            }
            if (b) {
                snprintf(ce.msg, sizeof ce.msg, "%.900s holds another key or other probes", res->cache_path);
                prw_probe_bake_destroy(b);
            }
            free(data);
            prw_bake_entry_rejected(&ce, res->warning, sizeof res->warning);
        }
    }
    prw_probe_bake *b = NULL;
    if (!prw_probe_build(s, o, progress, user, &b, e)) return false;
    res->built = true;
    if (!no_cache && res->cache_path[0]) {
        uint8_t *data = NULL;
        size_t n = 0;
        prw_error we = {{0}};
        if (prw_probe_encode(b, res->key, &data, &n, &we))
            res->cache_written = prw_bake_entry_store(PRW_PROBE_CACHE_KIND, res->key, "probe", data, n, res->cache_path,
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
