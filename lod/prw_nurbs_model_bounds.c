/* Bounds of the trimmed faces (prw_nurbs_model_trimmed_bounds, prw_nurbs_model.h).
 *
 * Each face's (u, v) domain is subdivided into rectangles; the surface over a rectangle is cut
 * out (knot insertion), so its control hull bounds it.  The trim loops become chords with a radius
 * (a piece of a curve lies within r of its chord: the hull of its control points does), so a
 * rectangle that no chord's capsule touches lies wholly inside or wholly outside the face, and the
 * even-odd count of its centre against the chords (the closed loops of prw_trim) tells which.
 * Rectangles outside are dropped; the others add their hull once it lies within eps of the box of
 * points known to be on faces (the trim curves' points, corners and centres of inside rectangles),
 * else they are split.  A face inside its loops (no natural outer boundary) starts from the loops'
 * (u, v) box, not the whole domain.  Two passes: the first only gathers face points (shallow), so
 * the second accepts early. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_nurbs_model.h"

#define REL_TOL 1e-4          /* accepted excess, per side, x the face points' box diagonal */
#define PASS1_DEPTH 6         /* first pass: at most 2^6 rectangles per face */
#define MAX_DEPTH 60          /* splits along one path */
#define MAX_RECTS 200000      /* per face and pass; beyond it hulls are taken as they are */
#define MAX_CHORDS 1000000    /* per face (curve pieces beyond it keep a larger radius) */
#define MAX_CURVE_DEPTH 24
#define MAX_SAMPLES 200000    /* model-space points per face's trim curves (default) */
#define MAX_WORK 400000000L   /* per model (default): control points of all cut-out patches x their degrees */

typedef struct chord {
    double a[2], b[2], r;
} chord;

typedef struct box {
    double lo[3], hi[3];
} box;

typedef struct face_ctx {
    const prw_trimmed_surface *t;
    chord *ch;
    int nch, cap;
    double u0, u1, v0, v1;
    long rects, samples;
    /* chords by v: bucket b holds (CSR) the chords whose v range meets [vb0 + b·dvb, vb0 + (b+1)·dvb] */
    int nb, *bstart, *bidx;
    double vb0, dvb;
    long *work; /* model-wide cost so far */
    long max_work, max_samples;
    box *inner; /* points on faces (model-wide) */
    box *outer; /* the result (model-wide) */
    double eps;
    bool pass2, capped;
} face_ctx;

static void box_empty(box *b)
{
    for (int k = 0; k < 3; k++) b->lo[k] = INFINITY, b->hi[k] = -INFINITY;
}

static void box_add(box *b, prw_dvec3 p)
{
    double q[3] = {p.x, p.y, p.z};
    for (int k = 0; k < 3; k++) b->lo[k] = fmin(b->lo[k], q[k]), b->hi[k] = fmax(b->hi[k], q[k]);
}

static void box_union(box *b, prw_dvec3 lo, prw_dvec3 hi)
{
    box_add(b, lo);
    box_add(b, hi);
}

static void add_chord(face_ctx *f, double ax, double ay, double bx, double by, double r)
{
    if (f->nch == f->cap) {
        f->cap = f->cap ? 2 * f->cap : 64;
        f->ch = prw_realloc(f->ch, sizeof *f->ch * (size_t)f->cap);
    }
    f->ch[f->nch++] = (chord){{ax, ay}, {bx, by}, r};
}

/* A point of a trim curve is on the face (the closed region) when it lies in the domain. */
static void add_trim_point(face_ctx *f, double u, double v)
{
    double tu = 1e-12 * (f->u1 - f->u0), tv = 1e-12 * (f->v1 - f->v0);
    if (u < f->u0 - tu || u > f->u1 + tu || v < f->v0 - tv || v > f->v1 + tv) return;
    box_add(f->inner, prw_nurbs_surface_eval(&f->t->surface, u, v));
}

static double seg_dist(const double *a, const double *b, double px, double py)
{
    double dx = b[0] - a[0], dy = b[1] - a[1], l2 = dx * dx + dy * dy;
    double s = l2 > 0 ? ((px - a[0]) * dx + (py - a[1]) * dy) / l2 : 0;
    s = fmin(fmax(s, 0), 1);
    return hypot(px - a[0] - s * dx, py - a[1] - s * dy);
}

/* A clamped Bezier / B-spline piece c over its domain: one chord from its first to its last
 * control point with r = the largest control point distance to it, or split in two. */
static bool curve_chords(face_ctx *f, const prw_nurbs_curve *c, double rtol, int depth, prw_error *e)
{
    double p0[2] = {c->pw[0] / c->pw[3], c->pw[1] / c->pw[3]};
    const double *q = c->pw + 4 * (c->n - 1);
    double p1[2] = {q[0] / q[3], q[1] / q[3]}, r = 0;
    for (int i = 1; i < c->n - 1; i++) {
        const double *w = c->pw + 4 * i;
        r = fmax(r, seg_dist(p0, p1, w[0] / w[3], w[1] / w[3]));
    }
    double t0, t1;
    prw_nurbs_curve_domain(c, &t0, &t1);
    if (!(r > rtol) || depth >= MAX_CURVE_DEPTH || f->nch >= MAX_CHORDS) {
        add_chord(f, p0[0], p0[1], p1[0], p1[1], r);
        add_trim_point(f, p0[0], p0[1]);
        add_trim_point(f, p1[0], p1[1]);
        prw_dvec3 m = prw_nurbs_curve_eval(c, 0.5 * (t0 + t1));
        add_trim_point(f, m.x, m.y);
        return true;
    }
    double tm = 0.5 * (t0 + t1);
    prw_nurbs_curve a, b;
    if (!prw_nurbs_curve_extract(c, t0, tm, &a, e)) return false;
    if (!prw_nurbs_curve_extract(c, tm, t1, &b, e)) {
        prw_nurbs_curve_free(&a);
        return false;
    }
    bool ok = curve_chords(f, &a, rtol, depth + 1, e) && curve_chords(f, &b, rtol, depth + 1, e);
    prw_nurbs_curve_free(&a);
    prw_nurbs_curve_free(&b);
    return ok;
}

static bool segment_chords(face_ctx *f, const prw_nurbs_curve *c, double rtol, prw_error *e)
{
    if (c->degree == 1) { /* a rational degree-1 curve is its control polygon */
        for (int i = 0; i + 1 < c->n; i++) {
            const double *a = c->pw + 4 * i, *b = a + 4;
            add_chord(f, a[0] / a[3], a[1] / a[3], b[0] / b[3], b[1] / b[3], 0);
        }
        for (int i = 0; i < c->n; i++) add_trim_point(f, c->pw[4 * i] / c->pw[4 * i + 3], c->pw[4 * i + 1] / c->pw[4 * i + 3]);
        return true;
    }
    /* knot spans one by one (Bezier pieces converge fast) */
    double t0, t1;
    prw_nurbs_curve_domain(c, &t0, &t1);
    double a = t0;
    for (int k = c->degree + 1; k <= c->n && a < t1; k++) {
        double b = k == c->n ? t1 : fmin(c->knots[k], t1);
        if (!(b > a)) continue;
        prw_nurbs_curve piece;
        if (!prw_nurbs_curve_extract(c, a, b, &piece, e)) return false;
        bool ok = curve_chords(f, &piece, rtol, 0, e);
        prw_nurbs_curve_free(&piece);
        if (!ok) return false;
        a = b;
    }
    return true;
}

/* Points of the trim curve c over [a, b] on the face, until the model-space midpoint lies within
 * tol of the model-space chord's midpoint (so the points' box misses little of the curve's). */
static void sample_curve(face_ctx *f, const prw_nurbs_curve *c, double a, double b, prw_dvec3 pa, prw_dvec3 pb,
                         double tol, int depth)
{
    double m = 0.5 * (a + b);
    prw_dvec3 q = prw_nurbs_curve_eval(c, m);
    add_trim_point(f, q.x, q.y);
    if (depth >= MAX_CURVE_DEPTH || ++f->samples > f->max_samples) return;
    prw_dvec3 pm = prw_nurbs_surface_eval(&f->t->surface, q.x, q.y);
    if (depth >= 2 && !(prw_v3_len(prw_v3_sub(pm, prw_v3_scale(prw_v3_add(pa, pb), 0.5))) > tol)) return;
    sample_curve(f, c, a, m, pa, pm, tol, depth + 1);
    sample_curve(f, c, m, b, pm, pb, tol, depth + 1);
}

static void sample_loops(face_ctx *f, double tol)
{
    for (int l = 0; l < f->t->nloops; l++)
        for (int s = 0; s < f->t->loops[l].count; s++) {
            const prw_nurbs_curve *c = &f->t->loops[l].segs[s].uv;
            double t0, t1;
            prw_nurbs_curve_domain(c, &t0, &t1);
            double a = t0;
            for (int k = c->degree + 1; k <= c->n && a < t1; k++) { /* span by span */
                double b = k == c->n ? t1 : fmin(c->knots[k], t1);
                if (!(b > a)) continue;
                prw_dvec3 qa = prw_nurbs_curve_eval(c, a), qb = prw_nurbs_curve_eval(c, b);
                sample_curve(f, c, a, b, prw_nurbs_surface_eval(&f->t->surface, qa.x, qa.y),
                             prw_nurbs_surface_eval(&f->t->surface, qb.x, qb.y), tol, 0);
                a = b;
            }
        }
}

/* The loops as chords, consecutive segments joined and each loop closed from its last point back
 * to its first (the polygons of prw_trim). */
static bool build_chords(face_ctx *f, double rtol, prw_error *e)
{
    const prw_trimmed_surface *t = f->t;
    for (int l = 0; l < t->nloops; l++) {
        int first = -1;
        double end[2] = {0, 0};
        for (int s = 0; s < t->loops[l].count; s++) {
            int k0 = f->nch;
            if (!segment_chords(f, &t->loops[l].segs[s].uv, rtol, e)) return false;
            if (f->nch == k0) continue;
            double a[2] = {f->ch[k0].a[0], f->ch[k0].a[1]}, b[2] = {f->ch[f->nch - 1].b[0], f->ch[f->nch - 1].b[1]};
            if (first < 0) first = k0;
            else if (a[0] != end[0] || a[1] != end[1]) add_chord(f, end[0], end[1], a[0], a[1], 0); /* (unordered set) */
            end[0] = b[0], end[1] = b[1];
        }
        if (first >= 0 && (f->ch[first].a[0] != end[0] || f->ch[first].a[1] != end[1]))
            add_chord(f, end[0], end[1], f->ch[first].a[0], f->ch[first].a[1], 0);
    }
    return true;
}

/* Could chord c's capsule meet the rectangle?  (The segment against the rectangle grown by r on
 * every side: a superset of the capsule test.) */
static bool touches(const chord *c, double u0, double u1, double v0, double v1)
{
    u0 -= c->r, u1 += c->r, v0 -= c->r, v1 += c->r;
    if (fmax(c->a[0], c->b[0]) < u0 || fmin(c->a[0], c->b[0]) > u1 || fmax(c->a[1], c->b[1]) < v0 ||
        fmin(c->a[1], c->b[1]) > v1)
        return false;
    double dx = c->b[0] - c->a[0], dy = c->b[1] - c->a[1];
    double s[4] = {dx * (v0 - c->a[1]) - dy * (u0 - c->a[0]), dx * (v0 - c->a[1]) - dy * (u1 - c->a[0]),
                   dx * (v1 - c->a[1]) - dy * (u0 - c->a[0]), dx * (v1 - c->a[1]) - dy * (u1 - c->a[0])};
    bool pos = false, neg = false;
    for (int k = 0; k < 4; k++) pos |= s[k] >= 0, neg |= s[k] <= 0;
    return pos && neg; /* the line through the chord separates no corner from the others: it crosses */
}

static void bucket_range(const face_ctx *f, double va, double vb, int *b0, int *b1)
{
    double x0 = (fmin(va, vb) - f->vb0) / f->dvb, x1 = (fmax(va, vb) - f->vb0) / f->dvb;
    *b0 = x0 < 0 ? 0 : x0 >= f->nb ? f->nb - 1 : (int)x0;
    *b1 = x1 < 0 ? 0 : x1 >= f->nb ? f->nb - 1 : (int)x1;
}

/* The buckets of the inside test (few chords per ray on long loops). */
static void build_buckets(face_ctx *f)
{
    double lo = INFINITY, hi = -INFINITY;
    for (int i = 0; i < f->nch; i++) lo = fmin(lo, fmin(f->ch[i].a[1], f->ch[i].b[1])), hi = fmax(hi, fmax(f->ch[i].a[1], f->ch[i].b[1]));
    f->nb = f->nch / 4 < 1 ? 1 : f->nch / 4 > 4096 ? 4096 : f->nch / 4;
    f->vb0 = lo;
    f->dvb = hi > lo ? (hi - lo) / f->nb : 1;
    f->bstart = prw_calloc((size_t)f->nb + 1, sizeof(int));
    for (int pass = 0; pass < 2; pass++) {
        for (int i = 0; i < f->nch; i++) {
            int b0, b1;
            bucket_range(f, f->ch[i].a[1], f->ch[i].b[1], &b0, &b1);
            for (int b = b0; b <= b1; b++) {
                if (pass == 0) f->bstart[b + 1]++;
                else f->bidx[f->bstart[b]++] = i;
            }
        }
        if (pass == 0) {
            for (int b = 0; b < f->nb; b++) f->bstart[b + 1] += f->bstart[b];
            f->bidx = prw_malloc(sizeof(int) * ((size_t)f->bstart[f->nb] + 1));
        } else {
            for (int b = f->nb; b > 0; b--) f->bstart[b] = f->bstart[b - 1]; /* undo the fill's shift */
            f->bstart[0] = 0;
        }
    }
}

/* Even-odd count of the chords crossed by the ray from (u, v) towards +u (the chords of v's
 * bucket: every chord whose v range holds v is there); the domain rectangle counts once for a
 * natural outer boundary. */
static bool inside(const face_ctx *f, double u, double v)
{
    bool in = f->t->natural_outer;
    if (!f->nch) return in;
    int b, b1;
    bucket_range(f, v, v, &b, &b1);
    for (int k = f->bstart[b]; k < f->bstart[b + 1]; k++) {
        const chord *c = &f->ch[f->bidx[k]];
        if ((c->a[1] > v) == (c->b[1] > v)) continue;
        double x = c->a[0] + (v - c->a[1]) * (c->b[0] - c->a[0]) / (c->b[1] - c->a[1]);
        if (x > u) in = !in;
    }
    return in;
}

static bool within(const face_ctx *f, prw_dvec3 lo, prw_dvec3 hi)
{
    const box *b = f->inner;
    double l[3] = {lo.x, lo.y, lo.z}, h[3] = {hi.x, hi.y, hi.z};
    for (int k = 0; k < 3; k++)
        if (!(l[k] >= b->lo[k] - f->eps && h[k] <= b->hi[k] + f->eps)) return false;
    return true;
}

/* Length of the control polygon of row (dir 0) or column (dir 1) r of P. */
static double net_length(const prw_nurbs_surface *P, int dir, int r)
{
    int n = dir ? P->nv : P->nu;
    size_t step = dir ? (size_t)P->nu : 1, base = dir ? (size_t)r : (size_t)r * (size_t)P->nu;
    double len = 0;
    for (int i = 1; i < n; i++) {
        const double *a = P->pw + 4 * (base + (size_t)(i - 1) * step), *b = P->pw + 4 * (base + (size_t)i * step);
        len += hypot(hypot(a[0] / a[3] - b[0] / b[3], a[1] / a[3] - b[1] / b[3]), a[2] / a[3] - b[2] / b[3]);
    }
    return len;
}

/* Where to split patch P (over [u0, u1] x [v0, v1]): along its longer direction in model space
 * (control polygon lengths of the edge and middle rows: closed rows have length too), at its
 * middle interior knot, else at the middle. */
static void split_at(const face_ctx *f, const prw_nurbs_surface *P, double u0, double u1, double v0, double v1, int *dir,
                     double *at)
{
    double eu = 0, ev = 0;
    int rows[3] = {0, P->nv / 2, P->nv - 1}, cols[3] = {0, P->nu / 2, P->nu - 1};
    for (int k = 0; k < 3; k++) eu = fmax(eu, net_length(P, 0, rows[k])), ev = fmax(ev, net_length(P, 1, cols[k]));
    *dir = ev > eu ? 1 : 0;
    if (!(eu > 0) && !(ev > 0)) *dir = v1 - v0 > u1 - u0 ? 1 : 0; /* collapsed: by parameter */
    if (*dir == 0 && u1 - u0 <= 1e-12 * (f->u1 - f->u0)) *dir = 1; /* too thin to split further */
    else if (*dir == 1 && v1 - v0 <= 1e-12 * (f->v1 - f->v0)) *dir = 0;
    const double *U = *dir ? P->knots_v : P->knots_u;
    int n = *dir ? P->nv : P->nu, p = *dir ? P->degree_v : P->degree_u;
    double lo = *dir ? v0 : u0, hi = *dir ? v1 : u1;
    int count = 0;
    for (int i = p + 1; i < n; i++)
        if (U[i] > lo && U[i] < hi && U[i] != U[i - 1]) count++;
    *at = 0.5 * (lo + hi);
    if (count > 0)
        for (int i = p + 1, m = 0; i < n; i++)
            if (U[i] > lo && U[i] < hi && U[i] != U[i - 1] && m++ == count / 2) *at = U[i];
}

static void visit(face_ctx *f, const prw_nurbs_surface *P, double u0, double u1, double v0, double v1, const int *idx,
                  int nidx, int depth)
{
    f->rects++;
    *f->work += (long)P->nu * P->nv * (P->degree_u + P->degree_v + 2);
    int *sub = nidx ? prw_malloc(sizeof(int) * (size_t)nidx) : NULL, ns = 0;
    for (int i = 0; i < nidx; i++)
        if (touches(&f->ch[idx[i]], u0, u1, v0, v1)) sub[ns++] = idx[i];
    double um = 0.5 * (u0 + u1), vm = 0.5 * (v0 + v1);
    if (ns == 0) {
        if (!inside(f, um, vm)) goto done; /* wholly outside the face */
        double us[3] = {u0, um, u1}, vs[3] = {v0, vm, v1};
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++) box_add(f->inner, prw_nurbs_surface_eval(P, us[a], vs[b]));
    }
    prw_dvec3 lo, hi;
    prw_nurbs_surface_bounds(P, &lo, &hi);
    bool last = depth >= (f->pass2 ? MAX_DEPTH : PASS1_DEPTH) || f->rects >= MAX_RECTS || *f->work > f->max_work ||
                (u1 - u0 <= 1e-12 * (f->u1 - f->u0) && v1 - v0 <= 1e-12 * (f->v1 - f->v0));
    if (f->pass2 && (last || within(f, lo, hi))) {
        if (!within(f, lo, hi)) f->capped = true;
        box_union(f->outer, lo, hi);
        goto done;
    }
    if (last) goto done;
    int dir;
    double at;
    split_at(f, P, u0, u1, v0, v1, &dir, &at);
    prw_nurbs_surface c[2];
    prw_error ignore;
    bool ok0 = prw_nurbs_surface_extract(P, u0, dir ? u1 : at, v0, dir ? at : v1, &c[0], &ignore);
    bool ok1 = ok0 && prw_nurbs_surface_extract(P, dir ? u0 : at, u1, dir ? at : v0, v1, &c[1], &ignore);
    if (!ok1) { /* cannot cut (should not happen): keep this hull */
        if (ok0) prw_nurbs_surface_free(&c[0]);
        if (f->pass2) box_union(f->outer, lo, hi), f->capped = true;
        goto done;
    }
    visit(f, &c[0], u0, dir ? u1 : at, v0, dir ? at : v1, sub, ns, depth + 1);
    visit(f, &c[1], dir ? u0 : at, u1, dir ? at : v0, v1, sub, ns, depth + 1);
    prw_nurbs_surface_free(&c[0]);
    prw_nurbs_surface_free(&c[1]);
done:
    free(sub);
}

/* One pass over one face.  false: the face could not be handled (its control hull is used).  A
 * face without a natural outer boundary lies inside its loops, so the search starts from the
 * loops' (u, v) box (grown by the capsule radii), clipped to the domain. */
static bool face_pass(face_ctx *f)
{
    double u0 = f->u0, u1 = f->u1, v0 = f->v0, v1 = f->v1;
    if (!f->t->natural_outer) {
        double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
        for (int i = 0; i < f->nch; i++)
            for (int k = 0; k < 2; k++) {
                const chord *c = &f->ch[i];
                lo[k] = fmin(lo[k], fmin(c->a[k], c->b[k]) - c->r), hi[k] = fmax(hi[k], fmax(c->a[k], c->b[k]) + c->r);
            }
        u0 = fmax(u0, lo[0]), u1 = fmin(u1, hi[0]), v0 = fmax(v0, lo[1]), v1 = fmin(v1, hi[1]);
        if (!(u0 < u1 && v0 < v1)) return true; /* no loop (or none in the domain): an empty face */
    }
    prw_nurbs_surface root;
    prw_error ignore;
    if (!prw_nurbs_surface_extract(&f->t->surface, u0, u1, v0, v1, &root, &ignore)) return false;
    int *idx = f->nch ? prw_malloc(sizeof(int) * (size_t)f->nch) : NULL;
    for (int i = 0; i < f->nch; i++) idx[i] = i;
    f->rects = 0;
    visit(f, &root, u0, u1, v0, v1, idx, f->nch, 0);
    free(idx);
    prw_nurbs_surface_free(&root);
    return true;
}

/* Model-space points of the trim curves at their knots and span middles (a first idea of the
 * face's size). */
static void coarse_points(face_ctx *f)
{
    for (int l = 0; l < f->t->nloops; l++)
        for (int s = 0; s < f->t->loops[l].count; s++) {
            const prw_nurbs_curve *c = &f->t->loops[l].segs[s].uv;
            double t0, t1;
            prw_nurbs_curve_domain(c, &t0, &t1);
            for (int k = c->degree; k < c->n; k++) {
                double a = fmax(c->knots[k], t0), b = fmin(c->knots[k + 1], t1);
                if (!(b >= a)) continue;
                for (int q = 0; q < 3; q++) {
                    prw_dvec3 p = prw_nurbs_curve_eval(c, a + (b - a) * q / 2);
                    add_trim_point(f, p.x, p.y);
                }
            }
        }
}

static double box_diag(const box *b)
{
    double d = 0;
    for (int k = 0; k < 3; k++) d = b->hi[k] >= b->lo[k] ? hypot(d, b->hi[k] - b->lo[k]) : d;
    return d;
}

/* Chords and trim samples of one face, then the first pass.  The capsule radius is set so that a
 * capsule is narrower than a quarter of the accepted excess in model space (the largest
 * parameter derivative over a grid of the domain, doubled, converts), the sampling so that the
 * curve's points miss at most about that much. */
static bool face_setup(face_ctx *f, box *inner)
{
    box coarse;
    box_empty(&coarse);
    f->inner = &coarse;
    coarse_points(f);
    double d = box_diag(&coarse);
    if (!(d > 0)) {
        prw_dvec3 a, b;
        prw_nurbs_surface_bounds(&f->t->surface, &a, &b);
        d = prw_v3_len(prw_v3_sub(b, a));
    }
    double lip = 0;
    for (int i = 0; i <= 8; i++)
        for (int j = 0; j <= 8; j++) {
            prw_dvec3 dd[4];
            prw_nurbs_surface_derivs(&f->t->surface, f->u0 + (f->u1 - f->u0) * i / 8, f->v0 + (f->v1 - f->v0) * j / 8, 1, dd);
            lip = fmax(lip, fmax(prw_v3_len(dd[2]), prw_v3_len(dd[1])));
        }
    double rtol = lip > 0 ? 0.25 * REL_TOL * d / (2 * lip) : 1e-9 * fmax(f->u1 - f->u0, f->v1 - f->v0);
    prw_error ignore;
    bool ok = build_chords(f, rtol, &ignore);
    if (ok) build_buckets(f);
    if (ok) sample_loops(f, 0.25 * REL_TOL * d);
    for (int k = 0; k < 3; k++) inner->lo[k] = fmin(inner->lo[k], coarse.lo[k]), inner->hi[k] = fmax(inner->hi[k], coarse.hi[k]);
    f->inner = inner;
    return ok && face_pass(f);
}

bool prw_nurbs_model_trimmed_bounds(const prw_nurbs_model *m, prw_dvec3 *lo, prw_dvec3 *hi)
{
    prw_bounds_limits lim = {.work = MAX_WORK, .samples = MAX_SAMPLES};
    return prw_nurbs_model_trimmed_bounds_limited(m, &lim, lo, hi);
}

bool prw_nurbs_model_trimmed_bounds_limited(const prw_nurbs_model *m, const prw_bounds_limits *lim, prw_dvec3 *lo,
                                            prw_dvec3 *hi)
{
    if (!m->count) return false;
    face_ctx *fc = prw_calloc(m->count, sizeof *fc);
    bool *bad = prw_calloc(m->count, sizeof *bad);
    box inner, outer;
    box_empty(&inner);
    box_empty(&outer);
    long work = 0;
    for (size_t i = 0; i < m->count; i++) {
        face_ctx *f = &fc[i];
        f->t = &m->surfaces[i];
        f->outer = &outer, f->work = &work, f->max_work = lim->work, f->max_samples = lim->samples;
        prw_nurbs_surface_domain(&f->t->surface, &f->u0, &f->u1, &f->v0, &f->v1);
        bad[i] = !face_setup(f, &inner);
    }
    double diag = box_diag(&inner);
    if (!(diag > 0)) { /* no point found yet (or all in one): scale from the control hulls */
        prw_dvec3 a, b;
        if (prw_nurbs_model_bounds(m, &a, &b)) diag = prw_v3_len(prw_v3_sub(b, a));
    }
    for (size_t i = 0; i < m->count; i++) {
        face_ctx *f = &fc[i];
        f->eps = REL_TOL * diag;
        f->pass2 = true;
        if (!bad[i]) bad[i] = !face_pass(f);
        if (bad[i]) { /* conservative fallback: the whole surface */
            prw_dvec3 a, b;
            prw_nurbs_surface_bounds(&f->t->surface, &a, &b);
            box_union(&outer, a, b);
        }
        free(f->ch);
        free(f->bstart);
        free(f->bidx);
    }
    free(fc);
    free(bad);
    if (!(outer.lo[0] <= outer.hi[0])) return prw_nurbs_model_bounds(m, lo, hi); /* nothing inside any loop */
    *lo = prw_v3(outer.lo[0], outer.lo[1], outer.lo[2]);
    *hi = prw_v3(outer.hi[0], outer.hi[1], outer.hi[2]);
    return true;
}
