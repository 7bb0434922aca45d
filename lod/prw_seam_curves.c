/* Seam-graph setup, part 1: boundary curves in model space, dense flattening, the adjacency grid,
 * and the split of each curve into pieces labelled with their partner curve (see prw_seam.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_nurbs_make.h"
#include "prw_seam_internal.h"

prw_dvec3 seam_curve_eval(const seam_curve *c, double t)
{
    prw_dvec3 q = prw_nurbs_curve_eval(&c->uv, t);
    return prw_nurbs_surface_eval(c->surf, q.x, q.y);
}

double seam_curve_uv(const seam_curve *c, double t, double *uv)
{
    prw_dvec3 q = prw_nurbs_curve_eval(&c->uv, t);
    uv[0] = q.x;
    uv[1] = q.y;
    return t;
}

static double seg_dist(prw_dvec3 p, prw_dvec3 a, prw_dvec3 b, double *s)
{
    prw_dvec3 ab = prw_v3_sub(b, a), ap = prw_v3_sub(p, a);
    double l2 = prw_v3_dot(ab, ab), t = l2 > 0 ? prw_v3_dot(ap, ab) / l2 : 0;
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    if (s) *s = t;
    return prw_v3_len(prw_v3_sub(p, prw_v3_add(a, prw_v3_scale(ab, t))));
}

/* Appends the dense flattening of [a, b] (point a included, b not). */
static void flatten(seam_ctx *cx, seam_curve *c, double a, double b, int *cap)
{
    double st[64][2];
    int sp = 0;
    st[sp][0] = a, st[sp][1] = b, sp++;
    int depth_guard = 0;
    while (sp > 0) {
        sp--;
        double ta = st[sp][0], tb = st[sp][1];
        prw_dvec3 xa = seam_curve_eval(c, ta), xb = seam_curve_eval(c, tb);
        bool ok = prw_v3_len(prw_v3_sub(xb, xa)) <= 0.25 * cx->max_edge;
        for (int k = 1; k <= 3 && ok; k++)
            ok = seg_dist(seam_curve_eval(c, ta + (tb - ta) * k / 4), xa, xb, NULL) <= cx->chord / 16;
        if (!ok && sp < 62 && tb - ta > 1e-12 * (c->t1 - c->t0) && depth_guard < 1000000) {
            depth_guard++;
            double mid = 0.5 * (ta + tb);
            st[sp][0] = mid, st[sp][1] = tb, sp++; /* right half processed after the left */
            st[sp][0] = ta, st[sp][1] = mid, sp++;
            continue;
        }
        if (c->n + 1 >= *cap) {
            *cap = *cap ? 2 * *cap : 64;
            c->t = prw_realloc(c->t, sizeof(double) * (size_t)*cap);
            c->x = prw_realloc(c->x, sizeof(prw_dvec3) * (size_t)*cap);
        }
        c->t[c->n] = ta;
        c->x[c->n] = xa;
        c->n++;
    }
}

static void add_curve(seam_ctx *cx, int *ccap, int patch, int loop, const prw_nurbs_surface *s, prw_nurbs_curve *uv)
{
    if (cx->ncurves == *ccap) {
        *ccap = *ccap ? 2 * *ccap : 64;
        cx->curves = prw_realloc(cx->curves, sizeof(seam_curve) * (size_t)*ccap);
    }
    seam_curve *c = &cx->curves[cx->ncurves++];
    memset(c, 0, sizeof *c);
    c->patch = patch;
    c->loop = loop;
    c->surf = s;
    c->uv = *uv;
    prw_nurbs_curve_domain(uv, &c->t0, &c->t1);
    int cap = 0;
    /* start from the distinct knots (kinks of polylines, arcs of circles) */
    const double *U = uv->knots;
    double prev = c->t0;
    for (int k = uv->degree + 1; k <= uv->n; k++) {
        double kt = k == uv->n ? c->t1 : U[k];
        if (kt <= prev) continue;
        double mid = 0.5 * (prev + kt);
        flatten(cx, c, prev, mid, &cap);
        flatten(cx, c, mid, kt, &cap);
        prev = kt;
    }
    if (c->n + 1 >= cap) {
        cap += 2;
        c->t = prw_realloc(c->t, sizeof(double) * (size_t)cap);
        c->x = prw_realloc(c->x, sizeof(prw_dvec3) * (size_t)cap);
    }
    c->t[c->n] = c->t1;
    c->x[c->n] = seam_curve_eval(c, c->t1);
    c->n++;
    c->lo = c->hi = c->x[0];
    for (int i = 0; i < c->n; i++) {
        c->lo = prw_v3_min(c->lo, c->x[i]);
        c->hi = prw_v3_max(c->hi, c->x[i]);
        if (i) c->length += prw_v3_len(prw_v3_sub(c->x[i], c->x[i - 1]));
    }
}

static uint64_t cell_key(int64_t ix, int64_t iy, int64_t iz)
{
    return ((uint64_t)(ix & 0x1FFFFF) << 42) | ((uint64_t)(iy & 0x1FFFFF) << 21) | (uint64_t)(iz & 0x1FFFFF);
}

typedef struct kv {
    uint64_t k, v;
} kv;

static int cmp_kv(const void *a, const void *b)
{
    const kv *x = a, *y = b;
    return x->k < y->k ? -1 : x->k > y->k ? 1 : x->v < y->v ? -1 : x->v > y->v;
}

static void build_grid(seam_ctx *cx, double diag)
{
    cx->cell = fmax(2 * cx->tol, diag / 256);
    cx->origin = prw_v3(INFINITY, INFINITY, INFINITY);
    for (int i = 0; i < cx->ncurves; i++) cx->origin = prw_v3_min(cx->origin, cx->curves[i].lo);
    cx->origin = prw_v3_sub(cx->origin, prw_v3(cx->cell, cx->cell, cx->cell));
    kv *list = NULL;
    size_t n = 0, cap = 0;
    for (int ci = 0; ci < cx->ncurves; ci++) {
        const seam_curve *c = &cx->curves[ci];
        for (int i = 0; i + 1 < c->n; i++) {
            prw_dvec3 lo = prw_v3_min(c->x[i], c->x[i + 1]), hi = prw_v3_max(c->x[i], c->x[i + 1]);
            double r = cx->tol;
            int64_t a[3], b[3];
            double l[3] = {lo.x - r, lo.y - r, lo.z - r}, h[3] = {hi.x + r, hi.y + r, hi.z + r};
            double o[3] = {cx->origin.x, cx->origin.y, cx->origin.z};
            for (int d = 0; d < 3; d++) {
                a[d] = (int64_t)floor((l[d] - o[d]) / cx->cell);
                b[d] = (int64_t)floor((h[d] - o[d]) / cx->cell);
            }
            for (int64_t x = a[0]; x <= b[0]; x++)
                for (int64_t y = a[1]; y <= b[1]; y++)
                    for (int64_t z = a[2]; z <= b[2]; z++) {
                        if (n == cap) {
                            cap = cap ? 2 * cap : 1024;
                            list = prw_realloc(list, sizeof(kv) * cap);
                        }
                        list[n].k = cell_key(x, y, z);
                        list[n].v = ((uint64_t)ci << 32) | (uint32_t)i;
                        n++;
                    }
        }
    }
    if (n) qsort(list, n, sizeof(kv), cmp_kv);
    cx->cell_key = prw_malloc(sizeof(uint64_t) * n + 1);
    cx->cell_edge = prw_malloc(sizeof(uint64_t) * n + 1);
    for (size_t i = 0; i < n; i++) {
        cx->cell_key[i] = list[i].k;
        cx->cell_edge[i] = list[i].v;
    }
    cx->ncell = n;
    free(list);
}

static bool dir_ok(prw_dvec3 dir, prw_dvec3 a, prw_dvec3 b)
{
    prw_dvec3 d = prw_v3_sub(b, a);
    double ld = prw_v3_len(d), l = prw_v3_len(dir);
    if (!(ld > 0) || !(l > 0)) return true;
    return fabs(prw_v3_dot(d, dir)) >= 0.5 * ld * l;
}

int seam_nearest_curve(const seam_ctx *cx, prw_dvec3 x, prw_dvec3 dir, int exclude, double radius, double *dist)
{
    int best = -1;
    double bd = INFINITY;
    if (radius <= cx->tol) {
        int64_t ix = (int64_t)floor((x.x - cx->origin.x) / cx->cell), iy = (int64_t)floor((x.y - cx->origin.y) / cx->cell),
                iz = (int64_t)floor((x.z - cx->origin.z) / cx->cell);
        uint64_t k = cell_key(ix, iy, iz);
        size_t lo = 0, hi = cx->ncell;
        while (lo < hi) {
            size_t mid = (lo + hi) / 2;
            if (cx->cell_key[mid] < k) lo = mid + 1;
            else hi = mid;
        }
        for (size_t i = lo; i < cx->ncell && cx->cell_key[i] == k; i++) {
            int ci = (int)(cx->cell_edge[i] >> 32), ei = (int)(cx->cell_edge[i] & 0xFFFFFFFFu);
            if (ci == exclude) continue;
            const seam_curve *c = &cx->curves[ci];
            double d = seg_dist(x, c->x[ei], c->x[ei + 1], NULL);
            if (d <= radius && d < bd && dir_ok(dir, c->x[ei], c->x[ei + 1])) {
                bd = d;
                best = ci;
            }
        }
    } else {
        for (int ci = 0; ci < cx->ncurves; ci++) {
            if (ci == exclude) continue;
            const seam_curve *c = &cx->curves[ci];
            double r = fmin(radius, bd);
            if (x.x < c->lo.x - r || x.y < c->lo.y - r || x.z < c->lo.z - r || x.x > c->hi.x + r || x.y > c->hi.y + r ||
                x.z > c->hi.z + r)
                continue;
            for (int ei = 0; ei + 1 < c->n; ei++) {
                double d = seg_dist(x, c->x[ei], c->x[ei + 1], NULL);
                if (d <= radius && d < bd && dir_ok(dir, c->x[ei], c->x[ei + 1])) {
                    bd = d;
                    best = ci;
                }
            }
        }
    }
    if (dist) *dist = bd;
    return best;
}

bool seam_curves_build(seam_ctx *cx, prw_seam_graph *g, prw_error *e)
{
    (void)e;
    const prw_nurbs_model *m = cx->m;
    int ccap = 0, lcap = 0;
    cx->patch_loop_first = prw_malloc(sizeof(int) * (m->count + 1));
    cx->loop_curve_start = NULL;
    cx->nloops_total = 0;
#define OPEN_LOOP()                                                                                   \
    do {                                                                                              \
        if (cx->nloops_total + 2 > lcap) {                                                            \
            lcap = lcap ? 2 * lcap : 64;                                                              \
            cx->loop_curve_start = prw_realloc(cx->loop_curve_start, sizeof(int) * (size_t)lcap);     \
        }                                                                                             \
        cx->loop_curve_start[cx->nloops_total++] = cx->ncurves;                                       \
    } while (0)
    for (size_t p = 0; p < m->count; p++) {
        const prw_trimmed_surface *t = &m->surfaces[p];
        cx->patch_loop_first[p] = cx->nloops_total;
        prw_error ve;
        if (!prw_nurbs_surface_validate(&t->surface, &ve)) {
            g->patches[p].skipped = true;
            g->skipped_patches++;
            continue;
        }
        int loop = 0;
        if (t->natural_outer) {
            double u0, u1, v0, v1;
            prw_nurbs_surface_domain(&t->surface, &u0, &u1, &v0, &v1);
            prw_dvec3 c[5] = {prw_v3(u0, v0, 0), prw_v3(u1, v0, 0), prw_v3(u1, v1, 0), prw_v3(u0, v1, 0),
                              prw_v3(u0, v0, 0)};
            OPEN_LOOP();
            for (int k = 0; k < 4; k++) {
                prw_nurbs_curve l;
                if (!prw_nurbs_make_line(&l, 2, c[k], c[k + 1], &ve)) continue;
                add_curve(cx, &ccap, (int)p, loop, &t->surface, &l);
            }
            loop++;
        }
        for (int l = 0; l < t->nloops; l++) {
            OPEN_LOOP();
            for (int k = 0; k < t->loops[l].count; k++) {
                prw_nurbs_curve cc;
                if (!prw_nurbs_curve_copy(&cc, &t->loops[l].segs[k].uv, &ve)) continue;
                add_curve(cx, &ccap, (int)p, loop, &t->surface, &cc);
            }
            loop++;
        }
    }
    cx->patch_loop_first[m->count] = cx->nloops_total;
    if (cx->nloops_total + 1 > lcap) cx->loop_curve_start = prw_realloc(cx->loop_curve_start, sizeof(int) * (size_t)(lcap + 1));
    cx->loop_curve_start[cx->nloops_total] = cx->ncurves;
#undef OPEN_LOOP
    build_grid(cx, g->diag);
    return true;
}

/* Label at parameter t of curve ci; `edge` is the dense edge containing t (for the direction). */
static int classify(const seam_ctx *cx, int ci, double t, int edge)
{
    const seam_curve *c = &cx->curves[ci];
    prw_dvec3 dir = prw_v3_sub(c->x[edge + 1], c->x[edge]);
    return seam_nearest_curve(cx, seam_curve_eval(c, t), dir, ci, cx->tol, NULL);
}

static void push_piece(seam_ctx *cx, int *cap, int curve, double ta, double tb, int label, bool degen)
{
    if (cx->npieces == *cap) {
        *cap = *cap ? 2 * *cap : 64;
        cx->pieces = prw_realloc(cx->pieces, sizeof(seam_piece) * (size_t)*cap);
    }
    seam_piece *p = &cx->pieces[cx->npieces++];
    memset(p, 0, sizeof *p);
    p->curve = curve;
    p->ta = ta;
    p->tb = tb;
    p->label = label;
    p->degenerate = degen;
    p->match = -1;
    p->seg = -1;
}

void seam_pieces_build(seam_ctx *cx)
{
    int cap = 0;
    int *lab = NULL;
    int lcap = 0;
    for (int ci = 0; ci < cx->ncurves; ci++) {
        const seam_curve *c = &cx->curves[ci];
        if (c->length < cx->tol) {
            push_piece(cx, &cap, ci, c->t0, c->t1, -1, true);
            continue;
        }
        if (c->n > lcap) {
            lcap = c->n;
            lab = prw_realloc(lab, sizeof(int) * (size_t)lcap);
        }
        int first = -1, last = -1;
        for (int i = 0; i < c->n; i++) {
            lab[i] = -2;
            bool eligible = prw_v3_len(prw_v3_sub(c->x[i], c->x[0])) > 2 * cx->tol &&
                            prw_v3_len(prw_v3_sub(c->x[i], c->x[c->n - 1])) > 2 * cx->tol;
            if (!eligible) continue;
            prw_dvec3 dir = prw_v3_sub(c->x[i + 1 < c->n ? i + 1 : i], c->x[i > 0 ? i - 1 : i]);
            lab[i] = seam_nearest_curve(cx, c->x[i], dir, ci, cx->tol, NULL);
            if (first < 0) first = i;
            last = i;
        }
        if (first < 0) {
            push_piece(cx, &cap, ci, c->t0, c->t1, -1, false);
            continue;
        }
        for (int i = 0; i < first; i++) lab[i] = lab[first];
        for (int i = last + 1; i < c->n; i++) lab[i] = lab[last];
        for (int i = first + 1; i < last; i++)
            if (lab[i] == -2) lab[i] = lab[i - 1];
        double ta = c->t0;
        for (int i = 0; i + 1 < c->n; i++) {
            if (lab[i] == lab[i + 1]) continue;
            double lo = c->t[i], hi = c->t[i + 1];
            for (int it = 0; it < 80; it++) {
                if (prw_v3_len(prw_v3_sub(seam_curve_eval(c, hi), seam_curve_eval(c, lo))) <= 1e-4 * cx->tol) break;
                double mid = 0.5 * (lo + hi);
                if (classify(cx, ci, mid, i) == lab[i]) lo = mid;
                else hi = mid;
            }
            double cut = 0.5 * (lo + hi);
            /* a transition at a kink of the trim curve (a knot) snaps to it exactly */
            prw_dvec3 xc = seam_curve_eval(c, cut);
            for (int q = i; q <= i + 1; q++)
                if (prw_knots_multiplicity(c->uv.knots, c->uv.n + c->uv.degree + 1, c->t[q]) > 0 &&
                    prw_v3_len(prw_v3_sub(c->x[q], xc)) <= cx->tol)
                    cut = c->t[q];
            push_piece(cx, &cap, ci, ta, cut, lab[i], false);
            ta = cut;
        }
        push_piece(cx, &cap, ci, ta, c->t1, lab[c->n - 1], false);
    }
    free(lab);
}

double seam_curve_project(const seam_curve *c, prw_dvec3 x, double ta, double tb, double *tout)
{
    double best = INFINITY, bt = ta, dt = tb - ta;
    for (int i = 0; i + 1 < c->n; i++) {
        double a = c->t[i], b = c->t[i + 1];
        if (b < ta || a > tb) continue;
        double s;
        double d = seg_dist(x, c->x[i], c->x[i + 1], &s);
        if (d < best) {
            best = d;
            bt = a + (b - a) * s;
            dt = b - a;
        }
    }
    /* golden-section refinement on the exact curve */
    double lo = fmax(ta, bt - dt), hi = fmin(tb, bt + dt);
    const double gr = 0.6180339887498949;
    double x1 = hi - gr * (hi - lo), x2 = lo + gr * (hi - lo);
    double f1 = prw_v3_len(prw_v3_sub(seam_curve_eval(c, x1), x)), f2 = prw_v3_len(prw_v3_sub(seam_curve_eval(c, x2), x));
    for (int it = 0; it < 60 && hi - lo > 1e-15 * (fabs(lo) + fabs(hi) + 1e-300); it++) {
        if (f1 < f2) {
            hi = x2, x2 = x1, f2 = f1;
            x1 = hi - gr * (hi - lo);
            f1 = prw_v3_len(prw_v3_sub(seam_curve_eval(c, x1), x));
        } else {
            lo = x1, x1 = x2, f1 = f2;
            x2 = lo + gr * (hi - lo);
            f2 = prw_v3_len(prw_v3_sub(seam_curve_eval(c, x2), x));
        }
    }
    double tm = 0.5 * (lo + hi), dm = prw_v3_len(prw_v3_sub(seam_curve_eval(c, tm), x));
    if (dm <= best) {
        *tout = tm;
        return dm;
    }
    *tout = bt;
    return prw_v3_len(prw_v3_sub(seam_curve_eval(c, bt), x));
}

void seam_ctx_free(seam_ctx *cx)
{
    for (int i = 0; i < cx->ncurves; i++) {
        prw_nurbs_curve_free(&cx->curves[i].uv);
        free(cx->curves[i].t);
        free(cx->curves[i].x);
    }
    free(cx->curves);
    free(cx->patch_loop_first);
    free(cx->loop_curve_start);
    free(cx->cell_key);
    free(cx->cell_edge);
    free(cx->pieces);
    memset(cx, 0, sizeof *cx);
}
