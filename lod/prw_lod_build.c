/* Per-patch LOD hierarchies: finest fixed-boundary tessellation, then greedy half-edge collapses
 * bounded by the triangle error bounds, snapshotted per level (see prw_lod.h). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_lod_internal.h"
#include "prw_predicates.h"
#include "prw_tess_fixed.h"

typedef struct work {
    const prw_seam_graph *g;
    const prw_nurbs_surface *s;
    prw_lod_patch *p;
    int **ladder;
    int *tri;
    unsigned char *alive;
    double *terr;
    int ntri;
    lod_ivec *vt;
    unsigned char *active;
    unsigned *stamp;
    lod_heap h;
    lod_ivec nb, nb2, tmp;
    int level;
    unsigned *vmark, *kmark, gen; /* de-duplication marks (per vertex / per weld key) */
    unsigned *pmark, pgen;        /* vertices whose candidates a collapse renews */
} work;

static int key(const work *w, int v) { return w->p->gid[v] >= 0 ? w->p->gid[v] : w->g->ngids + v; }

static void neighbours(work *w, int v, lod_ivec *out)
{
    out->n = 0;
    unsigned gen = ++w->gen;
    for (int k = 0; k < w->vt[v].n; k++) {
        const int *t = w->tri + 3 * w->vt[v].v[k];
        for (int q = 0; q < 3; q++) {
            int u = t[q];
            if (u == v || w->vmark[u] == gen) continue;
            w->vmark[u] = gen;
            lod_ipush(out, u);
        }
    }
}

static double seg_dist(prw_dvec3 x, prw_dvec3 a, prw_dvec3 b)
{
    prw_dvec3 ab = prw_v3_sub(b, a), ap = prw_v3_sub(x, a);
    double l2 = prw_v3_dot(ab, ab), t = l2 > 0 ? prw_v3_dot(ap, ab) / l2 : 0;
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    return prw_v3_len(prw_v3_sub(x, prw_v3_add(a, prw_v3_scale(ab, t))));
}

/* An interior pole copy: a vertex added by the level-0 refinement on a collapsed edge (same
 * global id and bit-identical position as the ring copies of its node). */
static bool interior_copy(const prw_lod_patch *p, int v) { return v >= p->nbound && p->gid[v] >= 0; }

/* A collapse target never takes more triangles than this: each collapse re-evaluates the
 * candidates of the target's 2-ring (quadratic in its valence), and a pole where every copy merged
 * into one (the apex of a cone from a B-rep) took minutes per level. */
#define LOD_MAX_TARGET_VALENCE 96

/* May v move at all at the current level, and may it move onto w (topologically)? */
static bool allowed(work *w, int v, int to)
{
    const prw_lod_patch *p = w->p;
    if (w->vt[to].n >= LOD_MAX_TARGET_VALENCE) return false;
    /* an interior pole copy only merges into another copy of its node (along the collapsed edge):
     * moving it anywhere else would open the (u, v) domain at the collapsed edge */
    if (interior_copy(p, v)) return p->gid[to] == p->gid[v];
    if (v < p->nbound) {
        if (p->gid[v] < w->g->nnodes) return false; /* a node */
        if (w->ladder[p->ring_seg[v]][p->ring_sidx[v]] >= w->level) return false;
        if (to >= p->nbound) return false;
        return lod_span(p, v, to, w->active, 0, &w->tmp); /* consecutive present ring vertices */
    }
    return true;
}

static void push_candidates(work *w, int v)
{
    if (!w->active[v]) return;
    neighbours(w, v, &w->nb);
    double verr = 0;
    for (int k = 0; k < w->vt[v].n; k++) verr = fmax(verr, w->terr[w->vt[v].v[k]]);
    for (int i = 0; i < w->nb.n; i++) {
        int to = w->nb.v[i];
        if (!allowed(w, v, to)) continue;
        /* cheap cost: distance of v to the planes of the triangles that would replace its own (and,
         * for a boundary vertex, to the new boundary edge) */
        double eps = 0;
        prw_dvec3 pv = w->p->pos[v], pt = w->p->pos[to];
        for (int k = 0; k < w->vt[v].n; k++) {
            const int *t = w->tri + 3 * w->vt[v].v[k];
            if (t[0] == to || t[1] == to || t[2] == to) continue;
            prw_dvec3 q[3];
            for (int c = 0; c < 3; c++) q[c] = t[c] == v ? pt : w->p->pos[t[c]];
            prw_dvec3 n = prw_v3_cross(prw_v3_sub(q[1], q[0]), prw_v3_sub(q[2], q[0]));
            double ln = prw_v3_len(n);
            if (ln > 0) eps = fmax(eps, fabs(prw_v3_dot(prw_v3_sub(pv, q[0]), n)) / ln);
        }
        if (v < w->p->nbound)
            for (int j = 0; j < w->nb.n; j++)
                if (j != i && w->nb.v[j] < w->p->nbound && lod_span(w->p, v, w->nb.v[j], w->active, 0, &w->tmp))
                    eps = fmax(eps, seg_dist(pv, pt, w->p->pos[w->nb.v[j]]));
        lod_heap_push(&w->h, (lod_hent){verr + eps, v, to, w->stamp[v], w->stamp[to]});
    }
}

/* Link condition on the welded mesh: the common neighbours of v and to (counted once per weld
 * key: several copies of one node are one welded vertex) are exactly the opposite vertices of the
 * edge, and v has no other neighbour welded to `to`. */
static bool welded_link_ok(work *w, int v, int to)
{
    lod_ivec *nv = &w->nb, *nt = &w->nb2;
    neighbours(w, v, nv);
    neighbours(w, to, nt);
    int kto = key(w, to);
    for (int i = 0; i < nv->n; i++)
        if (nv->v[i] != to && key(w, nv->v[i]) == kto) return false;
    int common = 0, opposite = 0;
    unsigned gen = ++w->gen;
    for (int j = 0; j < nt->n; j++)
        if (nt->v[j] != v) w->kmark[key(w, nt->v[j])] = gen;
    for (int i = 0; i < nv->n; i++) {
        int u = nv->v[i];
        if (u == to || w->kmark[key(w, u)] != gen) continue;
        common++;
        w->kmark[key(w, u)] = 0; /* once per key */
    }
    for (int k = 0; k < w->vt[v].n; k++) {
        const int *t = w->tri + 3 * w->vt[v].v[k];
        opposite += t[0] == to || t[1] == to || t[2] == to;
    }
    return common == opposite;
}

/* Full check of v -> to (topology, (u, v) validity, every new triangle's bound <= tau). */
static bool check(work *w, int v, int to, double tau)
{
    const prw_lod_patch *p = w->p;
    if (!allowed(w, v, to)) return false;
    /* two copies of one node merging: the welded mesh only loses triangles joining two copies (not
     * drawn), so only the (u, v) validity and the error bounds below decide */
    if (!interior_copy(p, v) && !welded_link_ok(w, v, to)) return false;
    /* geometry of the new triangles */
    w->active[v] = 0;
    bool ok = true;
    for (int k = 0; k < w->vt[v].n && ok; k++) {
        int t[3];
        memcpy(t, w->tri + 3 * w->vt[v].v[k], sizeof t);
        if (t[0] == to || t[1] == to || t[2] == to) continue;
        for (int q = 0; q < 3; q++)
            if (t[q] == v) t[q] = to;
        double e;
        ok = lod_triangle_eval(w->g, w->s, p, t[0], t[1], t[2], w->active, &e) && e <= tau;
    }
    w->active[v] = 1;
    return ok;
}

static void remove_tri_from(work *w, int v, int t)
{
    lod_ivec *l = &w->vt[v];
    for (int i = 0; i < l->n; i++)
        if (l->v[i] == t) {
            l->v[i] = l->v[--l->n];
            return;
        }
}

static void collapse(work *w, int v, int to)
{
    prw_lod_patch *p = w->p;
    w->active[v] = 0;
    p->removed_at[v] = w->level;
    lod_ivec l = w->vt[v];
    for (int k = 0; k < l.n; k++) {
        int ti = l.v[k];
        int *t = w->tri + 3 * ti;
        if (t[0] == to || t[1] == to || t[2] == to) {
            w->alive[ti] = 0;
            for (int q = 0; q < 3; q++)
                if (t[q] != v) remove_tri_from(w, t[q], ti);
            continue;
        }
        for (int q = 0; q < 3; q++)
            if (t[q] == v) t[q] = to;
        lod_ipush(&w->vt[to], ti);
    }
    w->vt[v].n = 0;
    /* new errors for the triangles around `to` (their spans may have changed too) */
    for (int k = 0; k < w->vt[to].n; k++) {
        int ti = w->vt[to].v[k];
        const int *t = w->tri + 3 * ti;
        lod_triangle_eval(w->g, w->s, p, t[0], t[1], t[2], w->active, &w->terr[ti]);
    }
    neighbours(w, to, &w->nb2);
    lod_ivec ring = {0};
    for (int i = 0; i < w->nb2.n; i++) lod_ipush(&ring, w->nb2.v[i]);
    lod_ipush(&ring, to);
    for (int i = 0; i < ring.n; i++) w->stamp[ring.v[i]]++;
    /* new candidates for the ring and its neighbours, each vertex once: the rings overlap, and a
     * vertex pushed twice leaves two valid heap entries whose full check() (surface evaluations)
     * would run twice */
    lod_ivec todo = {0};
    unsigned pgen = ++w->pgen;
    for (int i = 0; i < ring.n; i++) {
        int u = ring.v[i];
        if (w->pmark[u] != pgen) w->pmark[u] = pgen, lod_ipush(&todo, u);
        neighbours(w, u, &w->tmp);
        for (int j = 0; j < w->tmp.n; j++)
            if (w->pmark[w->tmp.v[j]] != pgen) w->pmark[w->tmp.v[j]] = pgen, lod_ipush(&todo, w->tmp.v[j]);
    }
    for (int i = 0; i < todo.n; i++) push_candidates(w, todo.v[i]);
    free(todo.v);
    free(ring.v);
}

/* Level-0 clean-up: edge flips (valid in (u, v) and in 3-D only) — first for triangles failing the
 * 3-D test (a sliver along a straight boundary: flip its longest edge), then towards the 3-D
 * Delaunay criterion (opposite angles summing to more than π), which removes the long ear-clipping
 * slivers of the boundary strip. */
static double angle_at(prw_dvec3 a, prw_dvec3 b, prw_dvec3 c)
{
    prw_dvec3 u = prw_v3_sub(b, a), v = prw_v3_sub(c, a);
    return atan2(prw_v3_len(prw_v3_cross(u, v)), prw_v3_dot(u, v));
}

static bool try_flip(work *w, int t, int k)
{
    const prw_lod_patch *p = w->p;
    int *tr = w->tri + 3 * t;
    int x = tr[k], y = tr[(k + 1) % 3], z = tr[(k + 2) % 3], t2 = -1, o = -1;
    for (int i = 0; i < w->vt[x].n && t2 < 0; i++) {
        int u = w->vt[x].v[i];
        const int *r = w->tri + 3 * u;
        if (u == t) continue;
        for (int q = 0; q < 3; q++)
            if (r[q] == y && r[(q + 1) % 3] == x) t2 = u, o = r[(q + 2) % 3];
    }
    if (t2 < 0 || o == z) return false;
    for (int i = 0; i < w->vt[z].n; i++) { /* the new edge z-o must not exist already */
        const int *r = w->tri + 3 * w->vt[z].v[i];
        if (r[0] == o || r[1] == o || r[2] == o) return false;
    }
    int n1[3] = {z, x, o}, n2[3] = {z, o, y};
    for (int h = 0; h < 2; h++) {
        const int *n = h ? n2 : n1;
        double uvc[2];
        prw_dvec3 xc;
        if (prw_orient2d(p->uv + 2 * n[0], p->uv + 2 * n[1], p->uv + 2 * n[2]) <= 0) return false;
        lod_centroid(p, n[0], n[1], n[2], uvc, &xc);
        if (!lod_tri3_ok(w->s, p, w->g->diag, n[0], n[1], n[2], uvc, p->pos[n[0]], p->pos[n[1]], p->pos[n[2]])) return false;
    }
    memcpy(tr, n1, sizeof n1);
    memcpy(w->tri + 3 * t2, n2, sizeof n2);
    remove_tri_from(w, x, t2);
    remove_tri_from(w, y, t);
    lod_ipush(&w->vt[z], t2);
    lod_ipush(&w->vt[o], t);
    return true;
}

static void improve_level0(work *w)
{
    const prw_lod_patch *p = w->p;
    for (int pass = 0; pass < 30; pass++) {
        int flips = 0;
        for (int t = 0; t < w->ntri; t++) {
            int *tr = w->tri + 3 * t;
            double uvc[2];
            prw_dvec3 xc;
            lod_centroid(p, tr[0], tr[1], tr[2], uvc, &xc);
            if (!lod_tri3_ok(w->s, p, w->g->diag, tr[0], tr[1], tr[2], uvc, p->pos[tr[0]], p->pos[tr[1]], p->pos[tr[2]])) {
                int k = 0;
                double best = -1;
                for (int q = 0; q < 3; q++) {
                    double l = prw_v3_len(prw_v3_sub(p->pos[tr[(q + 1) % 3]], p->pos[tr[q]]));
                    if (l > best) best = l, k = q;
                }
                flips += try_flip(w, t, k);
                continue;
            }
            for (int k = 0; k < 3; k++) {
                int x = tr[k], y = tr[(k + 1) % 3], z = tr[(k + 2) % 3], o = -1;
                for (int i = 0; i < w->vt[x].n && o < 0; i++) {
                    const int *r = w->tri + 3 * w->vt[x].v[i];
                    for (int q = 0; q < 3; q++)
                        if (r[q] == y && r[(q + 1) % 3] == x) o = r[(q + 2) % 3];
                }
                if (o < 0) continue;
                double sum = angle_at(p->pos[z], p->pos[x], p->pos[y]) + angle_at(p->pos[o], p->pos[y], p->pos[x]);
                if (sum > PRW_PI + 1e-9 && try_flip(w, t, k)) {
                    flips++;
                    break;
                }
            }
        }
        if (!flips) break;
    }
}

/* Level-0 refinement: until every triangle's error bound is <= tau0 (or the boundary chords alone
 * bound it higher — interior refinement cannot lower that part), split the longest non-boundary
 * edge of each offending triangle at its (u, v) midpoint together with the triangle across it
 * (2 -> 4 triangles, conforming; sewing points are never added), then Lawson-flip around the new
 * vertex; a sliver across is flipped instead; collapsed edges split into more node copies.  Splits
 * whose new triangles fail the orientation / 3-D tests are refused (the triangle may still be cut
 * later as a neighbour's partner); what is left above at the end is counted. */
#ifndef PRW_LOD_MAX_VALENCE
#define PRW_LOD_MAX_VALENCE 24
#endif
typedef struct refine_state {
    int vcap, tcap;
    int refused;
} refine_state;

static int find_across(const work *w, int t, int x, int y)
{
    for (int i = 0; i < w->vt[x].n; i++) {
        int u = w->vt[x].v[i];
        if (u == t || !w->alive[u]) continue;
        const int *r = w->tri + 3 * u;
        for (int q = 0; q < 3; q++)
            if (r[q] == y && r[(q + 1) % 3] == x) return u;
    }
    return -1;
}

/* copy_of >= 0: the new vertex is a copy of that vertex's node (a split of a collapsed edge) */
static int add_vertex(work *w, refine_state *rs, int levels, const double *uv, int copy_of)
{
    prw_lod_patch *p = w->p;
    if (p->nverts == rs->vcap) {
        rs->vcap = 2 * rs->vcap + 16;
        p->uv = prw_realloc(p->uv, sizeof(double) * 2 * (size_t)rs->vcap);
        p->pos = prw_realloc(p->pos, sizeof(prw_dvec3) * (size_t)rs->vcap);
        p->gid = prw_realloc(p->gid, sizeof(int) * (size_t)rs->vcap);
        p->removed_at = prw_realloc(p->removed_at, sizeof(int) * (size_t)rs->vcap);
        w->vt = prw_realloc(w->vt, sizeof(lod_ivec) * (size_t)rs->vcap);
        w->active = prw_realloc(w->active, (size_t)rs->vcap);
        w->stamp = prw_realloc(w->stamp, sizeof(unsigned) * (size_t)rs->vcap);
    }
    int v = p->nverts++;
    p->uv[2 * v] = uv[0], p->uv[2 * v + 1] = uv[1];
    p->pos[v] = copy_of >= 0 ? p->pos[copy_of] : prw_nurbs_surface_eval(w->s, uv[0], uv[1]);
    p->gid[v] = copy_of >= 0 ? p->gid[copy_of] : -1;
    p->removed_at[v] = levels;
    memset(&w->vt[v], 0, sizeof w->vt[v]);
    w->active[v] = 1;
    w->stamp[v] = 0;
    return v;
}

static int add_tri(work *w, refine_state *rs)
{
    if (w->ntri == rs->tcap) {
        rs->tcap = 2 * rs->tcap + 16;
        w->tri = prw_realloc(w->tri, sizeof(int) * 3 * (size_t)rs->tcap);
        w->alive = prw_realloc(w->alive, (size_t)rs->tcap);
        w->terr = prw_realloc(w->terr, sizeof(double) * (size_t)rs->tcap);
    }
    w->alive[w->ntri] = 1;
    return w->ntri++;
}

static bool needs_refine(work *w, int t, double tau0)
{
    const int *r = w->tri + 3 * t;
    double be;
    lod_triangle_eval_parts(w->g, w->s, w->p, r[0], r[1], r[2], w->active, &w->terr[t], &be);
    return w->terr[t] > fmax(tau0, be);
}

/* Does the straight (u, v) segment a -> b map to the single point of a (a collapsed edge)? */
static bool collapsed_edge(const work *w, int a, int b)
{
    const prw_lod_patch *p = w->p;
    if (p->gid[a] < 0 || p->gid[a] != p->gid[b]) return false;
    for (int k = 1; k < 4; k++) {
        double t = k / 4.0, u = (1 - t) * p->uv[2 * a] + t * p->uv[2 * b], v = (1 - t) * p->uv[2 * a + 1] + t * p->uv[2 * b + 1];
        if (!(prw_v3_len(prw_v3_sub(prw_nurbs_surface_eval(w->s, u, v), p->pos[a])) <= w->g->tol)) return false;
    }
    return true;
}

static void kill_tri(work *w, int t)
{
    w->alive[t] = 0;
    for (int q = 0; q < 3; q++) remove_tri_from(w, w->tri[3 * t + q], t);
}

static int ring_next(const prw_lod_patch *p, int v)
{
    int r = p->ring_of[v];
    return v + 1 == p->ring_start[r + 1] ? p->ring_start[r] : v + 1;
}

static int ring_prev(const prw_lod_patch *p, int v)
{
    int r = p->ring_of[v];
    return v == p->ring_start[r] ? p->ring_start[r + 1] - 1 : v - 1;
}

/* Level-0 pole comb: the ear clipping fans the triangles at a collapsed ring edge (a, b) out of a
 * and b, so a triangle's node copy sits far (along the edge) from the part of the surface the
 * triangle covers, its (u, v) error is large and no bisection fixes it (a split of its edges to a
 * or b inverts the 3-D triangle).  The star of the node's copies on the edge (a, b and interior
 * copies) — bounded by the edge and the chain x_0 .. x_N of their other neighbours — is
 * re-triangulated as a comb (old interior copies are left unused): copy d_i of the node on the edge
 * at the projection of the middle of (x_i, x_{i+1}), a drawn triangle (d_i, x_{i+1}, x_i) and
 * triangles joining consecutive copies (not drawn).  Skipped (the star kept) when the chain does
 * not project monotonically or a new triangle is invalid.  Returns the triangles made. */
static int pole_comb(work *w, refine_state *rs, int levels, int a, int b)
{
    prw_lod_patch *p = w->p;
    lod_ivec x = {0}, old = {0}, he = {0};
    double *tt = NULL;
    int made = 0, xn = ring_next(p, b), x0 = ring_prev(p, a), node = p->gid[a];
    /* the star: every triangle at a, b or an interior copy of the node (earlier combs and splits) */
    for (int v = 0; v < p->nverts; v++) {
        if (!(v == a || v == b || (interior_copy(p, v) && p->gid[v] == node))) continue;
        for (int i = 0; i < w->vt[v].n; i++) {
            int t = w->vt[v].v[i];
            bool seen = false;
            for (int j = 0; j < old.n && !seen; j++) seen = old.v[j] == t;
            if (!seen) lod_ipush(&old, t);
        }
    }
    /* its inner boundary: half-edges u -> v of star triangles between two non-copies whose twin
     * is not in the star, followed from xn to x0 */
    for (int i = 0; i < old.n; i++) {
        const int *r = w->tri + 3 * old.v[i];
        for (int k = 0; k < 3; k++) {
            int u = r[k], v = r[(k + 1) % 3];
            if (p->gid[u] == node || p->gid[v] == node) continue;
            int t2 = find_across(w, old.v[i], u, v);
            bool in = false;
            for (int j = 0; j < old.n && !in && t2 >= 0; j++) in = old.v[j] == t2;
            if (!in) lod_ipush(&he, u), lod_ipush(&he, v);
        }
    }
    lod_ipush(&x, xn);
    while (x.v[x.n - 1] != x0 && x.n <= he.n / 2 + 1) {
        int cur = x.v[x.n - 1], next = -1;
        for (int i = 0; i < he.n && next < 0; i += 2)
            if (he.v[i] == cur) next = he.v[i + 1];
        if (next < 0) goto done;
        lod_ipush(&x, next);
    }
    if (x.v[x.n - 1] != x0 || x.n != he.n / 2 + 1) goto done;
    for (int i = 0, j = x.n - 1; i < j; i++, j--) { /* from the a side */
        int t = x.v[i];
        x.v[i] = x.v[j], x.v[j] = t;
    }
    int n = x.n - 1; /* copies to make */
    if (n < 1) goto done;
    for (int i = 0; i < x.n; i++) {
        if (p->gid[x.v[i]] == p->gid[a]) goto done;
        for (int j = 0; j < i; j++)
            if (x.v[j] == x.v[i]) goto done;
    }
    const double ua[2] = {p->uv[2 * a], p->uv[2 * a + 1]}, ub[2] = {p->uv[2 * b], p->uv[2 * b + 1]}; /* add_vertex reallocates */
    double e[2] = {ub[0] - ua[0], ub[1] - ua[1]}, e2 = e[0] * e[0] + e[1] * e[1];
    if (!(e2 > 0)) goto done;
    tt = prw_malloc(sizeof(double) * (size_t)x.n);
    for (int i = 0; i < x.n; i++) tt[i] = ((p->uv[2 * x.v[i]] - ua[0]) * e[0] + (p->uv[2 * x.v[i] + 1] - ua[1]) * e[1]) / e2;
    for (int i = 0; i < n; i++) {
        double si = 0.5 * (tt[i] + tt[i + 1]), prev = i ? 0.5 * (tt[i - 1] + tt[i]) : 0;
        if (!(si > prev) || !(si < 1)) goto done;
    }
    int v0 = p->nverts;
    for (int i = 0; i < n; i++) {
        double si = 0.5 * (tt[i] + tt[i + 1]), uv[2] = {ua[0] + si * e[0], ua[1] + si * e[1]};
        add_vertex(w, rs, levels, uv, a);
    }
    /* the comb: (a, d0, x0), then per i (d_i, x_{i+1}, x_i) and (d_i, d_{i+1} | b, x_{i+1}) */
    int nt = 2 * n + 1;
    int(*tri)[3] = prw_malloc(sizeof(int[3]) * (size_t)nt);
    double *err = prw_malloc(sizeof(double) * (size_t)nt);
    tri[0][0] = a, tri[0][1] = v0, tri[0][2] = x.v[0];
    for (int i = 0; i < n; i++) {
        int d = v0 + i, dn = i + 1 < n ? d + 1 : b;
        tri[1 + 2 * i][0] = d, tri[1 + 2 * i][1] = x.v[i + 1], tri[1 + 2 * i][2] = x.v[i];
        tri[2 + 2 * i][0] = d, tri[2 + 2 * i][1] = dn, tri[2 + 2 * i][2] = x.v[i + 1];
    }
    bool ok = true;
    for (int k = 0; k < nt && ok; k++) ok = lod_triangle_eval(w->g, w->s, p, tri[k][0], tri[k][1], tri[k][2], w->active, &err[k]);
    if (ok) {
        for (int i = 0; i < old.n; i++) kill_tri(w, old.v[i]);
        for (int k = 0; k < nt; k++) {
            int t = add_tri(w, rs);
            memcpy(w->tri + 3 * t, tri[k], sizeof tri[k]);
            w->terr[t] = err[k];
            for (int q = 0; q < 3; q++) lod_ipush(&w->vt[tri[k][q]], t);
        }
        made = nt;
    } else {
        for (int v = v0; v < p->nverts; v++) free(w->vt[v].v);
        p->nverts = v0;
    }
    free(tri);
    free(err);
done:
    free(he.v);
    free(x.v);
    free(old.v);
    free(tt);
    return made;
}

/* Is o within 1/8 of |xy| of the line through x and y (lengths in (u, v) scaled by su, sv)? */
static bool sliver_apex(const prw_lod_patch *p, double su, double sv, int x, int y, int o)
{
    double ex = su * (p->uv[2 * y] - p->uv[2 * x]), ey = sv * (p->uv[2 * y + 1] - p->uv[2 * x + 1]);
    double ox = su * (p->uv[2 * o] - p->uv[2 * x]), oy = sv * (p->uv[2 * o + 1] - p->uv[2 * x + 1]);
    double l2 = ex * ex + ey * ey;
    return l2 > 0 && fabs(ex * oy - ey * ox) < 0.125 * l2;
}

/* Lawson flips around a vertex m new from a split, toward the 3-D Delaunay criterion (opposite
 * angles summing to more than π), as in improve_level0: bisection alone leaves the ear clipping's
 * long fans of slivers along the boundary, whose halves fail the 3-D tests.  Quads with two copies
 * of one node are left alone.  Changed triangles get new bounds and are queued if needed. */
static void legalize(work *w, int m, double tau0, lod_ivec *q)
{
    const prw_lod_patch *p = w->p;
    int budget = 64; /* flips per call: the 3-D criterion on a curved surface need not settle */
    lod_ivec st = {0};
    for (int i = 0; i < w->vt[m].n; i++) lod_ipush(&st, w->vt[m].v[i]);
    while (st.n > 0 && budget > 0) {
        int t = st.v[--st.n];
        if (!w->alive[t]) continue;
        const int *tr = w->tri + 3 * t;
        int km = tr[0] == m ? 0 : tr[1] == m ? 1 : tr[2] == m ? 2 : -1;
        if (km < 0) continue;
        int k = (km + 1) % 3, x = tr[k], y = tr[(k + 1) % 3];
        int t2 = find_across(w, t, x, y);
        if (t2 < 0) continue;
        const int *r2 = w->tri + 3 * t2;
        int o = r2[0] != x && r2[0] != y ? r2[0] : r2[1] != x && r2[1] != y ? r2[1] : r2[2];
        int qv[4] = {m, x, y, o};
        bool shared = false;
        for (int a = 0; a < 4; a++)
            for (int b = a + 1; b < 4; b++) shared = shared || (p->gid[qv[a]] >= 0 && p->gid[qv[a]] == p->gid[qv[b]]);
        if (shared) continue;
        double sum = angle_at(p->pos[m], p->pos[x], p->pos[y]) + angle_at(p->pos[o], p->pos[y], p->pos[x]);
        if (!(sum > PRW_PI + 1e-9) || !try_flip(w, t, k)) continue;
        budget--;
        for (int h = 0; h < 2; h++) {
            int tf = h ? t2 : t;
            if (needs_refine(w, tf, tau0)) lod_ipush(q, tf);
            lod_ipush(&st, tf);
        }
    }
    free(st.v);
}

static void refine_level0(work *w, int levels, double tau0, int max_tris, int max_valence, int *refused)
{
    prw_lod_patch *p = w->p;
    refine_state rs = {.vcap = p->nverts, .tcap = w->ntri};
    for (int r = 0; r < p->nrings; r++)
        for (int a = p->ring_start[r]; a < p->ring_start[r + 1]; a++)
            if (collapsed_edge(w, a, ring_next(p, a))) pole_comb(w, &rs, levels, a, ring_next(p, a));
    lod_ivec q = {0};
    for (int t = 0; t < w->ntri; t++)
        if (w->alive[t] && needs_refine(w, t, tau0)) lod_ipush(&q, t);
    /* edge lengths in (u, v) scaled by the mean speeds |S_u|, |S_v| over the patch's vertices: a
     * (u, v) bisection (unlike a 3-D one) also refines triangles fanning out of a pole */
    double su = 0, sv = 0;
    int ns = 0;
    for (int v = 0; v < p->nverts; v += 1 + p->nverts / 64) {
        prw_dvec3 d[4];
        prw_nurbs_surface_derivs(w->s, p->uv[2 * v], p->uv[2 * v + 1], 1, d);
        double a = prw_v3_len(d[2]), b = prw_v3_len(d[1]); /* d[2] = S_u, d[1] = S_v */
        if (isfinite(a) && isfinite(b)) su += a, sv += b, ns++;
    }
    su = ns && su > 0 ? su / ns : 1;
    sv = ns && sv > 0 ? sv / ns : 1;
    int flip_budget = 16 * w->ntri + 4096, attempts_refused = 0;
    for (int round = 0;; round++) {
    for (int head = 0; head < q.n; head++) {
        int t = q.v[head];
        if (!w->alive[t] || !(w->terr[t] > tau0)) continue; /* stale entry */
        if (w->ntri + 2 > max_tris) {
            attempts_refused++;
            continue;
        }
        const int *r = w->tri + 3 * t;
        /* edges by decreasing 3-D length; the first non-boundary one with a triangle across */
        int order[3] = {0, 1, 2};
        double len[3];
        for (int k = 0; k < 3; k++) {
            const double *a = p->uv + 2 * r[k], *b = p->uv + 2 * r[(k + 1) % 3];
            len[k] = hypot(su * (b[0] - a[0]), sv * (b[1] - a[1]));
        }
        for (int i = 0; i < 3; i++)
            for (int j = i + 1; j < 3; j++)
                if (len[order[j]] > len[order[i]]) {
                    int x = order[i];
                    order[i] = order[j], order[j] = x;
                }
        bool done = false;
        for (int oi = 0; oi < 3 && !done; oi++) {
            int k = order[oi], x = r[k], y = r[(k + 1) % 3], z = r[(k + 2) % 3];
            /* a collapsed edge (two copies of one node, the (u, v) segment between them mapping to
             * that point): split too, the new vertex being one more copy of the node */
            bool collapsed = collapsed_edge(w, x, y);
            if (!collapsed && p->gid[x] >= 0 && p->gid[x] == p->gid[y]) continue; /* e.g. a periodic seam */
            double uv[2] = {0.5 * (p->uv[2 * x] + p->uv[2 * y]), 0.5 * (p->uv[2 * x + 1] + p->uv[2 * y + 1])};
            if (!collapsed && lod_span(p, x, y, w->active, 0, &w->tmp) && w->tmp.n == 0) continue; /* boundary edge */
            int t2 = find_across(w, t, x, y), o = -1;
            if (t2 < 0 && !collapsed) continue;
            if (t2 >= 0) {
                const int *r2 = w->tri + 3 * t2;
                o = r2[0] != x && r2[0] != y ? r2[0] : r2[1] != x && r2[1] != y ? r2[1] : r2[2];
                /* a sliver across (its apex o within 1/8 of the edge's length from it, in scaled
                 * (u, v)): halving the edge would leave slivers no split can cure — flip the edge to
                 * (z, o) instead */
                if (!collapsed && flip_budget > 0 && sliver_apex(p, su, sv, x, y, o) && try_flip(w, t, k)) {
                    flip_budget--;
                    for (int h = 0; h < 2; h++) {
                        int tf = h ? t2 : t;
                        if (needs_refine(w, tf, tau0)) lod_ipush(&q, tf);
                    }
                    done = true;
                    break;
                }
                if (w->vt[o].n >= max_valence) continue;
            }
            if (w->vt[z].n >= max_valence) continue; /* no fans: they would stall the collapses */
            int m = add_vertex(w, &rs, levels, uv, collapsed ? x : -1);
            int nt[4][3] = {{x, m, z}, {m, y, z}, {y, m, o}, {m, x, o}};
            int nn = t2 >= 0 ? 4 : 2;
            bool ok = true;
            double err[4];
            for (int h = 0; h < nn && ok; h++)
                ok = lod_triangle_eval(w->g, w->s, p, nt[h][0], nt[h][1], nt[h][2], w->active, &err[h]);
            if (!ok) {
                p->nverts--;
                continue;
            }
            int t3 = add_tri(w, &rs), t4 = nn == 4 ? add_tri(w, &rs) : -1;
            int ids[4] = {t, t3, t2, t4};
            remove_tri_from(w, y, t);
            lod_ipush(&w->vt[y], t3);
            lod_ipush(&w->vt[z], t3);
            if (nn == 4) {
                remove_tri_from(w, x, t2);
                lod_ipush(&w->vt[x], t4);
                lod_ipush(&w->vt[o], t4);
            }
            for (int h = 0; h < nn; h++) {
                memcpy(w->tri + 3 * ids[h], nt[h], sizeof nt[h]);
                w->terr[ids[h]] = err[h];
                lod_ipush(&w->vt[m], ids[h]);
            }
            for (int h = 0; h < nn; h++)
                if (needs_refine(w, ids[h], tau0)) lod_ipush(&q, ids[h]);
            if (!collapsed) legalize(w, m, tau0, &q);
            flip_budget += 2;
            done = true;
        }
        if (!done) attempts_refused++;
        if (head > (1 << 20) && head > q.n / 2) { /* compact the queue */
            memmove(q.v, q.v + head + 1, sizeof(int) * (size_t)(q.n - head - 1));
            q.n -= head + 1;
            head = -1;
        }
    }
    /* a stall at a pole (an interior vertex fanned to node copies far from it along the edge: no
     * split of its edges is valid there) — comb the pole again from its now refined chain and go
     * on; at most 3 times */
    q.n = 0;
    bool stalled = false;
    for (int t = 0; t < w->ntri && attempts_refused; t++) {
        if (!w->alive[t] || !needs_refine(w, t, tau0)) continue;
        lod_ipush(&q, t);
        const int *r = w->tri + 3 * t;
        stalled = stalled || p->gid[r[0]] >= 0 || p->gid[r[1]] >= 0 || p->gid[r[2]] >= 0;
    }
    if (!stalled || round == 3 || w->ntri + 2 > max_tris) break;
    int combed = 0;
    for (int r = 0; r < p->nrings; r++)
        for (int a = p->ring_start[r]; a < p->ring_start[r + 1]; a++)
            if (p->gid[a] >= 0 && p->gid[ring_next(p, a)] == p->gid[a] && collapsed_edge(w, a, ring_next(p, a)))
                combed += pole_comb(w, &rs, levels, a, ring_next(p, a)) > 0;
    if (!combed) break;
    q.n = 0;
    for (int t = 0; t < w->ntri; t++)
        if (w->alive[t] && needs_refine(w, t, tau0)) lod_ipush(&q, t);
    attempts_refused = 0;
    }
    /* what is left above (a refused split may be made good by a later split of a neighbour) */
    if (attempts_refused)
        for (int t = 0; t < w->ntri; t++) *refused += w->alive[t] && needs_refine(w, t, tau0);
    free(q.v);
}

static void snapshot(work *w, lod_ivec *tris, int level)
{
    prw_lod_patch *p = w->p;
    p->tri_start[level] = tris->n / 3;
    double e = 0;
    for (int t = 0; t < w->ntri; t++) {
        if (!w->alive[t]) continue;
        for (int q = 0; q < 3; q++) lod_ipush(tris, w->tri[3 * t + q]);
        e = fmax(e, w->terr[t]);
    }
    p->err[level] = e;
}

/* Rings from the seam loops; fails (patch not drawn) on loops that cannot be tessellated. */
static bool build_patch(prw_lod_model *lm, const prw_nurbs_model *m, int pi, int max_cells, int max_tris, prw_error *e)
{
    const prw_seam_graph *g = lm->g;
    const prw_seam_patch *P = &g->patches[pi];
    prw_lod_patch *p = &lm->patches[pi];
    p->lo = P->lo;
    p->hi = P->hi;
    if (P->skipped) return prw_fail(e, "patch %d: skipped by the seam graph", pi);
    lod_ivec rs = {0}, seg = {0}, sidx = {0}, rev = {0}, side = {0};
    lod_ipush(&rs, 0);
    for (int l = 0; l < P->nloops; l++) {
        int first = seg.n;
        for (int u = 0; u < P->loops[l].count; u++) {
            const prw_seam_use *us = &P->loops[l].uses[u];
            int n = g->segs[us->seg].npts;
            for (int k = 0; k < n - 1; k++) {
                lod_ipush(&seg, us->seg);
                lod_ipush(&sidx, us->reversed ? n - 1 - k : k);
                lod_ipush(&rev, us->reversed);
                lod_ipush(&side, us->side);
            }
        }
        /* a loop needs 3 distinct sewing points */
        int distinct = 0;
        for (int i = first; i < seg.n && distinct < 3; i++) {
            int gi = prw_seam_point_gid(g, seg.v[i], sidx.v[i]);
            bool dup = false;
            for (int j = first; j < i && !dup; j++) dup = prw_seam_point_gid(g, seg.v[j], sidx.v[j]) == gi;
            distinct += !dup;
        }
        if (distinct < 3) seg.n = sidx.n = rev.n = side.n = first;
        else lod_ipush(&rs, seg.n);
    }
    int nb = seg.n;
    p->nrings = rs.n - 1;
    p->ring_start = rs.v;
    p->ring_seg = seg.v;
    p->ring_sidx = sidx.v;
    p->ring_rev = prw_malloc((size_t)nb + 1);
    p->ring_of = prw_malloc(sizeof(int) * (size_t)nb + 1);
    double *buv = prw_malloc(sizeof(double) * 2 * (size_t)nb + 1);
    for (int r = 0; r < p->nrings; r++)
        for (int i = p->ring_start[r]; i < p->ring_start[r + 1]; i++) p->ring_of[i] = r;
    for (int i = 0; i < nb; i++) {
        p->ring_rev[i] = (unsigned char)rev.v[i];
        const double *uv = g->segs[seg.v[i]].uv[side.v[i]];
        buv[2 * i] = uv[2 * sidx.v[i]];
        buv[2 * i + 1] = uv[2 * sidx.v[i] + 1];
    }
    free(rev.v);
    free(side.v);
    p->nbound = nb;
    const prw_nurbs_surface *s = &m->surfaces[pi].surface;
    prw_tess_fixed_mesh tm;
    if (p->nrings == 0) {
        free(buv);
        return prw_fail(e, "patch %d: no boundary loop with 3 distinct sewing points", pi);
    }
    /* ear clipping can strand collinear boundary chains for some grids: retry with other cell sizes */
    static const double scales[] = {1, 0.7, 1.4, 0.5, 2};
    bool tok = false;
    for (int k = 0; k < 5 && !tok; k++) tok = prw_tess_fixed(s, buv, p->ring_start, p->nrings, g->chord, max_cells, scales[k], &tm, e);
    if (!tok) {
        free(buv);
        return prw_fail_wrap(e, "patch %d", pi);
    }
    free(buv);
    p->nverts = tm.nverts;
    p->uv = tm.uv;
    tm.uv = NULL;
    p->pos = prw_malloc(sizeof(prw_dvec3) * (size_t)p->nverts);
    p->gid = prw_malloc(sizeof(int) * (size_t)p->nverts);
    p->removed_at = prw_malloc(sizeof(int) * (size_t)p->nverts);
    for (int v = 0; v < p->nverts; v++) {
        p->removed_at[v] = lm->levels;
        if (v < nb) {
            p->gid[v] = prw_seam_point_gid(g, p->ring_seg[v], p->ring_sidx[v]);
            p->pos[v] = g->segs[p->ring_seg[v]].pts[p->ring_sidx[v]];
        } else {
            p->gid[v] = -1;
            p->pos[v] = prw_nurbs_surface_eval(s, p->uv[2 * v], p->uv[2 * v + 1]);
        }
    }
    work w;
    memset(&w, 0, sizeof w);
    w.g = g;
    w.s = s;
    w.p = p;
    w.ladder = lm->ladder;
    w.ntri = tm.ntris;
    w.tri = tm.tris;
    tm.tris = NULL;
    prw_tess_fixed_free(&tm);
    w.alive = prw_malloc((size_t)w.ntri + 1);
    w.terr = prw_malloc(sizeof(double) * (size_t)w.ntri + 1);
    w.vt = prw_calloc((size_t)p->nverts, sizeof(lod_ivec));
    w.active = prw_malloc((size_t)p->nverts);
    w.stamp = prw_calloc((size_t)p->nverts, sizeof(unsigned));
    memset(w.active, 1, (size_t)p->nverts);
    for (int t = 0; t < w.ntri; t++) {
        w.alive[t] = 1;
        for (int q = 0; q < 3; q++) lod_ipush(&w.vt[w.tri[3 * t + q]], t);
    }
    improve_level0(&w);
    /* max_tris > 0: the caller's cap; else at most 2x + 4096 the initial count (the collapse
     * phase is super-linear in the valence of hub vertices) */
    refine_level0(&w, lm->levels, lm->tau0, max_tris > 0 ? max_tris : 2 * w.ntri + 4096, PRW_LOD_MAX_VALENCE,
                  &lm->refused_splits);
    for (int t = 0; t < w.ntri; t++)
        lod_triangle_eval(g, s, p, w.tri[3 * t], w.tri[3 * t + 1], w.tri[3 * t + 2], w.active, &w.terr[t]);
    w.vmark = prw_calloc((size_t)p->nverts + 1, sizeof(unsigned));
    w.kmark = prw_calloc((size_t)(g->ngids + p->nverts) + 1, sizeof(unsigned));
    w.pmark = prw_calloc((size_t)p->nverts + 1, sizeof(unsigned));
    p->tri_start = prw_malloc(sizeof(int) * (size_t)(lm->levels + 1));
    p->err = prw_malloc(sizeof(double) * (size_t)lm->levels);
    lod_ivec tris = {0};
    snapshot(&w, &tris, 0);
    /* an iteration cap per level (never reached on the procedural and test models: a hang guard);
     * a level stopped by it is still valid (every collapse made was checked), only coarser ones
     * keep more triangles than they could; reported in first_problem */
    long cap = 2000L * (p->nverts + 64);
    for (int k = 1; k < lm->levels; k++) {
        w.level = k;
        double tau = lm->tau0 * ldexp(1.0, k);
        w.h.n = 0;
        for (int v = 0; v < p->nverts; v++) push_candidates(&w, v);
        long pops = 0;
        while (w.h.n > 0) {
            if (++pops > cap) {
                lm->capped_levels++;
                if (!lm->first_problem[0])
                    snprintf(lm->first_problem, sizeof lm->first_problem,
                             "patch %d level %d: collapse search stopped at its cap of %ld candidates", pi, k, cap);
                break;
            }
            lod_hent x = lod_heap_pop(&w.h);
            if (x.cost > tau) break;
            if (!w.active[x.v] || !w.active[x.w] || w.stamp[x.v] != x.sv || w.stamp[x.w] != x.sw) continue;
            if (!check(&w, x.v, x.w, tau)) continue;
            collapse(&w, x.v, x.w);
        }
        snapshot(&w, &tris, k);
    }
    p->tri_start[lm->levels] = tris.n / 3;
    p->tris = tris.v;
    for (int v = 0; v < p->nverts; v++) free(w.vt[v].v);
    free(w.vt);
    free(w.tri);
    free(w.alive);
    free(w.terr);
    free(w.active);
    free(w.stamp);
    free(w.vmark);
    free(w.kmark);
    free(w.pmark);
    free(w.h.a);
    free(w.nb.v);
    free(w.nb2.v);
    free(w.tmp.v);
    p->ok = true;
    return true;
}

bool prw_lod_build(const prw_nurbs_model *m, const prw_seam_graph *g, const prw_lod_options *o, prw_lod_model *lm,
                   prw_error *e)
{
    memset(lm, 0, sizeof *lm);
    prw_lod_options opt = o ? *o : (prw_lod_options){0};
    lm->g = g;
    lm->levels = opt.levels > 0 ? (opt.levels > PRW_LOD_MAX_LEVELS ? PRW_LOD_MAX_LEVELS : opt.levels) : 14;
    lm->tau0 = opt.tau0 > 0 ? opt.tau0 : opt.finest_rel > 0 ? opt.finest_rel * g->diag : g->chord;
    if (opt.finest_rel > 0 && opt.levels <= 0) {
        int need = (int)ceil(log2(g->diag / lm->tau0)) + 1;
        lm->levels = need < 14 ? 14 : need > PRW_LOD_MAX_LEVELS ? PRW_LOD_MAX_LEVELS : need;
    }
    if ((int)m->count != g->npatches) return prw_fail(e, "lod: model has %zu patches, seam graph %d", m->count, g->npatches);
    lm->npatches = g->npatches;
    lm->patches = prw_calloc((size_t)g->npatches + 1, sizeof(prw_lod_patch));
    lm->ladder = prw_malloc(sizeof(int *) * (size_t)g->nsegs + 1);
    lm->seg_keep = prw_malloc(sizeof(int *) * (size_t)g->nsegs + 1);
    for (int s = 0; s < g->nsegs; s++) {
        lm->ladder[s] = prw_malloc(sizeof(int) * (size_t)g->segs[s].npts);
        lm->seg_keep[s] = prw_malloc(sizeof(int) * (size_t)g->segs[s].npts);
    }
    prw_lod_ladders(g, lm->levels, lm->tau0, lm->ladder);
    for (int s = 0; s < g->nsegs; s++) memcpy(lm->seg_keep[s], lm->ladder[s], sizeof(int) * (size_t)g->segs[s].npts);
    double t_last = prw_now(), t_start = t_last;
    for (int pi = 0; pi < g->npatches; pi++) {
        if (opt.progress && prw_now() - t_last >= 1.0) { /* at most one line a second */
            char line[160];
            snprintf(line, sizeof line, "hierarchy: patch %d of %d, %zu finest triangles so far, %.1f s", pi + 1,
                     g->npatches, lm->finest_triangles, prw_now() - t_start);
            opt.progress(opt.progress_user, line);
            t_last = prw_now();
        }
        prw_error pe;
        int cap = opt.max_patch_triangles > 0 ? opt.max_patch_triangles : opt.finest_rel > 0 ? INT32_MAX / 8 : 0;
        if (!build_patch(lm, m, pi, opt.max_cells > 0 ? opt.max_cells : 48, cap, &pe)) {
            lm->failed_patches++;
            if (!lm->first_problem[0]) snprintf(lm->first_problem, sizeof lm->first_problem, "%.200s", pe.msg);
            continue;
        }
        const prw_lod_patch *p = &lm->patches[pi];
        lm->finest_triangles += (size_t)(p->tri_start[1] - p->tri_start[0]);
        for (int v = 0; v < p->nbound; v++) {
            if (p->gid[v] < g->nnodes) continue;
            int *k = &lm->seg_keep[p->ring_seg[v]][p->ring_sidx[v]];
            if (p->removed_at[v] - 1 > *k) *k = p->removed_at[v] - 1;
        }
    }
    return true;
}

void prw_lod_free(prw_lod_model *lm)
{
    for (int pi = 0; pi < lm->npatches; pi++) {
        prw_lod_patch *p = &lm->patches[pi];
        free(p->uv);
        free(p->pos);
        free(p->gid);
        free(p->removed_at);
        free(p->ring_start);
        free(p->ring_of);
        free(p->ring_seg);
        free(p->ring_sidx);
        free(p->ring_rev);
        free(p->tri_start);
        free(p->tris);
        free(p->err);
    }
    free(lm->patches);
    if (lm->g)
        for (int s = 0; s < lm->g->nsegs; s++) {
            free(lm->ladder[s]);
            free(lm->seg_keep[s]);
        }
    free(lm->ladder);
    free(lm->seg_keep);
    memset(lm, 0, sizeof *lm);
}
