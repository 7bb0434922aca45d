/* Whole-model proxy levels: welded start mesh, greedy half-edge collapses in stages, measured
 * two-sided bounds against the start mesh (see prw_lod_proxy.h). */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "prw_lod_internal.h"
#include "prw_lod_proxy.h"

/* ---------- geometry ---------- */

static prw_dvec3 P3(const double *p) { return prw_v3(p[0], p[1], p[2]); }

static double seg_dist2(prw_dvec3 p, prw_dvec3 a, prw_dvec3 b)
{
    prw_dvec3 ab = prw_v3_sub(b, a), ap = prw_v3_sub(p, a);
    double l = prw_v3_dot(ab, ab), t = l > 0 ? prw_v3_dot(ap, ab) / l : 0;
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    prw_dvec3 d = prw_v3_sub(ap, prw_v3_scale(ab, t));
    return prw_v3_dot(d, d);
}

/* Exact distance from p to triangle abc: the plane distance when p projects inside (all three edge
 * tests on the same side as the normal), else the nearest of the three edges. */
static double tri_dist(prw_dvec3 p, prw_dvec3 a, prw_dvec3 b, prw_dvec3 c)
{
    prw_dvec3 n = prw_v3_cross(prw_v3_sub(b, a), prw_v3_sub(c, a));
    double nn = prw_v3_dot(n, n);
    if (nn > 0) {
        double s0 = prw_v3_dot(prw_v3_cross(prw_v3_sub(b, a), prw_v3_sub(p, a)), n);
        double s1 = prw_v3_dot(prw_v3_cross(prw_v3_sub(c, b), prw_v3_sub(p, b)), n);
        double s2 = prw_v3_dot(prw_v3_cross(prw_v3_sub(a, c), prw_v3_sub(p, c)), n);
        if (s0 >= 0 && s1 >= 0 && s2 >= 0) return fabs(prw_v3_dot(prw_v3_sub(p, a), n)) / sqrt(nn);
    }
    double d = fmin(seg_dist2(p, a, b), fmin(seg_dist2(p, b, c), seg_dist2(p, c, a)));
    return sqrt(d);
}

/* ---------- BVH over a triangle set (nearest-triangle queries) ---------- */

typedef struct bnode {
    prw_dvec3 lo, hi;
    int left, right; /* children, or -1 for a leaf */
    int first, count;
} bnode;

typedef struct bvh {
    const double *pos;
    const uint32_t *tris;
    int *order;
    bnode *nodes;
    int nnodes;
    double *cen;
} bvh;

static prw_dvec3 tv(const bvh *b, int t, int k) { return P3(b->pos + 3 * b->tris[3 * t + k]); }

/* Depth <= BVH_FREE_DEPTH + 31: below BVH_FREE_DEPTH the split is the plain half of the range, so
 * every deeper level halves the count (< 2^31 triangles).  bvh_nearest's stack holds at most one
 * pending sibling per level plus the root, so BVH_STACK covers every tree this builds. */
#define BVH_FREE_DEPTH 40
#define BVH_STACK (BVH_FREE_DEPTH + 31 + 2)

static int bvh_node(bvh *b, int first, int count, int depth)
{
    int id = b->nnodes++;
    bnode *n = &b->nodes[id];
    n->lo = prw_v3(INFINITY, INFINITY, INFINITY);
    n->hi = prw_v3(-INFINITY, -INFINITY, -INFINITY);
    prw_dvec3 clo = n->lo, chi = n->hi;
    for (int i = first; i < first + count; i++) {
        int t = b->order[i];
        for (int k = 0; k < 3; k++) {
            prw_dvec3 x = tv(b, t, k);
            n->lo = prw_v3_min(n->lo, x);
            n->hi = prw_v3_max(n->hi, x);
        }
        prw_dvec3 c = P3(b->cen + 3 * t);
        clo = prw_v3_min(clo, c);
        chi = prw_v3_max(chi, c);
    }
    n->first = first, n->count = count, n->left = n->right = -1;
    if (count <= 4) return id;
    prw_dvec3 ext = prw_v3_sub(chi, clo);
    int ax = ext.x >= ext.y && ext.x >= ext.z ? 0 : ext.y >= ext.z ? 1 : 2;
    double mid = 0.5 * ((&clo.x)[ax] + (&chi.x)[ax]);
    int i = first, j = first + count - 1;
    while (i <= j) {
        if (b->cen[3 * b->order[i] + ax] < mid)
            i++;
        else {
            int t = b->order[i];
            b->order[i] = b->order[j], b->order[j--] = t;
        }
    }
    int nl = i - first;
    if (nl == 0 || nl == count || depth >= BVH_FREE_DEPTH) nl = count / 2; /* equal centroids / depth bound */
    int l = bvh_node(b, first, nl, depth + 1), r = bvh_node(b, first + nl, count - nl, depth + 1);
    b->nodes[id].left = l, b->nodes[id].right = r;
    return id;
}

static void bvh_build(bvh *b, const double *pos, const uint32_t *tris, int ntris)
{
    memset(b, 0, sizeof *b);
    b->pos = pos, b->tris = tris;
    b->order = prw_malloc(sizeof(int) * ((size_t)ntris + 1));
    b->nodes = prw_malloc(sizeof(bnode) * (2 * (size_t)ntris + 1));
    b->cen = prw_malloc(sizeof(double) * 3 * ((size_t)ntris + 1));
    for (int t = 0; t < ntris; t++) {
        b->order[t] = t;
        prw_dvec3 c = prw_v3_scale(prw_v3_add(prw_v3_add(tv(b, t, 0), tv(b, t, 1)), tv(b, t, 2)), 1.0 / 3);
        b->cen[3 * t] = c.x, b->cen[3 * t + 1] = c.y, b->cen[3 * t + 2] = c.z;
    }
    if (ntris > 0) bvh_node(b, 0, ntris, 0);
}

static void bvh_free(bvh *b)
{
    free(b->order);
    free(b->nodes);
    free(b->cen);
    memset(b, 0, sizeof *b);
}

static double box_dist2(const bnode *n, prw_dvec3 p)
{
    double d = 0;
    for (int a = 0; a < 3; a++) {
        double x = (&p.x)[a], lo = (&n->lo.x)[a], hi = (&n->hi.x)[a];
        double e = x < lo ? lo - x : x > hi ? x - hi : 0;
        d += e * e;
    }
    return d;
}

/* Nearest triangle to p (*tri; -1 for an empty tree).  hint >= 0: a triangle tried first (its
 * distance seeds the pruning; the result is the same). */
static double bvh_nearest(const bvh *b, prw_dvec3 p, int hint, int *tri)
{
    double best = INFINITY;
    *tri = -1;
    if (!b->nnodes) return best;
    if (hint >= 0) best = tri_dist(p, tv(b, hint, 0), tv(b, hint, 1), tv(b, hint, 2)), *tri = hint;
    int stack[BVH_STACK], sp = 0;
    stack[sp++] = 0;
    while (sp) {
        const bnode *n = &b->nodes[stack[--sp]];
        if (box_dist2(n, p) >= best * best) continue;
        if (n->left < 0) {
            for (int i = n->first; i < n->first + n->count; i++) {
                int t = b->order[i];
                if (t == hint) continue;
                double d = tri_dist(p, tv(b, t, 0), tv(b, t, 1), tv(b, t, 2));
                if (d < best) best = d, *tri = t;
            }
            continue;
        }
        double dl = box_dist2(&b->nodes[n->left], p), dr = box_dist2(&b->nodes[n->right], p);
        if (sp + 2 > BVH_STACK) continue; /* cannot happen: see BVH_STACK */
        if (dl < dr)
            stack[sp++] = n->right, stack[sp++] = n->left;
        else
            stack[sp++] = n->left, stack[sp++] = n->right;
    }
    return best;
}

/* ---------- measured one-sided bound (convexity of the distance to one triangle) ---------- */

typedef struct meas {
    const bvh *dst;
    double queries, max_queries;
    double run; /* running max of the accepted upper bounds (and of the vertices' distances) */
} meas;

static double max_corner_dist(const bvh *b, int t, prw_dvec3 a, prw_dvec3 c1, prw_dvec3 c2)
{
    prw_dvec3 p = tv(b, t, 0), q = tv(b, t, 1), r = tv(b, t, 2);
    return fmax(tri_dist(a, p, q, r), fmax(tri_dist(c1, p, q, r), tri_dist(c2, p, q, r)));
}

/* For any one triangle T of dst, max over the (sub)triangle abc of dist(., dst) <= max of its three
 * corners' distances to T (the distance to a convex set is convex).  T: the better of the parent's
 * candidate and the triangle nearest to abc's centroid; when that bound is above the running max and
 * clearly above the centroid's own distance, abc is split in 4. */
static void tri_bound(meas *m, prw_dvec3 a, prw_dvec3 b, prw_dvec3 c, int cand, int depth)
{
    if (m->queries > m->max_queries) return;
    prw_dvec3 x = prw_v3_scale(prw_v3_add(prw_v3_add(a, b), c), 1.0 / 3);
    int tc;
    double dc = bvh_nearest(m->dst, x, cand, &tc);
    m->queries++;
    if (tc < 0) {
        m->run = INFINITY;
        return;
    }
    double ub = max_corner_dist(m->dst, tc, a, b, c);
    if (cand >= 0 && cand != tc) {
        double u2 = max_corner_dist(m->dst, cand, a, b, c);
        if (u2 < ub) ub = u2, tc = cand;
    }
    if (ub <= m->run) return;
    if (depth == 0 || ub - dc <= 0.05 * ub) {
        m->run = ub;
        return;
    }
    prw_dvec3 ab = prw_v3_scale(prw_v3_add(a, b), 0.5), bc = prw_v3_scale(prw_v3_add(b, c), 0.5),
              ca = prw_v3_scale(prw_v3_add(c, a), 0.5);
    tri_bound(m, a, ab, ca, tc, depth - 1);
    tri_bound(m, ab, b, bc, tc, depth - 1);
    tri_bound(m, ca, bc, c, tc, depth - 1);
    tri_bound(m, ab, bc, ca, tc, depth - 1);
}

/* max(floor, an upper bound of the max over the triangles of src of the distance to dst's triangle
 * set); -1 when the query budget runs out.  Parts whose bound is <= floor are not refined. */
static double one_sided(const double *pos, int nverts, const uint32_t *tris, int ntris, const bvh *dst, double floor,
                        double *queries, double max_queries)
{
    meas m = {dst, *queries, max_queries, floor};
    /* the vertices' own distances first: their max is a lower bound of the result, so no part
     * needs refining below it (the result is max(that, the parts' upper bounds): still a bound) */
    unsigned char *done = prw_calloc((size_t)nverts + 1, 1);
    for (int i = 0; i < 3 * ntris; i++) {
        uint32_t v = tris[i];
        if (done[v]) continue;
        done[v] = 1;
        int t;
        m.run = fmax(m.run, bvh_nearest(dst, P3(pos + 3 * v), -1, &t));
        m.queries++;
    }
    free(done);
    for (int t = 0; t < ntris && m.queries <= max_queries; t++)
        tri_bound(&m, P3(pos + 3 * tris[3 * t]), P3(pos + 3 * tris[3 * t + 1]), P3(pos + 3 * tris[3 * t + 2]), -1, 8);
    *queries = m.queries;
    return m.queries > max_queries ? -1 : m.run;
}

/* ---------- collapse work state ---------- */

typedef struct occ {
    int patch, next;
    double u, v;
} occ;

typedef struct work {
    int nv, nt;
    double *pos;
    occ *occs;
    int nocc, occcap;
    int *first_occ;
    uint32_t *tri;
    int *tpatch, *cpatch;
    double *cuv;
    unsigned char *talive, *valive, *fixed;
    lod_ivec *vt;
    double *verr;
    unsigned *stamp;
    lod_heap h;
    double area2_min; /* |cross| threshold: 2 x 1e-12 x diag^2 */
    lod_ivec nb, nbw;
    int alive_tris;
} work;

static prw_dvec3 wp(const work *w, int v) { return P3(w->pos + 3 * v); }

static bool tri_has(const work *w, int t, int x)
{
    const uint32_t *r = w->tri + 3 * t;
    return (int)r[0] == x || (int)r[1] == x || (int)r[2] == x;
}

/* Neighbours of v (each once) into nb; edge degrees into deg (parallel). */
static void neighbours(const work *w, int v, lod_ivec *nb, int *deg, int maxn)
{
    nb->n = 0;
    for (int i = 0; i < w->vt[v].n; i++) {
        const uint32_t *r = w->tri + 3 * w->vt[v].v[i];
        for (int k = 0; k < 3; k++) {
            int x = (int)r[k];
            if (x == v) continue;
            int j = 0;
            while (j < nb->n && nb->v[j] != x) j++;
            if (j == nb->n) {
                if (nb->n >= maxn) {
                    nb->n = -1;
                    return;
                }
                lod_ipush(nb, x);
                deg[j] = 0;
            }
            deg[j]++;
        }
    }
}

#define MAXVAL 64

/* Is v's star one fan (disc or half-disc) with no non-manifold edge?  *border: a half-disc. */
static bool manifold_star(work *w, int v, int *deg, bool *border)
{
    neighbours(w, v, &w->nb, deg, MAXVAL);
    const lod_ivec nb = w->nb;
    if (nb.n < 0) return false;
    int ones = 0;
    for (int j = 0; j < nb.n; j++) {
        if (deg[j] > 2) return false;
        ones += deg[j] == 1;
    }
    if (ones != 0 && ones != 2) return false;
    *border = ones == 2;
    /* connected: walk the triangles across shared edges */
    int n = w->vt[v].n;
    if (n > MAXVAL) return false;
    unsigned char seen[MAXVAL] = {0};
    int stack[MAXVAL], sp = 0, cnt = 1;
    seen[0] = 1, stack[sp++] = 0;
    while (sp) {
        int a = w->vt[v].v[stack[--sp]];
        for (int i = 0; i < n; i++) {
            if (seen[i]) continue;
            int b = w->vt[v].v[i], shared = 0;
            for (int k = 0; k < 3; k++) {
                int x = (int)w->tri[3 * a + k];
                if (x != v && tri_has(w, b, x)) shared++;
            }
            if (shared) seen[i] = 1, stack[sp++] = i, cnt++;
        }
    }
    return cnt == n;
}

/* Cost of v -> to, or INFINITY when the collapse is not allowed. */
static double collapse_cost(work *w, int v, int to)
{
    int deg[MAXVAL + 1], degw[4 * MAXVAL + 1]; /* degw: neighbours(.., 4 * MAXVAL) writes up to that many */
    bool border;
    if (w->fixed[v] || !manifold_star(w, v, deg, &border)) return INFINITY;
    const lod_ivec nb = w->nb; /* v's neighbours, from manifold_star */
    int ti = -1;
    for (int j = 0; j < nb.n; j++)
        if (nb.v[j] == to) ti = j;
    if (ti < 0) return INFINITY;
    int edge_deg = deg[ti];
    if (border && edge_deg != 1) return INFINITY;             /* a border vertex moves only along the border */
    if (w->vt[v].n == 1 && w->vt[to].n == 1) return INFINITY; /* an isolated triangle stays */
    neighbours(w, to, &w->nbw, degw, 4 * MAXVAL);
    const lod_ivec nbw = w->nbw;
    if (nbw.n < 0) return INFINITY;
    int common = 0;
    for (int j = 0; j < nb.n; j++) {
        if (nb.v[j] == to) continue;
        for (int i = 0; i < nbw.n; i++)
            if (nbw.v[i] == nb.v[j]) common++;
    }
    if (common != edge_deg) return INFINITY; /* link condition */
    prw_dvec3 pv = wp(w, v), pt = wp(w, to);
    double eps = 0;
    for (int i = 0; i < w->vt[v].n; i++) {
        int t = w->vt[v].v[i];
        if (tri_has(w, t, to)) continue;
        prw_dvec3 q[3], o[3];
        int other[2], no = 0;
        for (int k = 0; k < 3; k++) {
            int x = (int)w->tri[3 * t + k];
            o[k] = wp(w, x);
            q[k] = x == v ? pt : o[k];
            if (x != v) other[no++] = x;
        }
        /* the new triangle must not exist already */
        for (int j = 0; j < w->vt[to].n; j++) {
            int s = w->vt[to].v[j];
            if (tri_has(w, s, other[0]) && tri_has(w, s, other[1])) return INFINITY;
        }
        prw_dvec3 n0 = prw_v3_cross(prw_v3_sub(o[1], o[0]), prw_v3_sub(o[2], o[0]));
        prw_dvec3 n1 = prw_v3_cross(prw_v3_sub(q[1], q[0]), prw_v3_sub(q[2], q[0]));
        double l1 = prw_v3_len(n1);
        if (!(l1 > w->area2_min) || !(prw_v3_dot(n0, n1) > 0)) return INFINITY;
        eps = fmax(eps, fabs(prw_v3_dot(prw_v3_sub(pv, q[0]), n1)) / l1);
    }
    if (border)
        for (int j = 0; j < nb.n; j++)
            if (deg[j] == 1 && nb.v[j] != to) eps = fmax(eps, sqrt(seg_dist2(pv, pt, wp(w, nb.v[j]))));
    double c = fmax(w->verr[v], eps); /* max, not the thesis's sum: 10-25 % fewer triangles at equal measured error */
    return isfinite(c) ? c : INFINITY;
}

static void push_best(work *w, int v)
{
    w->stamp[v]++;
    if (!w->valive[v] || w->fixed[v]) return;
    int deg[MAXVAL + 1];
    neighbours(w, v, &w->nb, deg, MAXVAL);
    if (w->nb.n <= 0) return;
    int cand[MAXVAL], nc = w->nb.n;
    memcpy(cand, w->nb.v, sizeof(int) * (size_t)nc);
    double best = INFINITY;
    int bt = -1;
    for (int j = 0; j < nc; j++) {
        double c = collapse_cost(w, v, cand[j]);
        if (c < best) best = c, bt = cand[j];
    }
    if (bt >= 0) lod_heap_push(&w->h, (lod_hent){best, v, bt, w->stamp[v], 0});
}

/* Corner data of vertex x for a triangle of patch p. */
static void corner_of(const work *w, int x, int p, int *cp, double *uv)
{
    int o = w->first_occ[x], pick = o;
    for (; o >= 0; o = w->occs[o].next)
        if (w->occs[o].patch == p) {
            pick = o;
            break;
        }
    *cp = w->occs[pick].patch;
    uv[0] = w->occs[pick].u, uv[1] = w->occs[pick].v;
}

static void do_collapse(work *w, int v, int to, double cost)
{
    lod_ivec *lv = &w->vt[v];
    for (int i = 0; i < lv->n; i++) {
        int t = lv->v[i];
        if (tri_has(w, t, to)) {
            w->talive[t] = 0;
            w->alive_tris--;
            for (int k = 0; k < 3; k++) {
                int x = (int)w->tri[3 * t + k];
                if (x != v) lod_iremove(&w->vt[x], t);
            }
            continue;
        }
        for (int k = 0; k < 3; k++)
            if ((int)w->tri[3 * t + k] == v) {
                w->tri[3 * t + k] = (uint32_t)to;
                corner_of(w, to, w->tpatch[t], &w->cpatch[3 * t + k], &w->cuv[6 * t + 2 * k]);
            }
        lod_ipush(&w->vt[to], t);
    }
    lv->n = 0;
    w->valive[v] = 0;
    w->verr[to] = fmax(w->verr[to], cost);
    /* new costs around `to` (others are re-checked when popped) */
    int deg[4 * MAXVAL + 1];
    lod_ivec nb = {0};
    neighbours(w, to, &nb, deg, 4 * MAXVAL);
    push_best(w, to);
    for (int j = 0; j < nb.n; j++) push_best(w, nb.v[j]);
    free(nb.v);
}

/* ---------- start mesh ---------- */

static uint64_t pos_hash(const double *p)
{
    uint64_t h = 1469598103934665603ull, x;
    for (int k = 0; k < 3; k++) {
        memcpy(&x, p + k, 8);
        h = (h ^ x) * 1099511628211ull;
        h ^= h >> 29;
    }
    return h;
}

static void snapshot(const work *w, prw_lod_proxy_level *L, int *remap)
{
    memset(L, 0, sizeof *L);
    int nv = 0, nt = 0;
    for (int v = 0; v < w->nv; v++) remap[v] = -1;
    for (int t = 0; t < w->nt; t++) {
        if (!w->talive[t]) continue;
        nt++;
        for (int k = 0; k < 3; k++)
            if (remap[w->tri[3 * t + k]] < 0) remap[w->tri[3 * t + k]] = nv++;
    }
    L->nverts = nv, L->ntris = nt;
    L->pos = prw_malloc(sizeof(double) * 3 * ((size_t)nv + 1));
    L->tris = prw_malloc(sizeof(uint32_t) * 3 * ((size_t)nt + 1));
    L->corner_patch = prw_malloc(sizeof(int) * 3 * ((size_t)nt + 1));
    L->corner_uv = prw_malloc(sizeof(double) * 6 * ((size_t)nt + 1));
    L->tri_patch = prw_malloc(sizeof(int) * ((size_t)nt + 1));
    for (int v = 0; v < w->nv; v++)
        if (remap[v] >= 0) memcpy(L->pos + 3 * remap[v], w->pos + 3 * v, sizeof(double) * 3);
    int j = 0;
    for (int t = 0; t < w->nt; t++) {
        if (!w->talive[t]) continue;
        for (int k = 0; k < 3; k++) L->tris[3 * j + k] = (uint32_t)remap[w->tri[3 * t + k]];
        memcpy(L->corner_patch + 3 * j, w->cpatch + 3 * t, sizeof(int) * 3);
        memcpy(L->corner_uv + 6 * j, w->cuv + 6 * t, sizeof(double) * 6);
        L->tri_patch[j] = w->tpatch[t];
        j++;
    }
}

static void level_free(prw_lod_proxy_level *L)
{
    free(L->pos);
    free(L->tris);
    free(L->corner_patch);
    free(L->corner_uv);
    free(L->tri_patch);
    memset(L, 0, sizeof *L);
}

bool prw_lod_proxy_build(const prw_lod_model *lm, const unsigned char *flip, const prw_lod_proxy_options *o,
                         prw_lod_proxy *out, prw_error *e)
{
    memset(out, 0, sizeof *out);
    double t0 = prw_now();
    int maxst = o && o->max_start_triangles > 0 ? o->max_start_triangles : 16384;
    double maxs = o && o->max_samples > 0 ? o->max_samples : 2e6;
    int np = lm->npatches, okp = 0;
    for (int p = 0; p < np; p++) okp += lm->patches[p].ok;
    if (!okp || lm->levels < 1) return prw_fail(e, "lod proxy: the model has no usable patch");
    const prw_seam_graph *g = lm->g;
    int *plev = prw_malloc(sizeof(int) * ((size_t)np + 1)), *slev = prw_malloc(sizeof(int) * ((size_t)g->nsegs + 1));
    prw_lod_mesh m;
    memset(&m, 0, sizeof m);
    /* k_s: the finest level whose emission has <= maxst triangles (else the coarsest) */
    int ks = lm->levels - 1;
    for (int k = 0; k < lm->levels; k++) {
        for (int p = 0; p < np; p++) plev[p] = k;
        prw_lod_segment_levels(lm, plev, slev);
        prw_lod_mesh_reset(&m);
        for (int p = 0; p < np; p++) prw_lod_emit(lm, p, k, slev, &m);
        if (m.ntris <= (size_t)maxst) {
            ks = k;
            break;
        }
    }
    /* the patches' own floor: every patch at its coarsest level */
    for (int p = 0; p < np; p++) plev[p] = lm->levels - 1;
    prw_lod_segment_levels(lm, plev, slev);
    prw_lod_mesh_reset(&m);
    for (int p = 0; p < np; p++) prw_lod_emit(lm, p, lm->levels - 1, slev, &m);
    double max_level_tris = o && o->max_level_triangles > 0 ? o->max_level_triangles : 2.0 * (double)m.ntris;
    out->patch_floor_triangles = (int)m.ntris;
    for (int p = 0; p < np; p++) plev[p] = ks;
    prw_lod_segment_levels(lm, plev, slev);
    /* emit patch by patch, weld by bit-identical position */
    work w;
    memset(&w, 0, sizeof w);
    double diag = g->diag > 0 ? g->diag : 1;
    w.area2_min = 2e-12 * diag * diag;
    size_t vcap = 0, tcap = 0;
    int hsize = 1 << 10;
    int *htab = NULL;
    double eps_s = 0;
    bool ok = true;
    for (int p = 0; p < np && ok; p++) {
        const prw_lod_patch *lp = &lm->patches[p];
        if (!lp->ok) continue;
        eps_s = fmax(eps_s, lp->err[ks]);
        prw_lod_mesh_reset(&m);
        prw_lod_emit(lm, p, ks, slev, &m);
        size_t nv = m.nverts, nt = m.ntris;
        if (nv > (size_t)INT32_MAX / 8 || (size_t)w.nv + nv > (size_t)INT32_MAX / 8 ||
            (size_t)w.nt + nt > (size_t)INT32_MAX / 8) {
            ok = prw_fail(e, "lod proxy: start mesh too large (patch %d)", p);
            break;
        }
        double *uvw = prw_calloc(3 * nv + 3, sizeof(double));
        for (int v = 0; v < lp->nverts; v++) {
            int k = m.map[v];
            if (k < 0 || (size_t)k >= nv) continue;
            uvw[3 * k] = lp->uv[2 * v], uvw[3 * k + 1] = lp->uv[2 * v + 1], uvw[3 * k + 2] = -1;
        }
        for (size_t t = 0; t < nt; t++) {
            uint32_t c = m.tris[3 * t];
            if (uvw[3 * c + 2] < 0) continue;
            for (int k = 1; k < 3; k++) {
                uint32_t a = m.tris[3 * t + k];
                if (uvw[3 * a + 2] >= 0) continue;
                uvw[3 * c] += uvw[3 * a], uvw[3 * c + 1] += uvw[3 * a + 1], uvw[3 * c + 2] += 1;
            }
        }
        for (size_t i = 0; i < nv; i++)
            if (uvw[3 * i + 2] > 0) uvw[3 * i] /= uvw[3 * i + 2], uvw[3 * i + 1] /= uvw[3 * i + 2];
        /* weld */
        int *wid = prw_malloc(sizeof(int) * (nv + 1));
        if ((size_t)(w.nv + (int)nv) * 2 > (size_t)hsize || !htab) {
            while ((size_t)(w.nv + (int)nv) * 2 > (size_t)hsize) hsize *= 2;
            free(htab);
            htab = prw_malloc(sizeof(int) * (size_t)hsize);
            for (int i = 0; i < hsize; i++) htab[i] = -1;
            for (int v = 0; v < w.nv; v++) {
                size_t s = pos_hash(w.pos + 3 * v) & (size_t)(hsize - 1);
                while (htab[s] >= 0) s = (s + 1) & (size_t)(hsize - 1);
                htab[s] = v;
            }
        }
        for (size_t i = 0; i < nv; i++) {
            const double *x = m.pos + 3 * i;
            size_t s = pos_hash(x) & (size_t)(hsize - 1);
            while (htab[s] >= 0 && memcmp(w.pos + 3 * htab[s], x, sizeof(double) * 3))
                s = (s + 1) & (size_t)(hsize - 1);
            int v = htab[s];
            if (v < 0) {
                if ((size_t)w.nv == vcap) {
                    vcap = vcap ? 2 * vcap : 4096;
                    w.pos = prw_realloc(w.pos, sizeof(double) * 3 * vcap);
                    w.first_occ = prw_realloc(w.first_occ, sizeof(int) * vcap);
                }
                v = htab[s] = w.nv++;
                memcpy(w.pos + 3 * v, x, sizeof(double) * 3);
                w.first_occ[v] = -1;
            }
            wid[i] = v;
            /* occurrence (patch, u, v), appended at the end of v's list */
            bool have = false;
            int last = -1;
            for (int q = w.first_occ[v]; q >= 0; q = w.occs[q].next) {
                have = have || w.occs[q].patch == p;
                last = q;
            }
            if (have) continue;
            if (w.nocc == w.occcap) {
                w.occcap = w.occcap ? 2 * w.occcap : 4096;
                w.occs = prw_realloc(w.occs, sizeof(occ) * (size_t)w.occcap);
            }
            w.occs[w.nocc] = (occ){p, -1, uvw[3 * i], uvw[3 * i + 1]};
            if (last < 0)
                w.first_occ[v] = w.nocc;
            else
                w.occs[last].next = w.nocc;
            w.nocc++;
        }
        for (size_t t = 0; t < nt; t++) {
            int a = wid[m.tris[3 * t]], b = wid[m.tris[3 * t + 1]], c = wid[m.tris[3 * t + 2]];
            uint32_t la = m.tris[3 * t], lb = m.tris[3 * t + 1], lc = m.tris[3 * t + 2];
            if (a == b || b == c || c == a) continue;
            if (flip && flip[p]) {
                int s = b;
                b = c, c = s;
                uint32_t ls = lb;
                lb = lc, lc = ls;
            }
            if ((size_t)w.nt == tcap) {
                tcap = tcap ? 2 * tcap : 4096;
                w.tri = prw_realloc(w.tri, sizeof(uint32_t) * 3 * tcap);
                w.tpatch = prw_realloc(w.tpatch, sizeof(int) * tcap);
                w.cpatch = prw_realloc(w.cpatch, sizeof(int) * 3 * tcap);
                w.cuv = prw_realloc(w.cuv, sizeof(double) * 6 * tcap);
            }
            int j = w.nt++;
            w.tri[3 * j] = (uint32_t)a, w.tri[3 * j + 1] = (uint32_t)b, w.tri[3 * j + 2] = (uint32_t)c;
            w.tpatch[j] = p;
            uint32_t loc[3] = {la, lb, lc};
            for (int k = 0; k < 3; k++) {
                w.cpatch[3 * j + k] = p;
                w.cuv[6 * j + 2 * k] = uvw[3 * loc[k]];
                w.cuv[6 * j + 2 * k + 1] = uvw[3 * loc[k] + 1];
            }
        }
        free(wid);
        free(uvw);
    }
    free(htab);
    prw_lod_mesh_free(&m);
    free(plev);
    free(slev);
    if (!ok || w.nt == 0) goto done; /* no triangles at all: nlevels = 0 */
    out->start_level = ks;
    out->eps_start = eps_s;
    out->start_triangles = w.nt;
    /* adjacency */
    w.vt = prw_calloc((size_t)w.nv + 1, sizeof(lod_ivec));
    w.talive = prw_malloc((size_t)w.nt + 1);
    memset(w.talive, 1, (size_t)w.nt + 1);
    w.valive = prw_calloc((size_t)w.nv + 1, 1);
    w.fixed = prw_calloc((size_t)w.nv + 1, 1);
    w.verr = prw_calloc((size_t)w.nv + 1, sizeof(double));
    w.stamp = prw_calloc((size_t)w.nv + 1, sizeof(unsigned));
    for (int t = 0; t < w.nt; t++)
        for (int k = 0; k < 3; k++) {
            lod_ipush(&w.vt[w.tri[3 * t + k]], t);
            w.valive[w.tri[3 * t + k]] = 1;
        }
    w.alive_tris = w.nt;
    {
        int deg[4 * MAXVAL + 1];
        lod_ivec nb = {0};
        for (int v = 0; v < w.nv; v++) {
            neighbours(&w, v, &nb, deg, 4 * MAXVAL);
            if (nb.n < 0) {
                w.fixed[v] = 1;
                continue;
            }
            for (int j = 0; j < nb.n; j++) {
                if (deg[j] > 2) w.fixed[v] = 1; /* non-manifold edge: both ends fixed */
                if (deg[j] == 1 && nb.v[j] > v) out->border_edges++;
            }
        }
        free(nb.v);
    }
    /* measurement set-up: M_s and its BVH stay as built */
    double *spos = prw_malloc(sizeof(double) * 3 * ((size_t)w.nv + 1));
    uint32_t *stri = prw_malloc(sizeof(uint32_t) * 3 * ((size_t)w.nt + 1));
    memcpy(spos, w.pos, sizeof(double) * 3 * (size_t)w.nv);
    memcpy(stri, w.tri, sizeof(uint32_t) * 3 * (size_t)w.nt);
    int snt = w.nt;
    bvh bs;
    bvh_build(&bs, spos, stri, snt);
    int *remap = prw_malloc(sizeof(int) * ((size_t)w.nv + 1));
    int last_kept = snt, cap_levels = 0;
    for (int k = PRW_PROXY_STEPS * (ks + 1); k < PRW_PROXY_STEPS * lm->levels; k++) {
        double tau = lm->tau0 * exp2((double)k / PRW_PROXY_STEPS), budget = tau - eps_s;
        if (!(budget > 0)) continue;
        /* while the mesh is still too fine to be kept, whole octaves only (fewer heap rebuilds) */
        if (w.alive_tris > max_level_tris && k % PRW_PROXY_STEPS != PRW_PROXY_STEPS - 1) continue;
        int before = w.alive_tris;
        w.h.n = 0;
        for (int v = 0; v < w.nv; v++) push_best(&w, v);
        while (w.h.n > 0) {
            if (w.h.a[0].cost > budget) break;
            lod_hent x = lod_heap_pop(&w.h);
            if (x.sv != w.stamp[x.v] || !w.valive[x.v]) continue;
            double c = collapse_cost(&w, x.v, x.w);
            if (c > x.cost) { /* stale: look again */
                push_best(&w, x.v);
                continue;
            }
            do_collapse(&w, x.v, x.w, c);
        }
        if (w.alive_tris >= before || w.alive_tris >= last_kept || w.alive_tris > max_level_tris) continue;
        if (out->nlevels == cap_levels) {
            cap_levels = cap_levels ? 2 * cap_levels : 8;
            out->levels = prw_realloc(out->levels, sizeof(prw_lod_proxy_level) * (size_t)cap_levels);
        }
        snapshot(&w, &out->levels[out->nlevels], remap);
        out->levels[out->nlevels++].stage = k;
        last_kept = w.alive_tris;
    }
    /* measure coarse to fine: a finer level needs more queries, so once one runs out of budget (or
     * is predicted to: the previous level's queries scaled by the triangle count) the finer ones
     * are skipped unmeasured */
    int first_ok = out->nlevels;
    double q_prev = 0;
    for (int l = out->nlevels - 1; l >= 0; l--) {
        prw_lod_proxy_level *L = &out->levels[l];
        if (L->ntris > max_level_tris) break; /* the patches do as well there: not worth measuring */
        if (l + 1 < out->nlevels && q_prev * L->ntris / out->levels[l + 1].ntris > maxs) break;
        bvh bp;
        bvh_build(&bp, L->pos, L->tris, L->ntris);
        double q = 0;
        double d1 = one_sided(spos, w.nv, stri, snt, &bp, 0, &q, maxs);
        double d2 = d1 >= 0 ? one_sided(L->pos, L->nverts, L->tris, L->ntris, &bs, d1, &q, maxs) : -1;
        bvh_free(&bp);
        if (d1 < 0 || d2 < 0 || !isfinite(d1) || !isfinite(d2)) break;
        L->d_start = fmax(d1, d2) + 1e-12 * diag; /* rounding of the distance evaluations */
        L->err = eps_s + L->d_start;
        first_ok = l;
        q_prev = q;
    }
    for (int l = 0; l < first_ok; l++) level_free(&out->levels[l]);
    if (first_ok > 0) {
        memmove(out->levels, out->levels + first_ok, sizeof(prw_lod_proxy_level) * (size_t)(out->nlevels - first_ok));
        out->nlevels -= first_ok;
    }
    /* keep the Pareto front: a level is useless when a coarser one (fewer triangles) has no larger
     * bound (the measured bounds of neighbouring stages can tie or cross) */
    {
        int n = 0;
        double best = INFINITY;
        unsigned char *keep = prw_calloc((size_t)out->nlevels + 1, 1);
        for (int l = out->nlevels - 1; l >= 0; l--)
            if (out->levels[l].err < best) keep[l] = 1, best = out->levels[l].err;
        for (int l = 0; l < out->nlevels; l++) {
            if (keep[l]) out->levels[n++] = out->levels[l];
            else level_free(&out->levels[l]);
        }
        out->nlevels = n;
        free(keep);
    }
    bvh_free(&bs);
    free(remap);
    free(spos);
    free(stri);
    for (int v = 0; v < w.nv; v++) free(w.vt[v].v);
done:
    free(w.pos);
    free(w.occs);
    free(w.first_occ);
    free(w.tri);
    free(w.tpatch);
    free(w.cpatch);
    free(w.cuv);
    free(w.talive);
    free(w.valive);
    free(w.fixed);
    free(w.vt);
    free(w.verr);
    free(w.stamp);
    free(w.h.a);
    free(w.nb.v);
    free(w.nbw.v);
    if (!ok) {
        prw_lod_proxy_free(out);
        return false;
    }
    out->build_s = prw_now() - t0;
    return true;
}

void prw_lod_proxy_free(prw_lod_proxy *p)
{
    for (int i = 0; i < p->nlevels; i++) level_free(&p->levels[i]);
    free(p->levels);
    memset(p, 0, sizeof *p);
}
