/* Welding by bit-identical positions, edge-use counting, T-junction and zero-area search. */
#include <math.h>
#include <stdio.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "lod_mesh_check.h"

typedef struct bpt {
    double p[3];
    int seg;
} bpt;

struct lod_border_set {
    bpt *pts;
    int n;
};

static int cmp_pos(const void *a, const void *b) { return memcmp(a, b, 3 * sizeof(double)); }

static int cmp_bpt(const void *a, const void *b)
{
    int c = memcmp(((const bpt *)a)->p, ((const bpt *)b)->p, sizeof(double) * 3);
    return c ? c : ((const bpt *)a)->seg - ((const bpt *)b)->seg;
}

lod_border_set *lod_border_set_make(const prw_seam_graph *g)
{
    lod_border_set *b = prw_calloc(1, sizeof *b);
    int cap = 0;
    for (int s = 0; s < g->nsegs; s++) {
        const prw_seam_segment *sg = &g->segs[s];
        if (sg->patch[1] >= 0 || sg->degenerate) continue;
        for (int i = 0; i < sg->npts; i++) {
            if (b->n == cap) {
                cap = cap ? 2 * cap : 256;
                b->pts = prw_realloc(b->pts, sizeof(bpt) * (size_t)cap);
            }
            memcpy(b->pts[b->n].p, &sg->pts[i], sizeof(double) * 3);
            b->pts[b->n].seg = s;
            b->n++;
        }
    }
    if (b->n) qsort(b->pts, (size_t)b->n, sizeof(bpt), cmp_bpt);
    return b;
}

void lod_border_set_free(lod_border_set *b)
{
    if (!b) return;
    free(b->pts);
    free(b);
}

/* Range of border entries at position p. */
static void border_range(const lod_border_set *b, const double *p, int *lo, int *hi)
{
    int a = 0, z = b->n;
    while (a < z) {
        int m = (a + z) / 2;
        if (memcmp(b->pts[m].p, p, sizeof(double) * 3) < 0) a = m + 1;
        else z = m;
    }
    *lo = a;
    while (a < b->n && memcmp(b->pts[a].p, p, sizeof(double) * 3) == 0) a++;
    *hi = a;
}

static bool on_same_border(const lod_border_set *b, const double *p, const double *q)
{
    int a0, a1, b0, b1;
    border_range(b, p, &a0, &a1);
    border_range(b, q, &b0, &b1);
    for (int i = a0; i < a1; i++)
        for (int j = b0; j < b1; j++)
            if (b->pts[i].seg == b->pts[j].seg) return true;
    return false;
}

typedef struct wv {
    double p[3];
    uint32_t id;
} wv;

static int cmp_dbl(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

typedef struct cellv {
    uint64_t key;
    uint32_t v;
} cellv;

static int cmp_cellv(const void *a, const void *b)
{
    uint64_t x = ((const cellv *)a)->key, y = ((const cellv *)b)->key;
    return (x > y) - (x < y);
}

static uint64_t ckey(int64_t x, int64_t y, int64_t z)
{
    return ((uint64_t)(x & 0x1FFFFF) << 42) | ((uint64_t)(y & 0x1FFFFF) << 21) | (uint64_t)(z & 0x1FFFFF);
}

void lod_check_mesh(const lod_border_set *b, const prw_lod_mesh *m, double eps_tj, lod_check_result *r)
{
    memset(r, 0, sizeof *r);
    r->min_rel_area = INFINITY;
    size_t nv = m->nverts;
    wv *w = prw_malloc(sizeof(wv) * nv + 1);
    for (size_t i = 0; i < nv; i++) {
        memcpy(w[i].p, m->pos + 3 * i, sizeof(double) * 3);
        w[i].id = (uint32_t)i;
    }
    qsort(w, nv, sizeof(wv), cmp_pos);
    uint32_t *weld = prw_malloc(sizeof(uint32_t) * nv + 1);
    double *wp = prw_malloc(sizeof(double) * 3 * nv + 1);
    uint32_t nw = 0;
    for (size_t i = 0; i < nv; i++) {
        if (i == 0 || memcmp(w[i].p, w[i - 1].p, sizeof(double) * 3) != 0) {
            memcpy(wp + 3 * nw, w[i].p, sizeof(double) * 3);
            nw++;
        }
        weld[w[i].id] = nw - 1;
    }
    free(w);
    r->verts = nw;
    r->tris = m->ntris;
    uint64_t *e = prw_malloc(sizeof(uint64_t) * 3 * m->ntris + 1);
    size_t ne = 0;
    double *lens = prw_malloc(sizeof(double) * m->ntris + 1);
    for (size_t t = 0; t < m->ntris; t++) {
        uint32_t v[3];
        for (int q = 0; q < 3; q++) v[q] = weld[m->tris[3 * t + q]];
        const double *a = wp + 3 * v[0], *bb = wp + 3 * v[1], *c = wp + 3 * v[2];
        double ab[3], ac[3], bc[3];
        for (int d = 0; d < 3; d++) ab[d] = bb[d] - a[d], ac[d] = c[d] - a[d], bc[d] = c[d] - bb[d];
        double cr[3] = {ab[1] * ac[2] - ab[2] * ac[1], ab[2] * ac[0] - ab[0] * ac[2], ab[0] * ac[1] - ab[1] * ac[0]};
        double l2 = fmax(ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2],
                         fmax(ac[0] * ac[0] + ac[1] * ac[1] + ac[2] * ac[2], bc[0] * bc[0] + bc[1] * bc[1] + bc[2] * bc[2]));
        double rel = sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]) / (l2 > 0 ? l2 : 1);
        if (!(rel > 1e-12)) r->zero_area++;
        r->min_rel_area = fmin(r->min_rel_area, rel);
        lens[t] = sqrt(l2);
        for (int q = 0; q < 3; q++) {
            uint32_t x = v[q], y = v[(q + 1) % 3];
            e[ne++] = x < y ? ((uint64_t)x << 32 | y) : ((uint64_t)y << 32 | x);
        }
    }
    qsort(e, ne, sizeof(uint64_t), cmp_u64);
    size_t nu = 0;
    for (size_t i = 0; i < ne;) {
        size_t j = i;
        while (j < ne && e[j] == e[i]) j++;
        int uses = (int)(j - i);
        uint32_t x = (uint32_t)(e[i] >> 32), y = (uint32_t)(e[i] & 0xFFFFFFFFu);
        if (uses == 1 && on_same_border(b, wp + 3 * x, wp + 3 * y)) r->border_edges++;
        else if (uses != 2) r->bad_edges++;
        e[nu++] = e[i];
        i = j;
    }
    r->edges = nu;
    if (eps_tj > 0 && nu > 0) {
        qsort(lens, m->ntris, sizeof(double), cmp_dbl);
        double cell = fmax(lens[m->ntris / 2], 1e-300);
        /* vertices within eps of an edge are searched in the cells the edge passes through */
        double o[3] = {INFINITY, INFINITY, INFINITY};
        for (uint32_t i = 0; i < nw; i++)
            for (int d = 0; d < 3; d++) o[d] = fmin(o[d], wp[3 * i + d]);
        cellv *cv = prw_malloc(sizeof(cellv) * nw + 1);
        for (uint32_t i = 0; i < nw; i++) {
            const double *p = wp + 3 * i;
            cv[i].key = ckey((int64_t)floor((p[0] - o[0]) / cell), (int64_t)floor((p[1] - o[1]) / cell),
                             (int64_t)floor((p[2] - o[2]) / cell));
            cv[i].v = i;
        }
        qsort(cv, nw, sizeof(cellv), cmp_cellv);
        for (size_t k = 0; k < nu; k++) {
            uint32_t x = (uint32_t)(e[k] >> 32), y = (uint32_t)(e[k] & 0xFFFFFFFFu);
            const double *a = wp + 3 * x, *bb = wp + 3 * y;
            double ab[3] = {bb[0] - a[0], bb[1] - a[1], bb[2] - a[2]};
            double l2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
            /* 3-D DDA over the cells the edge passes through */
            double p0[3], d[3], tmax[3], tdel[3];
            int64_t c[3], end[3], step[3];
            for (int q = 0; q < 3; q++) {
                p0[q] = (a[q] - o[q]) / cell;
                d[q] = ab[q] / cell;
                c[q] = (int64_t)floor(p0[q]);
                end[q] = (int64_t)floor((bb[q] - o[q]) / cell);
                step[q] = d[q] > 0 ? 1 : d[q] < 0 ? -1 : 0;
                tdel[q] = d[q] != 0 ? fabs(1 / d[q]) : INFINITY;
                tmax[q] = d[q] > 0 ? ((double)c[q] + 1 - p0[q]) / d[q] : d[q] < 0 ? ((double)c[q] - p0[q]) / d[q] : INFINITY;
            }
            for (int guard = 0; guard < 100000; guard++) {
                uint64_t key = ckey(c[0], c[1], c[2]);
                size_t s0 = 0, s1 = nw;
                while (s0 < s1) {
                    size_t mid = (s0 + s1) / 2;
                    if (cv[mid].key < key) s0 = mid + 1;
                    else s1 = mid;
                }
                for (size_t i = s0; i < nw && cv[i].key == key; i++) {
                    uint32_t v = cv[i].v;
                    if (v == x || v == y) continue;
                    const double *p = wp + 3 * v;
                    double ap[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
                    double t = l2 > 0 ? (ap[0] * ab[0] + ap[1] * ab[1] + ap[2] * ab[2]) / l2 : -1;
                    if (!(t > 0 && t < 1)) continue;
                    double dx = ap[0] - t * ab[0], dy = ap[1] - t * ab[1], dz = ap[2] - t * ab[2];
                    if (dx * dx + dy * dy + dz * dz <= eps_tj * eps_tj) {
                        if (getenv("LOD_DEBUG") && r->tjunctions < 3)
                            fprintf(stderr, "TJ: edge (%.17g %.17g %.17g)-(%.17g %.17g %.17g) v (%.17g %.17g %.17g) t %g\n",
                                    a[0], a[1], a[2], bb[0], bb[1], bb[2], p[0], p[1], p[2], t);
                        r->tjunctions++;
                    }
                }
                if (c[0] == end[0] && c[1] == end[1] && c[2] == end[2]) break;
                int q = tmax[0] <= tmax[1] && tmax[0] <= tmax[2] ? 0 : tmax[1] <= tmax[2] ? 1 : 2;
                if (tmax[q] > 1) break;
                c[q] += step[q];
                tmax[q] += tdel[q];
            }
        }
        free(cv);
    }
    free(lens);
    free(e);
    free(weld);
    free(wp);
}
