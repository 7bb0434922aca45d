/* Ear clipping of polygons with holes (after D. Eberly, "Triangulation by Ear Clipping"), on a
 * circular doubly-linked node list with exact orientation tests.  The ear tests look only at the
 * ring vertices and edges a uniform grid (prw_cellgrid) finds in the cells the ear's triangle and
 * diagonal touch: the same answers as scanning the whole ring, without its quadratic cost. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_cellgrid.h"
#include "prw_earclip.h"
#include "prw_predicates.h"

/* Tests build this file a second time with PRW_EARCLIP_SCAN_ALL: one cell and no clean-ring
 * shortcut, so every ear is tested against every vertex and edge of the ring (the quadratic
 * clipper), to check that the index changes no answer. */
#ifdef PRW_EARCLIP_SCAN_ALL
enum { SCAN_ALL = 1 };
#else
enum { SCAN_ALL = 0 };
#endif

typedef struct node {
    int pt;         /* point index */
    int prev, next; /* node indices */
} node;

typedef struct elist {
    int *v; /* (from, to) node pairs: edges registered in a cell, some of them gone */
    int n, cap;
} elist;

/* The ring being clipped, indexed: each live vertex in the list of its cell.  While the ring is
 * `clean` (two edges meet only at a common end point, or are the same segment) an edge crossing an
 * ear's diagonal has an end in the ear's closed triangle, so the edges of the vertices found there
 * are the only ones to test.  Otherwise (`full`) each edge, when made, is added to every cell its
 * segment touches (removed edges are dropped lazily, when met). */
typedef struct grid {
    prw_cellgrid g;
    bool full;
    int *head;   /* per cell: first node, -1 */
    elist *edges; /* per cell */
    int *cell;   /* per node: its cell, -1 when not in the ring */
    int *cnext, *cprev;
    signed char *turn; /* per node: prw_orient2d(prev, node, next), 2 when not known */
    int *cov;
    int covcap;
} grid;

typedef struct ctx {
    const double *xy;
    node *nodes;
    int count, cap;
    int *tris;
    int ntris, tcap;
    grid gr;
} ctx;

/* fmin / fmax (a NaN operand loses) without the library call */
static inline double dmin(double a, double b) { return a < b ? a : b == b ? b : a; }
static inline double dmax(double a, double b) { return a > b ? a : b == b ? b : a; }

static const double *P(const ctx *c, int nd) { return c->xy + 2 * c->nodes[nd].pt; }

static int new_node(ctx *c, int pt)
{
    if (c->count == c->cap) {
        c->cap = c->cap ? 2 * c->cap : 64;
        c->nodes = prw_realloc(c->nodes, sizeof(node) * (size_t)c->cap);
    }
    c->nodes[c->count].pt = pt;
    c->nodes[c->count].prev = c->nodes[c->count].next = c->count;
    return c->count++;
}

static void emit(ctx *c, int a, int b, int d)
{
    if (c->ntris == c->tcap) {
        c->tcap = c->tcap ? 2 * c->tcap : 64;
        c->tris = prw_realloc(c->tris, sizeof(int) * 3 * (size_t)c->tcap);
    }
    c->tris[3 * c->ntris] = c->nodes[a].pt;
    c->tris[3 * c->ntris + 1] = c->nodes[b].pt;
    c->tris[3 * c->ntris + 2] = c->nodes[d].pt;
    c->ntris++;
}

static bool same(const double *a, const double *b) { return a[0] == b[0] && a[1] == b[1]; }

/* Loop as a ring; reversed if its orientation is not `ccw`.  Returns the first node. */
static int make_ring(ctx *c, const int *idx, int n, bool ccw, double area)
{
    bool rev = (area > 0) != ccw;
    int first = -1, last = -1;
    for (int k = 0; k < n; k++) {
        int i = rev ? idx[n - 1 - k] : idx[k];
        int nd = new_node(c, i);
        if (first < 0) first = nd;
        else {
            c->nodes[last].next = nd;
            c->nodes[nd].prev = last;
        }
        last = nd;
    }
    c->nodes[last].next = first;
    c->nodes[first].prev = last;
    return first;
}

static double loop_area(const double *xy, const int *idx, int n)
{
    double ox = xy[2 * idx[0]], oy = xy[2 * idx[0] + 1], s = 0;
    for (int i = 1; i + 1 < n; i++) {
        double ax = xy[2 * idx[i]] - ox, ay = xy[2 * idx[i] + 1] - oy;
        double bx = xy[2 * idx[i + 1]] - ox, by = xy[2 * idx[i + 1] + 1] - oy;
        s += ax * by - ay * bx;
    }
    return 0.5 * s;
}

/* -1 on the boundary, 0 outside, 1 inside (even-odd, exact). */
static int point_in_loop(const double *xy, const int *idx, int n, const double *p)
{
    int c = 0;
    for (int i = 0, j = n - 1; i < n; j = i++) {
        const double *a = xy + 2 * idx[j], *b = xy + 2 * idx[i];
        if (p[0] >= dmin(a[0], b[0]) && p[0] <= dmax(a[0], b[0]) && p[1] >= dmin(a[1], b[1]) &&
            p[1] <= dmax(a[1], b[1]) && prw_orient2d(a, b, p) == 0)
            return -1;
        bool aa = a[1] > p[1], ba = b[1] > p[1];
        if (aa == ba) continue;
        const double *lo = aa ? b : a, *hi = aa ? a : b;
        if (prw_orient2d(lo, hi, p) > 0) c ^= 1;
    }
    return c;
}

/* Does loop `in` lie inside loop `out`?  Decided at the first vertex or edge midpoint of `in`
 * that is not on `out`. */
static bool loop_inside(const double *xy, const int *in, int nin, const int *out, int nout)
{
    for (int i = 0; i < nin; i++) {
        const double *a = xy + 2 * in[i], *b = xy + 2 * in[(i + 1) % nin];
        double mid[2] = {0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])};
        int r = point_in_loop(xy, out, nout, a);
        if (r >= 0) return r == 1;
        r = point_in_loop(xy, out, nout, mid);
        if (r >= 0) return r == 1;
    }
    return false; /* identical loops: treat as not nested */
}

/* Closed (strict = false) or open (strict = true) point-in-triangle test for a CCW triangle. */
static bool in_triangle(const double *a, const double *b, const double *d, const double *p, bool strict)
{
    int o1 = prw_orient2d(a, b, p), o2 = prw_orient2d(b, d, p), o3 = prw_orient2d(d, a, p);
    if (strict) return o1 > 0 && o2 > 0 && o3 > 0;
    return o1 >= 0 && o2 >= 0 && o3 >= 0;
}

/* Does the ring's interior corner at node v (interior on the left) hold the direction to m? */
static bool corner_holds(const ctx *c, int v, const double *m)
{
    const double *p = P(c, c->nodes[v].prev), *q = P(c, v), *n = P(c, c->nodes[v].next);
    int in = prw_orient2d(p, q, m), out = prw_orient2d(q, n, m);
    if (prw_orient2d(p, q, n) > 0) return in > 0 && out > 0;
    return in > 0 || out > 0;
}

/* The ring can pass a point several times (bridges made before, loops touching there): of the
 * nodes at pn's point, the one whose corner faces m, so the new bridge does not cross a sheet. */
static int facing_node(const ctx *c, int outer, int pn, const double *m)
{
    if (corner_holds(c, pn, m)) return pn;
    int it = outer;
    do {
        if (it != pn && same(P(c, it), P(c, pn)) && corner_holds(c, it, m)) return it;
        it = c->nodes[it].next;
    } while (it != outer);
    return pn;
}

/* Joins the hole ring (starting at any node) into the outer ring. */
static void bridge(ctx *c, int outer, int hole)
{
    /* M: the hole's rightmost vertex */
    int m = hole, it = c->nodes[hole].next;
    while (it != hole) {
        const double *p = P(c, it), *q = P(c, m);
        if (p[0] > q[0] || (p[0] == q[0] && p[1] > q[1])) m = it;
        it = c->nodes[it].next;
    }
    const double *M = P(c, m);
    /* nearest upward edge crossed by the ray M + t(1, 0), t >= 0 */
    double best = INFINITY;
    int ea = -1;
    it = outer;
    do {
        int nx = c->nodes[it].next;
        const double *a = P(c, it), *b = P(c, nx);
        if (a[1] < b[1] && a[1] <= M[1] && M[1] <= b[1]) {
            double x = a[1] == M[1] ? a[0] : b[1] == M[1] ? b[0] : a[0] + (M[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
            if (x >= M[0] && x < best) {
                best = x;
                ea = it;
            }
        }
        it = nx;
    } while (it != outer);
    int pn;
    if (ea < 0) {
        pn = outer; /* no crossing (degenerate input): bridge to the outer start */
    } else {
        int eb = c->nodes[ea].next;
        const double *a = P(c, ea), *b = P(c, eb);
        double I[2] = {best, M[1]};
        if (same(a, I)) pn = ea;
        else if (same(b, I)) pn = eb;
        else {
            pn = a[0] > b[0] ? ea : eb;
            const double *Pp = P(c, pn);
            /* reflex vertices inside triangle (M, I, P) block the view: take the one with the
             * smallest angle to the ray */
            double tri[3][2] = {{M[0], M[1]}, {I[0], I[1]}, {Pp[0], Pp[1]}};
            if (prw_orient2d(tri[0], tri[1], tri[2]) < 0) {
                double t[2] = {tri[1][0], tri[1][1]};
                tri[1][0] = tri[2][0];
                tri[1][1] = tri[2][1];
                tri[2][0] = t[0];
                tri[2][1] = t[1];
            }
            double best_ang = INFINITY, best_d = INFINITY;
            it = outer;
            do {
                int pv = c->nodes[it].prev, nx = c->nodes[it].next;
                const double *r = P(c, it);
                if (it != pn && !same(r, Pp) && prw_orient2d(P(c, pv), r, P(c, nx)) < 0 &&
                    in_triangle(tri[0], tri[1], tri[2], r, false) &&
                    r[0] > M[0]) {
                    double ang = fabs(r[1] - M[1]) / (r[0] - M[0]);
                    double d = (r[0] - M[0]) * (r[0] - M[0]) + (r[1] - M[1]) * (r[1] - M[1]);
                    if (ang < best_ang || (ang == best_ang && d < best_d)) {
                        best_ang = ang;
                        best_d = d;
                        pn = it;
                    }
                }
                it = nx;
            } while (it != outer);
        }
    }
    pn = facing_node(c, outer, pn, M);
    /* splice: ... P -> M -> ... -> M.prev -> M' -> P' -> P.next ... */
    int m2 = new_node(c, c->nodes[m].pt);
    int p2 = new_node(c, c->nodes[pn].pt);
    int pnext = c->nodes[pn].next, mprev = c->nodes[m].prev;
    c->nodes[pn].next = m;
    c->nodes[m].prev = pn;
    c->nodes[mprev].next = m2;
    c->nodes[m2].prev = mprev;
    c->nodes[m2].next = p2;
    c->nodes[p2].prev = m2;
    c->nodes[p2].next = pnext;
    c->nodes[pnext].prev = p2;
}

static void add_edge(ctx *c, int from, int to)
{
    grid *g = &c->gr;
    double seg[4] = {P(c, from)[0], P(c, from)[1], P(c, to)[0], P(c, to)[1]};
    int nc = prw_cellgrid_cover(&g->g, seg, 2, &g->cov, &g->covcap);
    for (int i = 0; i < nc; i++) {
        elist *l = &g->edges[g->cov[i]];
        if (l->n + 2 > l->cap) {
            l->cap = l->cap ? 2 * l->cap : 8;
            l->v = prw_realloc(l->v, sizeof(int) * (size_t)l->cap);
        }
        l->v[l->n++] = from;
        l->v[l->n++] = to;
    }
}

static void index_edges(ctx *c, int start, int n)
{
    c->gr.full = true;
    int it = start;
    for (int k = 0; k < n; k++, it = c->nodes[it].next) add_edge(c, it, c->nodes[it].next);
}

/* Do the segments meet anywhere but at a common end point (exactly)?  The same segment twice (a
 * bridge and its way back) counts as not meeting. */
static bool bad_contact(const double *p1, const double *p2, const double *q1, const double *q2)
{
    if (dmax(p1[0], p2[0]) < dmin(q1[0], q2[0]) || dmax(q1[0], q2[0]) < dmin(p1[0], p2[0]) ||
        dmax(p1[1], p2[1]) < dmin(q1[1], q2[1]) || dmax(q1[1], q2[1]) < dmin(p1[1], p2[1]))
        return false;
    int o1 = prw_orient2d(p1, p2, q1), o2 = prw_orient2d(p1, p2, q2);
    if (o1 * o2 > 0) return false;
    int o3 = prw_orient2d(q1, q2, p1), o4 = prw_orient2d(q1, q2, p2);
    if (o3 * o4 > 0) return false;
    bool shared = same(p1, q1) || same(p1, q2) || same(p2, q1) || same(p2, q2);
    if (o1 || o2 || o3 || o4) return !shared; /* not collinear: one point, fine when shared */
    if ((same(p1, q1) && same(p2, q2)) || (same(p1, q2) && same(p2, q1))) return false; /* twins */
    /* collinear: overlap along the axis of the larger extent; one common point is a shared end */
    double ex = dmax(dmax(p1[0], p2[0]), dmax(q1[0], q2[0])) - dmin(dmin(p1[0], p2[0]), dmin(q1[0], q2[0]));
    double ey = dmax(dmax(p1[1], p2[1]), dmax(q1[1], q2[1])) - dmin(dmin(p1[1], p2[1]), dmin(q1[1], q2[1]));
    int k = ex >= ey ? 0 : 1;
    double plo = dmin(p1[k], p2[k]), phi = dmax(p1[k], p2[k]), qlo = dmin(q1[k], q2[k]), qhi = dmax(q1[k], q2[k]);
    if (phi < qlo || qhi < plo) return false;
    return !(phi == qlo || qhi == plo);
}

/* With every edge indexed: is the ring clean (no two edges of one cell in bad contact)? */
static bool ring_clean(const ctx *c)
{
    const grid *g = &c->gr;
    size_t ncells = (size_t)g->g.nx * (size_t)g->g.ny;
    for (size_t i = 0; i < ncells; i++) {
        const elist *l = &g->edges[i];
        for (int x = 0; x < l->n; x += 2)
            for (int y = x + 2; y < l->n; y += 2)
                if (bad_contact(P(c, l->v[x]), P(c, l->v[x + 1]), P(c, l->v[y]), P(c, l->v[y + 1]))) return false;
    }
    return true;
}

/* Indexes the ring of n nodes from `start` (every node of the ctx gets a cell entry); the edges
 * too unless the ring is clean. */
static void grid_build(ctx *c, int start, int n)
{
    grid *g = &c->gr;
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    int it = start;
    for (int k = 0; k < n; k++, it = c->nodes[it].next)
        for (int j = 0; j < 2; j++) lo[j] = dmin(lo[j], P(c, it)[j]), hi[j] = dmax(hi[j], P(c, it)[j]);
    prw_cellgrid_init(&g->g, lo, hi, SCAN_ALL ? 1 : n);
    size_t ncells = (size_t)g->g.nx * (size_t)g->g.ny;
    g->head = prw_malloc(sizeof(int) * ncells);
    for (size_t i = 0; i < ncells; i++) g->head[i] = -1;
    g->edges = prw_calloc(ncells, sizeof(elist));
    g->cell = prw_malloc(sizeof(int) * (size_t)c->count);
    g->cnext = prw_malloc(sizeof(int) * (size_t)c->count);
    g->cprev = prw_malloc(sizeof(int) * (size_t)c->count);
    g->turn = prw_malloc((size_t)c->count);
    for (int i = 0; i < c->count; i++) g->cell[i] = -1, g->turn[i] = 2;
    it = start;
    for (int k = 0; k < n; k++, it = c->nodes[it].next) {
        int cl = prw_cellgrid_cell(&g->g, P(c, it));
        g->cell[it] = cl;
        g->cprev[it] = -1;
        g->cnext[it] = g->head[cl];
        if (g->head[cl] >= 0) g->cprev[g->head[cl]] = it;
        g->head[cl] = it;
    }
    index_edges(c, start, n);
    if (!SCAN_ALL && ring_clean(c)) {
        g->full = false;
        size_t ncells = (size_t)g->g.nx * (size_t)g->g.ny;
        for (size_t i = 0; i < ncells; i++) g->edges[i].n = 0;
    }
}

static void grid_free(ctx *c)
{
    grid *g = &c->gr;
    size_t ncells = (size_t)g->g.nx * (size_t)g->g.ny;
    for (size_t i = 0; i < ncells; i++) free(g->edges[i].v);
    free(g->edges);
    free(g->head);
    free(g->cell);
    free(g->cnext);
    free(g->cprev);
    free(g->turn);
    free(g->cov);
    memset(g, 0, sizeof *g);
}

/* Takes the node out of the ring and the grid; its neighbours' new edge is indexed. */
static void unlink_node(ctx *c, int nd)
{
    int pv = c->nodes[nd].prev, nx = c->nodes[nd].next;
    c->nodes[pv].next = nx;
    c->nodes[nx].prev = pv;
    grid *g = &c->gr;
    int cl = g->cell[nd];
    if (g->cprev[nd] >= 0) g->cnext[g->cprev[nd]] = g->cnext[nd];
    else g->head[cl] = g->cnext[nd];
    if (g->cnext[nd] >= 0) g->cprev[g->cnext[nd]] = g->cprev[nd];
    g->cell[nd] = -1;
    g->turn[pv] = g->turn[nx] = 2;
    if (g->full) add_edge(c, pv, nx);
}

/* The turn at a ring node, remembered until a neighbour changes: the walk passes long collinear
 * runs many times, and their exact orientation tests take the slow path. */
static int turn(ctx *c, int nd)
{
    signed char *t = &c->gr.turn[nd];
    if (*t == 2) *t = (signed char)prw_orient2d(P(c, c->nodes[nd].prev), P(c, nd), P(c, c->nodes[nd].next));
    return *t;
}

/* Does the edge q-r cross the diagonal a-d (interiors, exactly)?  lo/hi: the diagonal's box. */
static bool crosses(const double *a, const double *d, const double *q, const double *r, const double *lo, const double *hi)
{
    if (dmax(q[0], r[0]) < lo[0] || dmin(q[0], r[0]) > hi[0] || dmax(q[1], r[1]) < lo[1] || dmin(q[1], r[1]) > hi[1])
        return false;
    int o1 = prw_orient2d(a, d, q), o2 = prw_orient2d(a, d, r), o3 = prw_orient2d(q, r, a), o4 = prw_orient2d(q, r, d);
    return o1 * o2 < 0 && o3 * o4 < 0;
}

/* Same answer as testing every other vertex and edge of the ring: the vertices that can reject
 * the ear lie in its closed triangle, and an edge crossing the diagonal a-d has an end there (clean
 * ring) or passes through a cell both segments touch. */
static bool is_ear(ctx *c, int pv, int cur, int nx, bool strict)
{
    grid *g = &c->gr;
    const double *a = P(c, pv), *b = P(c, cur), *d = P(c, nx);
    double lo0 = dmin(a[0], dmin(b[0], d[0])), hi0 = dmax(a[0], dmax(b[0], d[0]));
    double lo1 = dmin(a[1], dmin(b[1], d[1])), hi1 = dmax(a[1], dmax(b[1], d[1]));
    double dlo[2] = {dmin(a[0], d[0]), dmin(a[1], d[1])}, dhi[2] = {dmax(a[0], d[0]), dmax(a[1], d[1])};
    double tri[6] = {a[0], a[1], b[0], b[1], d[0], d[1]};
    int nc = prw_cellgrid_cover(&g->g, tri, 3, &g->cov, &g->covcap);
    for (int ci = 0; ci < nc; ci++) {
        for (int it = g->head[g->cov[ci]]; it >= 0; it = g->cnext[it]) {
            if (it == pv || it == cur || it == nx) continue;
            const double *q = P(c, it);
            if (q[0] < lo0 || q[0] > hi0 || q[1] < lo1 || q[1] > hi1) continue;
            if (!g->full) { /* the edges from and to q (not those from the ear's own nodes) */
                int qp = c->nodes[it].prev;
                if (crosses(a, d, q, P(c, c->nodes[it].next), dlo, dhi)) return false;
                if (qp != pv && qp != cur && qp != nx && crosses(a, d, P(c, qp), q, dlo, dhi)) return false;
            }
            if (same(q, a) || same(q, b) || same(q, d)) {
                /* a pinch (the ring passes through a corner again): the other sheet's neighbours must
                 * not enter the ear */
                const double *qp = P(c, c->nodes[it].prev), *qn = P(c, c->nodes[it].next);
                if ((!same(qp, a) && !same(qp, b) && !same(qp, d) && in_triangle(a, b, d, qp, true)) ||
                    (!same(qn, a) && !same(qn, b) && !same(qn, d) && in_triangle(a, b, d, qn, true)))
                    return false;
                continue;
            }
            if (in_triangle(a, b, d, q, strict)) return false;
        }
    }
    if (!g->full) return true;
    /* the diagonal a-d must not cross a ring edge */
    double diag[4] = {a[0], a[1], d[0], d[1]};
    nc = prw_cellgrid_cover(&g->g, diag, 2, &g->cov, &g->covcap);
    for (int ci = 0; ci < nc; ci++) {
        elist *l = &g->edges[g->cov[ci]];
        for (int k = 0; k < l->n;) {
            int it = l->v[k], jt = l->v[k + 1];
            if (g->cell[it] < 0 || c->nodes[it].next != jt) { /* gone: drop the entry */
                l->n -= 2;
                l->v[k] = l->v[l->n];
                l->v[k + 1] = l->v[l->n + 1];
                continue;
            }
            k += 2;
            if (it == pv || it == cur || it == nx) continue;
            if (crosses(a, d, P(c, it), P(c, jt), dlo, dhi)) return false;
        }
    }
    return true;
}

static void clip_ring(ctx *c, int start, prw_earclip_stats *st)
{
    int n = 1;
    for (int it = c->nodes[start].next; it != start; it = c->nodes[it].next) n++;
    grid_build(c, start, n);
    int cur = start, stall = 0, pass = 0;
    while (n > 3) {
        int pv = c->nodes[cur].prev, nx = c->nodes[cur].next;
        const double *a = P(c, pv), *b = P(c, cur), *d = P(c, nx);
        if (same(b, d) || same(a, b)) { /* duplicate point: drop without a triangle */
            unlink_node(c, cur);
            n--;
            cur = nx;
            stall = 0;
            continue;
        }
        int o = turn(c, cur);
        if (o == 0 && (b[0] - a[0]) * (d[0] - b[0]) + (b[1] - a[1]) * (d[1] - b[1]) < 0) {
            unlink_node(c, cur); /* spike: the boundary doubles back on itself */
            n--;
            cur = nx;
            stall = 0;
            if (!c->gr.full) index_edges(c, cur, n); /* the new edge may overlap a twin */
            continue;
        }
        if (o > 0 && is_ear(c, pv, cur, nx, pass == 1)) {
            emit(c, pv, cur, nx);
            unlink_node(c, cur);
            n--;
            cur = nx;
            stall = 0;
            /* an ear with a vertex on its diagonal (second pass) leaves that vertex on an edge */
            if (pass == 1 && !c->gr.full) index_edges(c, cur, n);
            pass = 0;
            continue;
        }
        cur = nx;
        if (++stall <= n) continue;
        stall = 0;
        if (pass == 0) {
            pass = 1;
            continue;
        }
        /* forced: the convex vertex with the largest triangle */
        int bestn = -1;
        double besta = 0;
        int it = cur;
        for (int k = 0; k < n; k++, it = c->nodes[it].next) {
            const double *x = P(c, c->nodes[it].prev), *y = P(c, it), *z = P(c, c->nodes[it].next);
            if (turn(c, it) <= 0) continue;
            double ar = (y[0] - x[0]) * (z[1] - x[1]) - (y[1] - x[1]) * (z[0] - x[0]);
            if (ar > besta) {
                besta = ar;
                bestn = it;
            }
        }
        if (bestn < 0) {
            st->leftover += n;
            grid_free(c);
            return;
        }
        emit(c, c->nodes[bestn].prev, bestn, c->nodes[bestn].next);
        cur = c->nodes[bestn].next;
        unlink_node(c, bestn);
        n--;
        st->forced++;
        if (!c->gr.full) index_edges(c, cur, n);
        pass = 0;
    }
    int pv = c->nodes[cur].prev, nx = c->nodes[cur].next;
    if (n == 3 && prw_orient2d(P(c, pv), P(c, cur), P(c, nx)) > 0) emit(c, pv, cur, nx);
    else if (n == 3) st->leftover += 3;
    grid_free(c);
}

typedef struct hole_ref {
    int ring;
    double maxx;
} hole_ref;

static int cmp_hole(const void *a, const void *b)
{
    double x = ((const hole_ref *)a)->maxx, y = ((const hole_ref *)b)->maxx;
    return (x < y) - (x > y); /* descending */
}

bool prw_earclip(const double *xy, const int *idx, const int *start, int nloops, int **tris, int *ntris,
                 prw_earclip_stats *st, prw_error *e)
{
    ctx c = {.xy = xy};
    memset(st, 0, sizeof *st);
    int *depth = prw_calloc((size_t)nloops + 1, sizeof(int));
    int *parent = prw_malloc(sizeof(int) * ((size_t)nloops + 1));
    double *area = prw_malloc(sizeof(double) * ((size_t)nloops + 1));
    for (int l = 0; l < nloops; l++) {
        int n = start[l + 1] - start[l];
        if (n < 3) {
            free(depth);
            free(parent);
            free(area);
            return prw_fail(e, "earclip: loop %d has %d points", l, n);
        }
        area[l] = loop_area(xy, idx + start[l], n);
        parent[l] = -1;
    }
    /* containment: depth = number of containing loops; parent = the deepest container */
    for (int l = 0; l < nloops; l++)
        for (int k = 0; k < nloops; k++)
            if (k != l && loop_inside(xy, idx + start[l], start[l + 1] - start[l], idx + start[k], start[k + 1] - start[k]))
                depth[l]++;
    for (int l = 0; l < nloops; l++)
        for (int k = 0; k < nloops; k++)
            if (k != l && depth[k] == depth[l] - 1 &&
                loop_inside(xy, idx + start[l], start[l + 1] - start[l], idx + start[k], start[k + 1] - start[k]))
                parent[l] = k;
    hole_ref *holes = prw_malloc(sizeof(hole_ref) * ((size_t)nloops + 1));
    for (int l = 0; l < nloops; l++) {
        if (depth[l] % 2) continue;
        int outer = make_ring(&c, idx + start[l], start[l + 1] - start[l], true, area[l]);
        int nh = 0;
        for (int k = 0; k < nloops; k++) {
            if (parent[k] != l || depth[k] % 2 == 0) continue;
            int n = start[k + 1] - start[k];
            holes[nh].ring = make_ring(&c, idx + start[k], n, false, area[k]);
            holes[nh].maxx = -INFINITY;
            for (int i = 0; i < n; i++) holes[nh].maxx = dmax(holes[nh].maxx, xy[2 * idx[start[k] + i]]);
            nh++;
        }
        qsort(holes, (size_t)nh, sizeof *holes, cmp_hole);
        for (int h = 0; h < nh; h++) bridge(&c, outer, holes[h].ring);
        clip_ring(&c, outer, st);
    }
    free(holes);
    free(depth);
    free(parent);
    free(area);
    free(c.nodes);
    *tris = c.tris;
    *ntris = c.ntris;
    return true;
}
