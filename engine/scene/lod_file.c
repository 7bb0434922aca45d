/* lod_file.c — the .lod file: writer and the validating reader (prw_lod_file.h). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_lod_file.h"

/* ---- writer ---- */

typedef struct wbuf {
    uint8_t *p;
    size_t n, cap;
} wbuf;

static void w_bytes(wbuf *b, const void *d, size_t n)
{
    if (b->n + n > b->cap) {
        while (b->n + n > b->cap) b->cap = b->cap ? 2 * b->cap : 4096;
        b->p = prw_realloc(b->p, b->cap);
    }
    if (n) memcpy(b->p + b->n, d, n);
    b->n += n;
}

static void w_u64(wbuf *b, uint64_t v)
{
    uint8_t t[8];
    for (int i = 0; i < 8; i++) t[i] = (uint8_t)(v >> (8 * i));
    w_bytes(b, t, 8);
}

static void w_u32(wbuf *b, uint32_t v)
{
    uint8_t t[4];
    for (int i = 0; i < 4; i++) t[i] = (uint8_t)(v >> (8 * i));
    w_bytes(b, t, 4);
}

static void w_i32(wbuf *b, int v) { w_u32(b, (uint32_t)v); }
static void w_u8(wbuf *b, unsigned v) { uint8_t t = (uint8_t)v; w_bytes(b, &t, 1); }

static void w_f64(wbuf *b, double v)
{
    uint64_t u;
    memcpy(&u, &v, 8);
    w_u64(b, u);
}

static void w_v3(wbuf *b, prw_dvec3 v)
{
    w_f64(b, v.x);
    w_f64(b, v.y);
    w_f64(b, v.z);
}

static void w_str(wbuf *b, const char *s, size_t cap)
{
    size_t n = strnlen(s, cap);
    w_u32(b, (uint32_t)n);
    w_bytes(b, s, n);
}

static void w_ints(wbuf *b, const int *v, size_t n)
{
    for (size_t i = 0; i < n; i++) w_i32(b, v[i]);
}

static void w_f64s(wbuf *b, const double *v, size_t n)
{
    for (size_t i = 0; i < n; i++) w_f64(b, v[i]);
}

void prw_lod_file_serialize(const prw_baked_lod *bk, uint8_t **data, size_t *size)
{
    const prw_seam_graph *g = &bk->graph;
    const prw_lod_model *lm = &bk->lod;
    wbuf b = {0};
    uint8_t hdr[PRW_LOD_HEADER_SIZE] = {0};
    w_bytes(&b, hdr, sizeof hdr); /* filled in below */
    char key[32] = {0};
    memcpy(key, bk->key, strnlen(bk->key, 32));
    w_bytes(&b, key, 32);
    /* seam graph */
    w_f64(&b, g->tol);
    w_f64(&b, g->chord);
    w_f64(&b, g->max_edge);
    w_f64(&b, g->diag);
    w_i32(&b, g->ngids);
    w_i32(&b, g->shared);
    w_i32(&b, g->open);
    w_i32(&b, g->degenerate);
    w_i32(&b, g->unmatched);
    w_i32(&b, g->skipped_patches);
    w_f64(&b, g->max_shared_gap);
    w_str(&b, g->first_problem, sizeof g->first_problem);
    w_i32(&b, g->nnodes);
    for (int i = 0; i < g->nnodes; i++) w_v3(&b, g->nodes[i]);
    w_i32(&b, g->nsegs);
    for (int s = 0; s < g->nsegs; s++) {
        const prw_seam_segment *sg = &g->segs[s];
        w_ints(&b, sg->node, 2);
        w_ints(&b, sg->patch, 2);
        w_ints(&b, sg->loop, 2);
        w_u8(&b, sg->degenerate);
        w_i32(&b, sg->gid0);
        w_i32(&b, sg->min_interior);
        w_f64(&b, sg->chord_err);
        w_f64(&b, sg->gap);
        w_f64(&b, sg->length);
        w_i32(&b, sg->npts);
        for (int i = 0; i < sg->npts; i++) w_v3(&b, sg->pts[i]);
        for (int side = 0; side < 2; side++) {
            w_u8(&b, sg->uv[side] != NULL);
            if (sg->uv[side]) w_f64s(&b, sg->uv[side], 2 * (size_t)sg->npts);
        }
        w_ints(&b, lm->seg_keep[s], (size_t)sg->npts);
        w_ints(&b, lm->ladder[s], (size_t)sg->npts);
    }
    w_i32(&b, g->npatches);
    for (int p = 0; p < g->npatches; p++) {
        const prw_seam_patch *P = &g->patches[p];
        w_u8(&b, P->skipped);
        w_v3(&b, P->lo);
        w_v3(&b, P->hi);
        w_i32(&b, P->nloops);
        for (int l = 0; l < P->nloops; l++) {
            w_i32(&b, P->loops[l].count);
            for (int u = 0; u < P->loops[l].count; u++) {
                w_i32(&b, P->loops[l].uses[u].seg);
                w_u8(&b, P->loops[l].uses[u].reversed);
                w_i32(&b, P->loops[l].uses[u].side);
            }
        }
    }
    /* LOD model */
    w_i32(&b, lm->levels);
    w_f64(&b, lm->tau0);
    w_i32(&b, lm->failed_patches);
    w_i32(&b, lm->refused_splits);
    w_u64(&b, lm->finest_triangles);
    w_str(&b, lm->first_problem, sizeof lm->first_problem);
    for (int pi = 0; pi < lm->npatches; pi++) {
        const prw_lod_patch *p = &lm->patches[pi];
        w_u8(&b, p->ok);
        w_v3(&b, p->lo);
        w_v3(&b, p->hi);
        if (!p->ok) continue;
        w_i32(&b, p->nverts);
        w_i32(&b, p->nbound);
        w_i32(&b, p->nrings);
        w_f64s(&b, p->uv, 2 * (size_t)p->nverts);
        for (int v = 0; v < p->nverts; v++) w_v3(&b, p->pos[v]);
        w_ints(&b, p->gid, (size_t)p->nverts);
        w_ints(&b, p->removed_at, (size_t)p->nverts);
        w_ints(&b, p->ring_start, (size_t)p->nrings + 1);
        w_ints(&b, p->ring_of, (size_t)p->nbound);
        w_ints(&b, p->ring_seg, (size_t)p->nbound);
        w_ints(&b, p->ring_sidx, (size_t)p->nbound);
        for (int v = 0; v < p->nbound; v++) w_u8(&b, p->ring_rev[v]);
        w_ints(&b, p->tri_start, (size_t)lm->levels + 1);
        w_ints(&b, p->tris, 3 * (size_t)p->tri_start[lm->levels]);
        w_f64s(&b, p->err, (size_t)lm->levels);
    }
    /* culling data (version 2) */
    const prw_lod_cull *c = &bk->cull;
    w_i32(&b, c->npatches);
    w_i32(&b, c->full_cones);
    w_i32(&b, c->refined);
    for (int i = 0; i < c->npatches; i++) {
        w_v3(&b, c->lo[i]);
        w_v3(&b, c->hi[i]);
        w_v3(&b, c->centre[i]);
        w_f64(&b, c->radius[i]);
        w_v3(&b, c->axis[i]);
        w_f64(&b, c->half_angle[i]);
        w_u8(&b, c->single_sided[i]);
    }
    /* proxy levels (version 3) */
    const prw_lod_proxy *px = &bk->proxy;
    w_u8(&b, bk->have_proxy);
    if (bk->have_proxy) {
        w_i32(&b, px->start_level);
        w_f64(&b, px->eps_start);
        w_i32(&b, px->start_triangles);
        w_i32(&b, px->patch_floor_triangles);
        w_i32(&b, px->border_edges);
        w_i32(&b, px->nlevels);
        for (int l = 0; l < px->nlevels; l++) {
            const prw_lod_proxy_level *pl = &px->levels[l];
            size_t nv = (size_t)pl->nverts, nt = (size_t)pl->ntris;
            w_i32(&b, pl->stage);
            w_f64(&b, pl->err);
            w_f64(&b, pl->d_start);
            w_i32(&b, pl->nverts);
            w_i32(&b, pl->ntris);
            w_f64s(&b, pl->pos, 3 * nv);
            for (size_t i = 0; i < 3 * nt; i++) w_u32(&b, pl->tris[i]);
            w_ints(&b, pl->corner_patch, 3 * nt);
            w_f64s(&b, pl->corner_uv, 6 * nt);
            w_ints(&b, pl->tri_patch, nt);
        }
    }
    /* header */
    size_t payload = b.n - PRW_LOD_HEADER_SIZE;
    uint64_t sum = prw_hash64(b.p + PRW_LOD_HEADER_SIZE, payload, 0);
    wbuf h = {0};
    w_bytes(&h, PRW_LOD_FILE_MAGIC, 8);
    w_u32(&h, PRW_LOD_FILE_VERSION);
    w_u32(&h, 0);
    w_u64(&h, payload);
    w_u64(&h, sum);
    memcpy(b.p, h.p, PRW_LOD_HEADER_SIZE);
    free(h.p);
    *data = b.p;
    *size = b.n;
}

bool prw_lod_file_write(const char *path, const prw_baked_lod *b, prw_error *e)
{
    uint8_t *d;
    size_t n;
    prw_lod_file_serialize(b, &d, &n);
    bool ok = prw_write_file_atomic(path, d, n, e);
    free(d);
    return ok;
}

/* ---- reader ---- */

/* Absolute limits (far above any real model, far below what overflows int arithmetic). */
#define LIM_COUNT 100000000 /* any element count */

typedef struct rbuf {
    const uint8_t *p;
    size_t n, at;
    const char *name;
    prw_error *e;
    bool bad;
} rbuf;

static bool r_fail(rbuf *r, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static bool r_fail(rbuf *r, const char *fmt, ...)
{
    if (r->bad) return false;
    r->bad = true;
    char m[400];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(m, sizeof m, fmt, ap);
    va_end(ap);
    prw_fail(r->e, "%s: %s (at byte %zu)", r->name, m, r->at + PRW_LOD_HEADER_SIZE);
    return false;
}

static bool r_need(rbuf *r, size_t n, const char *what)
{
    if (r->bad) return false;
    if (n > r->n - r->at) return r_fail(r, "truncated: %s needs %zu bytes, %zu left", what, n, r->n - r->at);
    return true;
}

static uint64_t r_u64(rbuf *r, const char *what)
{
    if (!r_need(r, 8, what)) return 0;
    uint64_t v = 0;
    for (int i = 0; i < 8; i++) v |= (uint64_t)r->p[r->at + i] << (8 * i);
    r->at += 8;
    return v;
}

static uint32_t r_u32(rbuf *r, const char *what)
{
    if (!r_need(r, 4, what)) return 0;
    uint32_t v = 0;
    for (int i = 0; i < 4; i++) v |= (uint32_t)r->p[r->at + i] << (8 * i);
    r->at += 4;
    return v;
}

static int r_i32(rbuf *r, const char *what) { return (int)(int32_t)r_u32(r, what); }

static unsigned r_u8(rbuf *r, const char *what)
{
    if (!r_need(r, 1, what)) return 0;
    return r->p[r->at++];
}

static bool r_bool(rbuf *r, const char *what)
{
    unsigned v = r_u8(r, what);
    if (v > 1) r_fail(r, "%s: flag %u is not 0 or 1", what, v);
    return v == 1;
}

static double r_f64(rbuf *r, const char *what)
{
    uint64_t u = r_u64(r, what);
    double v;
    memcpy(&v, &u, 8);
    return v;
}

/* A finite double (coordinates, tolerances). */
static double r_fin(rbuf *r, const char *what)
{
    double v = r_f64(r, what);
    if (!r->bad && !isfinite(v)) r_fail(r, "%s: %g is not finite", what, v);
    return v;
}

static prw_dvec3 r_v3(rbuf *r, const char *what)
{
    prw_dvec3 v;
    v.x = r_fin(r, what);
    v.y = r_fin(r, what);
    v.z = r_fin(r, what);
    return v;
}

/* A count in [lo, LIM_COUNT] whose elements (elem bytes each, times mult) fit in what is left. */
static int r_count(rbuf *r, int lo, size_t elem, const char *what)
{
    int n = r_i32(r, what);
    if (r->bad) return 0;
    if (n < lo || n > LIM_COUNT) {
        r_fail(r, "%s: count %d out of range", what, n);
        return 0;
    }
    if (elem && (size_t)n > (r->n - r->at) / elem) {
        r_fail(r, "truncated or corrupt: %s: count %d needs %zu bytes, %zu left", what, n, (size_t)n * elem,
               r->n - r->at);
        return 0;
    }
    return n;
}

static void r_str(rbuf *r, char *out, size_t cap, const char *what)
{
    uint32_t n = r_u32(r, what);
    if (r->bad) return;
    if (n >= cap) {
        r_fail(r, "%s: string length %u exceeds %zu", what, n, cap - 1);
        return;
    }
    if (!r_need(r, n, what)) return;
    memcpy(out, r->p + r->at, n);
    out[n] = '\0';
    r->at += n;
}

/* n ints, each in [lo, hi]; NULL (and r->bad) on failure.  n is bounded by the caller. */
static int *r_ints(rbuf *r, size_t n, long lo, long hi, const char *what)
{
    if (!r_need(r, 4 * n, what)) return NULL;
    int *v = prw_malloc(sizeof(int) * n + 1);
    for (size_t i = 0; i < n; i++) {
        v[i] = r_i32(r, what);
        if (v[i] < lo || v[i] > hi) {
            r_fail(r, "%s[%zu] = %d out of range [%ld, %ld]", what, i, v[i], lo, hi);
            free(v);
            return NULL;
        }
    }
    return v;
}

static double *r_f64s(rbuf *r, size_t n, const char *what)
{
    if (!r_need(r, 8 * n, what)) return NULL;
    double *v = prw_malloc(sizeof(double) * n + 1);
    for (size_t i = 0; i < n; i++) v[i] = r_fin(r, what);
    if (r->bad) {
        free(v);
        return NULL;
    }
    return v;
}

static prw_dvec3 *r_v3s(rbuf *r, size_t n, const char *what)
{
    if (!r_need(r, 24 * n, what)) return NULL;
    prw_dvec3 *v = prw_malloc(sizeof(prw_dvec3) * n + 1);
    for (size_t i = 0; i < n; i++) v[i] = r_v3(r, what);
    if (r->bad) {
        free(v);
        return NULL;
    }
    return v;
}

static bool read_graph(rbuf *r, prw_baked_lod *b)
{
    prw_seam_graph *g = &b->graph;
    prw_lod_model *lm = &b->lod;
    g->tol = r_fin(r, "graph tolerance");
    g->chord = r_fin(r, "graph chord");
    g->max_edge = r_fin(r, "graph max_edge");
    g->diag = r_fin(r, "graph diagonal");
    g->ngids = r_count(r, 0, 0, "gid count");
    g->shared = r_i32(r, "report");
    g->open = r_i32(r, "report");
    g->degenerate = r_i32(r, "report");
    g->unmatched = r_i32(r, "report");
    g->skipped_patches = r_i32(r, "report");
    g->max_shared_gap = r_f64(r, "report");
    r_str(r, g->first_problem, sizeof g->first_problem, "graph report");
    int nn = r_count(r, 0, 24, "node count");
    if (r->bad) return false;
    g->nodes = r_v3s(r, (size_t)nn, "nodes");
    if (r->bad) return false;
    g->nnodes = nn;
    if (g->ngids < nn) return r_fail(r, "gid count %d < node count %d", g->ngids, nn);
    /* smallest segment record: 6 ints + flag + 2 ints + 3 doubles + npts + 2 flags + (2 points) */
    int ns = r_count(r, 0, 60, "segment count");
    if (r->bad) return false;
    g->segs = prw_calloc((size_t)ns + 1, sizeof(prw_seam_segment));
    lm->seg_keep = prw_calloc((size_t)ns + 1, sizeof(int *));
    lm->ladder = prw_calloc((size_t)ns + 1, sizeof(int *));
    g->nsegs = ns; /* arrays NULL until read: prw_seam_free / cleanup tolerate that */
    for (int s = 0; s < ns && !r->bad; s++) {
        prw_seam_segment *sg = &g->segs[s];
        for (int k = 0; k < 2; k++) sg->node[k] = r_i32(r, "segment node");
        for (int k = 0; k < 2; k++) sg->patch[k] = r_i32(r, "segment patch");
        for (int k = 0; k < 2; k++) sg->loop[k] = r_i32(r, "segment loop");
        sg->degenerate = r_bool(r, "segment degenerate");
        sg->gid0 = r_i32(r, "segment gid0");
        sg->min_interior = r_i32(r, "segment min_interior");
        sg->chord_err = r_f64(r, "segment chord_err");
        sg->gap = r_f64(r, "segment gap");
        sg->length = r_f64(r, "segment length");
        if (r->bad) break;
        for (int k = 0; k < 2; k++)
            if (sg->node[k] < 0 || sg->node[k] >= nn) return r_fail(r, "segment %d: node %d out of range", s, sg->node[k]);
        int npts = r_count(r, 2, 24, "segment point count");
        if (r->bad) break;
        if (npts > 2 && (sg->gid0 < nn || sg->gid0 > g->ngids - (npts - 2)))
            return r_fail(r, "segment %d: interior gids %d.. out of range", s, sg->gid0);
        sg->pts = r_v3s(r, (size_t)npts, "segment points");
        if (r->bad) break;
        sg->npts = npts;
        for (int side = 0; side < 2 && !r->bad; side++)
            if (r_bool(r, "segment uv flag")) sg->uv[side] = r_f64s(r, 2 * (size_t)npts, "segment uv");
        if (r->bad) break;
        lm->seg_keep[s] = r_ints(r, (size_t)npts, INT32_MIN, INT32_MAX, "seg_keep");
        lm->ladder[s] = r_ints(r, (size_t)npts, INT32_MIN, INT32_MAX, "ladder");
    }
    if (r->bad) return false;
    int np = r_count(r, 0, 53, "patch count");
    if (r->bad) return false;
    g->patches = prw_calloc((size_t)np + 1, sizeof(prw_seam_patch));
    g->npatches = np;
    for (int s = 0; s < ns; s++)
        for (int k = 0; k < 2; k++)
            if (g->segs[s].patch[k] < (k ? -1 : 0) || g->segs[s].patch[k] >= np)
                return r_fail(r, "segment %d: patch %d out of range", s, g->segs[s].patch[k]);
    for (int p = 0; p < np && !r->bad; p++) {
        prw_seam_patch *P = &g->patches[p];
        P->skipped = r_bool(r, "patch skipped");
        P->lo = r_v3(r, "patch box");
        P->hi = r_v3(r, "patch box");
        int nl = r_count(r, 0, 4, "loop count");
        if (r->bad) break;
        P->loops = prw_calloc((size_t)nl + 1, sizeof(prw_seam_loop));
        P->nloops = nl;
        for (int l = 0; l < nl && !r->bad; l++) {
            int nu = r_count(r, 0, 9, "loop use count");
            if (r->bad) break;
            P->loops[l].uses = prw_calloc((size_t)nu + 1, sizeof(prw_seam_use));
            P->loops[l].count = nu;
            for (int u = 0; u < nu && !r->bad; u++) {
                prw_seam_use *us = &P->loops[l].uses[u];
                us->seg = r_i32(r, "loop use");
                us->reversed = r_bool(r, "loop use");
                us->side = r_i32(r, "loop use");
                if (!r->bad && (us->seg < 0 || us->seg >= ns || us->side < 0 || us->side > 1))
                    return r_fail(r, "patch %d loop %d: use %d out of range", p, l, u);
            }
        }
    }
    return !r->bad;
}

static bool read_lod(rbuf *r, prw_baked_lod *b)
{
    prw_seam_graph *g = &b->graph;
    prw_lod_model *lm = &b->lod;
    lm->g = g;
    int L = r_i32(r, "level count");
    if (r->bad) return false;
    if (L < 1 || L > PRW_LOD_MAX_LEVELS) return r_fail(r, "level count %d out of range 1..%d", L, PRW_LOD_MAX_LEVELS);
    lm->levels = L;
    lm->tau0 = r_fin(r, "tau0");
    lm->failed_patches = r_i32(r, "report");
    lm->refused_splits = r_i32(r, "report");
    lm->finest_triangles = (size_t)r_u64(r, "report");
    r_str(r, lm->first_problem, sizeof lm->first_problem, "lod report");
    if (r->bad) return false;
    lm->patches = prw_calloc((size_t)g->npatches + 1, sizeof(prw_lod_patch));
    lm->npatches = g->npatches;
    for (int pi = 0; pi < lm->npatches; pi++) {
        prw_lod_patch *p = &lm->patches[pi];
        bool ok = r_bool(r, "patch ok");
        p->lo = r_v3(r, "patch box");
        p->hi = r_v3(r, "patch box");
        if (r->bad) return false;
        if (!ok) continue;
        int nv = r_count(r, 0, 48, "vertex count"); /* uv, pos, gid, removed_at */
        int nb = r_count(r, 0, 0, "boundary vertex count");
        int nr = r_count(r, 0, 0, "ring count");
        if (r->bad) return false;
        if (nb > nv) return r_fail(r, "patch %d: %d boundary vertices > %d vertices", pi, nb, nv);
        if ((size_t)nr > (r->n - r->at) / 4) return r_fail(r, "truncated or corrupt: patch %d: ring count %d", pi, nr);
        /* arrays first assigned, so cleanup frees whatever was read */
        p->uv = r_f64s(r, 2 * (size_t)nv, "vertex uv");
        if (!r->bad) p->pos = r_v3s(r, (size_t)nv, "vertex position");
        if (!r->bad) p->gid = r_ints(r, (size_t)nv, -1, g->ngids - 1, "vertex gid");
        if (!r->bad) p->removed_at = r_ints(r, (size_t)nv, 0, L, "vertex removed_at");
        if (!r->bad) p->ring_start = r_ints(r, (size_t)nr + 1, 0, nb, "ring_start");
        if (!r->bad) p->ring_of = r_ints(r, (size_t)nb, 0, nr - 1, "ring_of");
        if (!r->bad) p->ring_seg = r_ints(r, (size_t)nb, 0, g->nsegs - 1, "ring_seg");
        if (!r->bad) p->ring_sidx = r_ints(r, (size_t)nb, 0, LIM_COUNT, "ring_sidx");
        if (!r->bad && r_need(r, (size_t)nb, "ring_rev")) {
            p->ring_rev = prw_malloc((size_t)nb + 1);
            for (int v = 0; v < nb; v++) p->ring_rev[v] = (unsigned char)r_bool(r, "ring_rev");
        }
        if (!r->bad) p->tri_start = r_ints(r, (size_t)L + 1, 0, LIM_COUNT, "tri_start");
        if (r->bad) return false;
        p->nverts = nv;
        p->nbound = nb;
        p->nrings = nr;
        p->ok = true;
        if (p->ring_start[0] != 0 || p->ring_start[nr] != nb)
            return r_fail(r, "patch %d: ring offsets do not span the %d boundary vertices", pi, nb);
        for (int k = 0; k < nr; k++) {
            if (p->ring_start[k + 1] <= p->ring_start[k]) return r_fail(r, "patch %d: ring %d is empty or reversed", pi, k);
            for (int i = p->ring_start[k]; i < p->ring_start[k + 1]; i++)
                if (p->ring_of[i] != k) return r_fail(r, "patch %d: ring_of[%d] disagrees with ring_start", pi, i);
        }
        for (int v = 0; v < nb; v++)
            if (p->ring_sidx[v] >= g->segs[p->ring_seg[v]].npts)
                return r_fail(r, "patch %d: ring_sidx[%d] beyond its segment", pi, v);
        if (p->tri_start[0] != 0) return r_fail(r, "patch %d: tri_start[0] is not 0", pi);
        for (int k = 0; k < L; k++)
            if (p->tri_start[k + 1] < p->tri_start[k]) return r_fail(r, "patch %d: tri_start decreases at level %d", pi, k);
        size_t nt = (size_t)p->tri_start[L];
        if (nt > (r->n - r->at) / 12) return r_fail(r, "truncated or corrupt: patch %d: %zu triangles", pi, nt);
        p->tris = r_ints(r, 3 * nt, 0, nv - 1, "triangle index");
        if (!r->bad) p->err = r_f64s(r, (size_t)L, "level error");
        if (r->bad) return false;
        for (int k = 0; k < L; k++)
            if (p->err[k] < 0) return r_fail(r, "patch %d: negative error at level %d", pi, k);
    }
    return !r->bad;
}

static bool read_cull(rbuf *r, prw_baked_lod *b)
{
    prw_lod_cull *c = &b->cull;
    int n = r_count(r, 0, 113, "culling patch count"); /* 14 doubles + 1 byte per patch */
    if (r->bad) return false;
    if (n != b->lod.npatches) return r_fail(r, "culling data for %d patches, the hierarchy has %d", n, b->lod.npatches);
    int full = r_i32(r, "full cone count"), refined = r_i32(r, "refined count");
    if (r->bad) return false;
    if (full < 0 || full > n || refined < 0 || refined > n)
        return r_fail(r, "culling report counts %d / %d out of range 0..%d", full, refined, n);
    c->lo = prw_malloc(sizeof(prw_dvec3) * (size_t)n + 1);
    c->hi = prw_malloc(sizeof(prw_dvec3) * (size_t)n + 1);
    c->centre = prw_malloc(sizeof(prw_dvec3) * (size_t)n + 1);
    c->radius = prw_malloc(sizeof(double) * (size_t)n + 1);
    c->axis = prw_malloc(sizeof(prw_dvec3) * (size_t)n + 1);
    c->half_angle = prw_malloc(sizeof(double) * (size_t)n + 1);
    c->single_sided = prw_malloc((size_t)n + 1);
    c->npatches = n;
    c->full_cones = full;
    c->refined = refined;
    for (int i = 0; i < n && !r->bad; i++) {
        c->lo[i] = r_v3(r, "culling box");
        c->hi[i] = r_v3(r, "culling box");
        c->centre[i] = r_v3(r, "culling sphere centre");
        c->radius[i] = r_fin(r, "culling sphere radius");
        c->axis[i] = r_v3(r, "normal cone axis");
        c->half_angle[i] = r_fin(r, "normal cone half-angle");
        c->single_sided[i] = (unsigned char)r_bool(r, "single_sided");
        if (r->bad) break;
        if (!(c->lo[i].x <= c->hi[i].x && c->lo[i].y <= c->hi[i].y && c->lo[i].z <= c->hi[i].z))
            return r_fail(r, "patch %d: culling box is inverted", i);
        if (!(c->radius[i] >= 0)) return r_fail(r, "patch %d: negative culling sphere radius", i);
        if (!(c->half_angle[i] >= 0 && c->half_angle[i] <= PRW_PI))
            return r_fail(r, "patch %d: normal cone half-angle %g outside [0, pi]", i, c->half_angle[i]);
        double al = prw_v3_len(c->axis[i]);
        if (!(fabs(al - 1) <= 1e-9 || (al == 0 && c->half_angle[i] == PRW_PI)))
            return r_fail(r, "patch %d: normal cone axis of length %g", i, al);
    }
    return !r->bad;
}

/* The proxy section (version 3): see prw_bake.h for every check. */
static bool read_proxy(rbuf *r, prw_baked_lod *b)
{
    prw_lod_proxy *px = &b->proxy;
    bool have = r_bool(r, "proxy flag");
    if (r->bad) return false;
    if (!have) return true;
    int np = b->lod.npatches, L = b->lod.levels;
    px->start_level = r_i32(r, "proxy start level");
    px->eps_start = r_fin(r, "proxy eps_start");
    px->start_triangles = r_count(r, 0, 0, "proxy start triangles");
    px->patch_floor_triangles = r_count(r, 0, 0, "proxy patch_floor_triangles");
    px->border_edges = r_count(r, 0, 0, "proxy border_edges");
    if (r->bad) return false;
    if (px->start_level < 0 || px->start_level >= L)
        return r_fail(r, "proxy start level %d outside the hierarchy's levels 0..%d", px->start_level, L - 1);
    if (!(px->eps_start >= 0)) return r_fail(r, "proxy eps_start %g is negative", px->eps_start);
    /* smallest level record: stage, err, d_start, nverts, ntris (28 bytes) + 3 vertices + 1 triangle */
    int nl = r_count(r, 0, 28 + 72 + 76, "proxy level count");
    if (r->bad) return false;
    px->levels = prw_calloc((size_t)nl + 1, sizeof(prw_lod_proxy_level));
    px->nlevels = nl; /* arrays NULL until read: prw_lod_proxy_free tolerates that */
    b->have_proxy = true;
    for (int l = 0; l < nl; l++) {
        prw_lod_proxy_level *pl = &px->levels[l];
        pl->stage = r_i32(r, "proxy level stage");
        pl->err = r_fin(r, "proxy level err");
        pl->d_start = r_fin(r, "proxy level d_start");
        if (r->bad) return false;
        if (pl->stage < 0 || pl->stage > PRW_PROXY_STEPS * PRW_LOD_MAX_LEVELS)
            return r_fail(r, "proxy level %d: stage %d out of range", l, pl->stage);
        if (!(pl->err >= 0) || !(pl->d_start >= 0))
            return r_fail(r, "proxy level %d: negative err %g / d_start %g", l, pl->err, pl->d_start);
        int nv = r_count(r, 3, 24, "proxy vertex count");
        int nt = r_count(r, 1, 0, "proxy triangle count"); /* bytes checked below */
        if (r->bad) return false;
        if (l > 0 && nt >= px->levels[l - 1].ntris)
            return r_fail(r, "proxy level %d: %d triangles, not fewer than level %d's %d (levels must strictly decrease)",
                          l, nt, l - 1, px->levels[l - 1].ntris);
        if ((size_t)nv > (r->n - r->at) / 24 || (size_t)nt > (r->n - r->at - 24 * (size_t)nv) / 76)
            return r_fail(r, "truncated or corrupt: proxy level %d: %d vertices, %d triangles", l, nv, nt);
        pl->pos = r_f64s(r, 3 * (size_t)nv, "proxy vertex position");
        if (r->bad) return false;
        int *tri = r_ints(r, 3 * (size_t)nt, 0, nv - 1, "proxy triangle index");
        if (r->bad) return false;
        pl->tris = prw_malloc(sizeof(uint32_t) * 3 * (size_t)nt + 1);
        for (size_t i = 0; i < 3 * (size_t)nt; i++) pl->tris[i] = (uint32_t)tri[i];
        free(tri);
        pl->corner_patch = r_ints(r, 3 * (size_t)nt, 0, np - 1, "proxy corner_patch");
        if (!r->bad) pl->corner_uv = r_f64s(r, 6 * (size_t)nt, "proxy corner uv");
        if (!r->bad) pl->tri_patch = r_ints(r, (size_t)nt, 0, np - 1, "proxy tri_patch");
        if (r->bad) return false;
        pl->nverts = nv;
        pl->ntris = nt;
    }
    return !r->bad;
}

void prw_lod_file_destroy(prw_baked_lod *b)
{
    if (!b) return;
    prw_seam_graph *g = &b->graph;
    /* prw_lod_free walks lod.g->nsegs for the ladders: keep it pointing at the graph */
    b->lod.g = g;
    if (!b->lod.seg_keep) b->lod.g = NULL;
    prw_lod_free(&b->lod);
    prw_seam_free(g);
    prw_lod_cull_free(&b->cull);
    prw_lod_proxy_free(&b->proxy);
    free(b);
}

bool prw_lod_file_parse(const void *data, size_t size, const char *name, prw_baked_lod **out, prw_error *e)
{
    *out = NULL;
    const uint8_t *d = data;
    if (size < PRW_LOD_HEADER_SIZE)
        return prw_fail(e, "%s: truncated: %zu bytes, a .lod header has %u", name, size, PRW_LOD_HEADER_SIZE);
    if (memcmp(d, PRW_LOD_FILE_MAGIC, 8) != 0) return prw_fail(e, "%s: not a .lod file (no PRWLOD01 magic)", name);
    rbuf h = {.p = d, .n = size, .at = 8, .name = name, .e = e};
    uint32_t ver = r_u32(&h, "version"), flags = r_u32(&h, "flags");
    uint64_t payload = r_u64(&h, "payload size"), sum = r_u64(&h, "checksum");
    if (ver != PRW_LOD_FILE_VERSION)
        return prw_fail(e, "%s: format version %u, this prw reads %u", name, ver, PRW_LOD_FILE_VERSION);
    if (flags != 0) return prw_fail(e, "%s: unknown flags 0x%x", name, flags);
    if (payload != size - PRW_LOD_HEADER_SIZE)
        return prw_fail(e, "%s: %s: header says %llu payload bytes, the file has %zu", name,
                        payload > size - PRW_LOD_HEADER_SIZE ? "truncated" : "trailing bytes",
                        (unsigned long long)payload, size - PRW_LOD_HEADER_SIZE);
    if (prw_hash64(d + PRW_LOD_HEADER_SIZE, (size_t)payload, 0) != sum)
        return prw_fail(e, "%s: corrupt: payload checksum mismatch", name);
    prw_baked_lod *b = prw_calloc(1, sizeof *b);
    b->lod.g = &b->graph;
    rbuf r = {.p = d + PRW_LOD_HEADER_SIZE, .n = (size_t)payload, .at = 0, .name = name, .e = e};
    if (r_need(&r, 32, "key")) {
        memcpy(b->key, r.p, 32);
        b->key[32] = '\0';
        r.at += 32;
        for (int i = 0; i < 32 && !r.bad; i++)
            if (b->key[i] && !((b->key[i] >= '0' && b->key[i] <= '9') || (b->key[i] >= 'a' && b->key[i] <= 'f')))
                r_fail(&r, "key is not hexadecimal");
    }
    bool ok = !r.bad && read_graph(&r, b) && read_lod(&r, b) && read_cull(&r, b) && read_proxy(&r, b);
    if (ok && r.at != r.n) ok = r_fail(&r, "%zu unexplained bytes after the hierarchy", r.n - r.at);
    if (!ok) {
        prw_lod_file_destroy(b);
        return false;
    }
    *out = b;
    return true;
}

bool prw_lod_file_read(const char *path, prw_baked_lod **out, prw_error *e)
{
    char *d;
    size_t n;
    *out = NULL;
    if (!prw_read_file(path, &d, &n, e)) return false;
    bool ok = prw_lod_file_parse(d, n, path, out, e);
    free(d);
    return ok;
}
