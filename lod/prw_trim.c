/* Trim loops: adaptive flattening and the even-odd inside test with exact orientation. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_predicates.h"
#include "prw_trim.h"

#define MAX_FLAT_POINTS 4000000
#define MAX_DEPTH 24

static void push(double **pts, int *n, int *cap, double u, double v)
{
    if (*n == *cap) {
        *cap = *cap ? 2 * *cap : 64;
        *pts = prw_realloc(*pts, sizeof(double) * 2 * (size_t)*cap);
    }
    (*pts)[2 * *n] = u;
    (*pts)[2 * *n + 1] = v;
    (*n)++;
}

static double dist_to_chord(prw_dvec3 a, prw_dvec3 b, prw_dvec3 p)
{
    double dx = b.x - a.x, dy = b.y - a.y;
    double l2 = dx * dx + dy * dy;
    double px = p.x - a.x, py = p.y - a.y;
    if (!(l2 > 0)) return sqrt(px * px + py * py);
    return fabs(dx * py - dy * px) / sqrt(l2);
}

/* Appends points for (a, b], given C(a) = pa, C(b) = pb. */
static bool subdivide(const prw_nurbs_curve *c, double a, double b, prw_dvec3 pa, prw_dvec3 pb, double tol, int depth,
                      double **pts, int *n, int *cap, prw_error *e)
{
    if (*n > MAX_FLAT_POINTS) return prw_fail(e, "trim curve: more than %d points at tolerance %g", MAX_FLAT_POINTS, tol);
    double t1 = a + (b - a) / 3, t2 = a + 2 * (b - a) / 3;
    prw_dvec3 p1 = prw_nurbs_curve_eval(c, t1), p2 = prw_nurbs_curve_eval(c, t2);
    double d = fmax(dist_to_chord(pa, pb, p1), dist_to_chord(pa, pb, p2));
    if (d > tol && depth < MAX_DEPTH) {
        double m = 0.5 * (a + b);
        prw_dvec3 pm = prw_nurbs_curve_eval(c, m);
        return subdivide(c, a, m, pa, pm, tol, depth + 1, pts, n, cap, e) &&
               subdivide(c, m, b, pm, pb, tol, depth + 1, pts, n, cap, e);
    }
    push(pts, n, cap, pb.x, pb.y);
    return true;
}

bool prw_trim_flatten_curve(const prw_nurbs_curve *c, double tol, double **pts, int *n, int *cap, prw_error *e)
{
    if (!(tol > 0)) return prw_fail(e, "trim curve: tolerance %g is not positive", tol);
    int p = c->degree;
    double t0, t1;
    prw_nurbs_curve_domain(c, &t0, &t1);
    prw_dvec3 prev = prw_nurbs_curve_eval(c, t0);
    push(pts, n, cap, prev.x, prev.y);
    double a = t0;
    for (int k = p + 1; k <= c->n; k++) {
        double b = k == c->n ? t1 : c->knots[k];
        if (!(b > a)) continue;
        if (b > t1) b = t1;
        if (p == 1) {
            prw_dvec3 pb = prw_nurbs_curve_eval(c, b);
            push(pts, n, cap, pb.x, pb.y);
            prev = pb;
        } else {
            /* at least `degree` pieces per span before the adaptive test */
            for (int s = 0; s < p; s++) {
                double aa = a + (b - a) * s / p, bb = s == p - 1 ? b : a + (b - a) * (s + 1) / p;
                prw_dvec3 pb = prw_nurbs_curve_eval(c, bb);
                if (!subdivide(c, aa, bb, prev, pb, tol, 0, pts, n, cap, e)) return false;
                prev = pb;
            }
        }
        a = b;
        if (a >= t1) break;
    }
    return true;
}

double prw_trim_polygon_area(const prw_trim_polygon *p)
{
    if (p->n < 3) return 0;
    double ox = p->uv[0], oy = p->uv[1], s = 0;
    for (int i = 1; i + 1 < p->n; i++) {
        double ax = p->uv[2 * i] - ox, ay = p->uv[2 * i + 1] - oy;
        double bx = p->uv[2 * i + 2] - ox, by = p->uv[2 * i + 3] - oy;
        s += ax * by - ay * bx;
    }
    return 0.5 * s;
}

static bool near_pt(const double *a, const double *b, double snap)
{
    return fabs(a[0] - b[0]) <= snap && fabs(a[1] - b[1]) <= snap;
}

/* Where consecutive trim curves do not meet exactly, their flattened ends can overshoot each
 * other and cross (a bow-tie of 1e-16 .. 1e-3 of the domain at a corner): edge i and a later edge j
 * that cross, with a short path (<= maxlen, <= a tenth of the perimeter, < WINDOW vertices) from
 * the end of i to the start of j, become one corner at their intersection; the little loop between
 * them is dropped.  Returns the new point count. */
#define CUT_WINDOW 256
static int cut_junction_crossings(double *pts, int m, double maxlen)
{
    double perim = 0;
    for (int i = 0; i < m; i++) {
        const double *a = pts + 2 * i, *b = pts + 2 * ((i + 1) % m);
        perim += hypot(b[0] - a[0], b[1] - a[1]);
    }
    maxlen = fmin(maxlen, 0.1 * perim);
    for (int i = 0; i < m && m > 3; i++) {
        const double *a = pts + 2 * i, *b = pts + 2 * ((i + 1) % m);
        double len = 0;
        for (int step = 2; step < m - 1 && step <= CUT_WINDOW; step++) {
            int j = (i + step) % m, jn = (j + 1) % m;
            const double *c = pts + 2 * j, *d = pts + 2 * jn, *cp = pts + 2 * ((j + m - 1) % m);
            len += hypot(c[0] - cp[0], c[1] - cp[1]);
            if (len > maxlen) break;
            int o1 = prw_orient2d(a, b, c), o2 = prw_orient2d(a, b, d), o3 = prw_orient2d(c, d, a), o4 = prw_orient2d(c, d, b);
            if (o1 * o2 > 0 || o3 * o4 > 0 || (o1 == 0 && o2 == 0)) continue; /* apart, or collinear */
            double d1 = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
            double d2 = (b[0] - a[0]) * (d[1] - a[1]) - (b[1] - a[1]) * (d[0] - a[0]);
            double t = d1 == d2 ? 0 : d1 / (d1 - d2);
            t = fmin(fmax(t, 0), 1);
            double x[2] = {c[0] + t * (d[0] - c[0]), c[1] + t * (d[1] - c[1])};
            /* drop the points i+1 .. j (cyclically), x after i; each cut removes at least one point */
            if (i + step < m) { /* in place: 0 .. i, x, j+1 .. m-1; then edge i again */
                pts[2 * (i + 1)] = x[0], pts[2 * (i + 1) + 1] = x[1];
                memmove(pts + 2 * (i + 2), pts + 2 * (j + 1), sizeof(double) * 2 * (size_t)(m - j - 1));
                m -= step - 1;
                i--;
            } else { /* the path wraps past the end: jn .. i, x (rotated), and start again */
                int keep = 0;
                double *tmp = prw_malloc(sizeof(double) * 2 * (size_t)m);
                for (int k = 0; k < m - step; k++) {
                    int src = (jn + k) % m;
                    tmp[2 * keep] = pts[2 * src], tmp[2 * keep + 1] = pts[2 * src + 1], keep++;
                }
                tmp[2 * keep] = x[0], tmp[2 * keep + 1] = x[1], keep++;
                memcpy(pts, tmp, sizeof(double) * 2 * (size_t)keep);
                free(tmp);
                m = keep;
                i = -1;
            }
            break;
        }
    }
    return m;
}

static bool finish_loop(prw_trim_region *r, double *pts, int n, double snap)
{
    /* clamp, merge consecutive points within `snap` (the ends of curves that should meet) and the
     * closing duplicate */
    int m = 0;
    for (int i = 0; i < n; i++) {
        double uv[2] = {fmin(fmax(pts[2 * i], r->u0), r->u1), fmin(fmax(pts[2 * i + 1], r->v0), r->v1)};
        if (m > 0 && near_pt(pts + 2 * (m - 1), uv, snap)) continue;
        pts[2 * m] = uv[0];
        pts[2 * m + 1] = uv[1];
        m++;
    }
    while (m > 1 && near_pt(pts, pts + 2 * (m - 1), snap)) m--;
    if (m > 3) {
        double side = fmax(r->u1 - r->u0, r->v1 - r->v0);
        m = cut_junction_crossings(pts, m, 1e-2 * side);
    }
    prw_trim_polygon poly = {pts, m};
    bool degenerate = m < 3;
    if (!degenerate) {
        /* zero area exactly: every point collinear with the first two distinct ones */
        degenerate = true;
        for (int i = 2; i < m && degenerate; i++) degenerate = prw_orient2d(pts, pts + 2, pts + 2 * i) == 0;
    }
    if (degenerate) {
        free(pts);
        r->dropped++;
        return false;
    }
    r->loops = prw_realloc(r->loops, sizeof *r->loops * (size_t)(r->count + 1));
    r->loops[r->count++] = poly;
    return true;
}

bool prw_trim_region_build(const prw_trimmed_surface *t, double tol, prw_trim_region *r, prw_error *e)
{
    memset(r, 0, sizeof *r);
    prw_nurbs_surface_domain(&t->surface, &r->u0, &r->u1, &r->v0, &r->v1);
    if (t->natural_outer) {
        double *p = prw_malloc(sizeof(double) * 8);
        double q[8] = {r->u0, r->v0, r->u1, r->v0, r->u1, r->v1, r->u0, r->v1};
        memcpy(p, q, sizeof q);
        finish_loop(r, p, 4, 0);
    }
    for (int l = 0; l < t->nloops; l++) {
        double *pts = NULL;
        int n = 0, cap = 0;
        for (int s = 0; s < t->loops[l].count; s++) {
            if (!prw_trim_flatten_curve(&t->loops[l].segs[s].uv, tol, &pts, &n, &cap, e)) {
                free(pts);
                prw_trim_region_free(r);
                return prw_fail_wrap(e, "loop %d segment %d", l, s);
            }
        }
        finish_loop(r, pts, n, 1e-3 * tol);
    }
    return true;
}

void prw_trim_region_free(prw_trim_region *r)
{
    for (int i = 0; i < r->count; i++) free(r->loops[i].uv);
    free(r->loops);
    memset(r, 0, sizeof *r);
}

/* Crossing parity of one polygon for the ray from p toward +u; sets *on when p lies on an edge. */
static int crossings(const prw_trim_polygon *poly, const double *p, bool *on)
{
    int c = 0;
    for (int i = 0, j = poly->n - 1; i < poly->n; j = i++) {
        const double *a = poly->uv + 2 * j, *b = poly->uv + 2 * i;
        bool a_above = a[1] > p[1], b_above = b[1] > p[1];
        /* on-edge: collinear and inside the closed bounding box */
        if (p[0] >= fmin(a[0], b[0]) && p[0] <= fmax(a[0], b[0]) && p[1] >= fmin(a[1], b[1]) &&
            p[1] <= fmax(a[1], b[1]) && prw_orient2d(a, b, p) == 0) {
            *on = true;
            return 0;
        }
        if (a_above == b_above) continue;
        /* the edge straddles the horizontal line; p is left of it (crossing to the right) when
         * orient(lower, upper, p) > 0 */
        const double *lo = a_above ? b : a, *hi = a_above ? a : b;
        if (prw_orient2d(lo, hi, p) > 0) c ^= 1;
    }
    return c;
}

prw_trim_class prw_trim_classify(const prw_trim_region *r, double u, double v)
{
    double p[2] = {u, v};
    int parity = 0;
    for (int l = 0; l < r->count; l++) {
        bool on = false;
        parity ^= crossings(&r->loops[l], p, &on);
        if (on) return PRW_TRIM_ON;
    }
    return parity ? PRW_TRIM_INSIDE : PRW_TRIM_OUTSIDE;
}

static double seg_dist2(const double *a, const double *b, const double *p)
{
    double dx = b[0] - a[0], dy = b[1] - a[1];
    double l2 = dx * dx + dy * dy;
    double t = l2 > 0 ? ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2 : 0;
    t = fmin(fmax(t, 0), 1);
    double ex = a[0] + t * dx - p[0], ey = a[1] + t * dy - p[1];
    return ex * ex + ey * ey;
}

bool prw_trim_inside(const prw_trim_region *r, double u, double v, double tol)
{
    if (prw_trim_classify(r, u, v) != PRW_TRIM_OUTSIDE) return true;
    if (!(tol > 0)) return false;
    double p[2] = {u, v}, t2 = tol * tol;
    for (int l = 0; l < r->count; l++) {
        const prw_trim_polygon *poly = &r->loops[l];
        for (int i = 0, j = poly->n - 1; i < poly->n; j = i++)
            if (seg_dist2(poly->uv + 2 * j, poly->uv + 2 * i, p) <= t2) return true;
    }
    return false;
}

double prw_trim_region_area(const prw_trim_region *r)
{
    double total = 0;
    for (int l = 0; l < r->count; l++) {
        /* depth = number of other loops containing this loop (tested at an edge midpoint and the
         * vertices until one is not ON another loop) */
        const prw_trim_polygon *pl = &r->loops[l];
        int depth = 0;
        for (int k = 0; k < r->count; k++) {
            if (k == l) continue;
            prw_trim_region one = {(prw_trim_polygon *)&r->loops[k], 1, 0, 0, 0, 0, 0};
            int verdict = -1;
            for (int i = 0; i < pl->n && verdict < 0; i++) {
                const double *a = pl->uv + 2 * i, *b = pl->uv + 2 * ((i + 1) % pl->n);
                double mids[2][2] = {{a[0], a[1]}, {0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])}};
                for (int m = 0; m < 2 && verdict < 0; m++) {
                    prw_trim_class c = prw_trim_classify(&one, mids[m][0], mids[m][1]);
                    if (c != PRW_TRIM_ON) verdict = c == PRW_TRIM_INSIDE;
                }
            }
            depth += verdict > 0;
        }
        double a = fabs(prw_trim_polygon_area(pl));
        total += depth % 2 ? -a : a;
    }
    return total;
}
