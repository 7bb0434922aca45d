/* Point inversion (Newton with a coarse-grid start, NURBS Book §6.1) and curve projection. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_invert.h"
#include "prw_nurbs_make.h"

#define MAX_PROJ_POINTS 200000

/* A coarse parameter grid of surface points, evaluated once per surface and reused by every start
 * (a projected curve restarts from it for many points). */
typedef struct grid {
    int nu, nv;
    double u0, u1, v0, v1;
    prw_dvec3 *q; /* (nu + 1) x (nv + 1), row j = v */
} grid;

static void grid_build(const prw_nurbs_surface *s, grid *g)
{
    prw_nurbs_surface_domain(s, &g->u0, &g->u1, &g->v0, &g->v1);
    int nu = 2 * s->nu + 4, nv = 2 * s->nv + 4;
    if (nu > 64) nu = 64;
    if (nv > 64) nv = 64;
    g->nu = nu, g->nv = nv;
    g->q = prw_malloc(sizeof(prw_dvec3) * (size_t)(nu + 1) * (size_t)(nv + 1));
    for (int j = 0; j <= nv; j++)
        for (int i = 0; i <= nu; i++)
            g->q[j * (nu + 1) + i] = prw_nurbs_surface_eval(s, g->u0 + (g->u1 - g->u0) * i / nu, g->v0 + (g->v1 - g->v0) * j / nv);
}

/* Nearest point of the grid.  skip_degenerate: ignore grid points that coincide with a grid
 * neighbour (rows on a collapsed edge — a pole), where Newton cannot start. */
static void grid_start(const prw_nurbs_surface *s, grid *g, prw_dvec3 p, bool skip_degenerate, double scale, double *u,
                       double *v)
{
    if (!g->q) grid_build(s, g);
    int nu = g->nu, nv = g->nv;
    const prw_dvec3 *q = g->q;
    double best = INFINITY;
    *u = g->u0;
    *v = g->v0;
    for (int j = 0; j <= nv; j++)
        for (int i = 0; i <= nu; i++) {
            prw_dvec3 x = q[j * (nu + 1) + i];
            if (skip_degenerate) {
                bool deg = false;
                if (i > 0) deg = deg || prw_v3_len(prw_v3_sub(x, q[j * (nu + 1) + i - 1])) <= 1e-12 * scale;
                if (i < nu) deg = deg || prw_v3_len(prw_v3_sub(x, q[j * (nu + 1) + i + 1])) <= 1e-12 * scale;
                if (j > 0) deg = deg || prw_v3_len(prw_v3_sub(x, q[(j - 1) * (nu + 1) + i])) <= 1e-12 * scale;
                if (j < nv) deg = deg || prw_v3_len(prw_v3_sub(x, q[(j + 1) * (nu + 1) + i])) <= 1e-12 * scale;
                if (deg) continue;
            }
            double d = prw_v3_len(prw_v3_sub(x, p));
            if (d < best) {
                best = d;
                *u = g->u0 + (g->u1 - g->u0) * i / nu;
                *v = g->v0 + (g->v1 - g->v0) * j / nv;
            }
        }
}

/* Damped Newton from (*u, *v); returns the distance; *degenerate: it stopped where S_u or S_v
 * vanishes (a pole) without reaching the point. */
static double newton(const prw_nurbs_surface *s, prw_dvec3 p, double scale, double *u, double *v, bool *degenerate)
{
    double u0, u1, v0, v1;
    prw_nurbs_surface_domain(s, &u0, &u1, &v0, &v1);
    double uu = fmin(fmax(*u, u0), u1), vv = fmin(fmax(*v, v0), v1);
    *degenerate = false;
    for (int it = 0; it < 50; it++) {
        prw_dvec3 d[9];
        prw_nurbs_surface_derivs(s, uu, vv, 2, d);
        prw_dvec3 r = prw_v3_sub(d[0], p), su = d[3], sv = d[1];
        prw_dvec3 suu = d[6], suv = d[4], svv = d[2];
        double rl = prw_v3_len(r), sul = prw_v3_len(su), svl = prw_v3_len(sv);
        if (rl <= 1e-12 * scale) {
            *degenerate = false;
            break;
        }
        double f = prw_v3_dot(su, r), g = prw_v3_dot(sv, r);
        *degenerate = sul <= 1e-8 * scale / (u1 - u0) || svl <= 1e-8 * scale / (v1 - v0);
        if ((sul == 0 || fabs(f) <= 1e-10 * sul * rl) && (svl == 0 || fabs(g) <= 1e-10 * svl * rl)) break;
        double a = sul * sul + prw_v3_dot(r, suu), b = prw_v3_dot(su, sv) + prw_v3_dot(r, suv);
        double c = svl * svl + prw_v3_dot(r, svv);
        double det = a * c - b * b;
        double du, dv;
        if (fabs(det) > 1e-14 * fabs(a * c) && isfinite(det) && det != 0) {
            du = (-f * c + g * b) / det;
            dv = (-g * a + f * b) / det;
        } else { /* singular Jacobian (collapsed edge): steepest descent step */
            du = sul > 0 ? -f / (sul * sul) : 0;
            dv = svl > 0 ? -g / (svl * svl) : 0;
        }
        if (!isfinite(du) || !isfinite(dv)) break;
        double nu = fmin(fmax(uu + du, u0), u1), nv = fmin(fmax(vv + dv, v0), v1);
        double step = fabs(nu - uu) / (u1 - u0) + fabs(nv - vv) / (v1 - v0);
        /* accept only steps that do not increase the distance (halve otherwise) */
        double dist_new = prw_v3_len(prw_v3_sub(prw_nurbs_surface_eval(s, nu, nv), p));
        for (int h = 0; h < 20 && dist_new > rl; h++) {
            nu = 0.5 * (nu + uu);
            nv = 0.5 * (nv + vv);
            dist_new = prw_v3_len(prw_v3_sub(prw_nurbs_surface_eval(s, nu, nv), p));
        }
        if (dist_new > rl) break;
        uu = nu;
        vv = nv;
        if (step <= 1e-15) break;
    }
    *u = uu;
    *v = vv;
    return prw_v3_len(prw_v3_sub(prw_nurbs_surface_eval(s, uu, vv), p));
}

static double invert(const prw_nurbs_surface *s, grid *g, double scale, prw_dvec3 p, bool use_start, double *u,
                     double *v)
{
    if (!use_start || !isfinite(*u) || !isfinite(*v)) grid_start(s, g, p, false, scale, u, v);
    bool degenerate;
    double d = newton(s, p, scale, u, v, &degenerate);
    if (degenerate && d > 1e-12 * scale) {
        /* stuck on a pole (no derivative there to leave it by): once more from the nearest grid
         * point off the collapsed rows, keeping the nearer answer */
        double u2, v2;
        grid_start(s, g, p, true, scale, &u2, &v2);
        double d2 = newton(s, p, scale, &u2, &v2, &degenerate);
        if (d2 < d) d = d2, *u = u2, *v = v2;
    }
    return d;
}

/* The distance scale of the stopping tests: the control hull's diagonal + |p|. */
static double surface_diag(const prw_nurbs_surface *s)
{
    prw_dvec3 lo, hi;
    prw_nurbs_surface_bounds(s, &lo, &hi);
    return prw_v3_len(prw_v3_sub(hi, lo));
}

double prw_nurbs_surface_invert(const prw_nurbs_surface *s, prw_dvec3 p, bool use_start, double *u, double *v)
{
    grid g = {0};
    double d = invert(s, &g, surface_diag(s) + prw_v3_len(p), p, use_start, u, v);
    free(g.q);
    return d;
}

typedef struct plist {
    prw_dvec3 *p;
    int n, cap, max;
} plist;

static bool push3(plist *l, prw_dvec3 p, prw_error *e)
{
    if (l->n >= l->max) return prw_fail(e, "curve projection: more than %d points", l->max);
    if (l->n == l->cap) {
        l->cap = l->cap ? 2 * l->cap : 64;
        l->p = prw_realloc(l->p, sizeof(prw_dvec3) * (size_t)l->cap);
    }
    l->p[l->n++] = p;
    return true;
}

static bool flatten3(const prw_nurbs_curve *c, double a, double b, prw_dvec3 pa, prw_dvec3 pb, double tol, int depth,
                     plist *l, prw_error *e)
{
    double m = 0.5 * (a + b);
    prw_dvec3 pm = prw_nurbs_curve_eval(c, m);
    prw_dvec3 ch = prw_v3_sub(pb, pa), w = prw_v3_sub(pm, pa);
    double cl = prw_v3_len(ch);
    double dev = cl > 0 ? prw_v3_len(prw_v3_cross(ch, w)) / cl : prw_v3_len(w);
    if (dev > tol && depth < 20)
        return flatten3(c, a, m, pa, pm, tol, depth + 1, l, e) && flatten3(c, m, b, pm, pb, tol, depth + 1, l, e);
    return push3(l, pb, e);
}

bool prw_nurbs_surface_project_curve(const prw_nurbs_surface *s, const prw_nurbs_curve *c, double tol, int max_points,
                                     prw_nurbs_curve *uv, double *max_dist, prw_error *e)
{
    plist l = {.max = max_points > 0 && max_points < MAX_PROJ_POINTS ? max_points : MAX_PROJ_POINTS};
    double t0, t1;
    prw_nurbs_curve_domain(c, &t0, &t1);
    prw_dvec3 prev = prw_nurbs_curve_eval(c, t0);
    bool ok = push3(&l, prev, e);
    double a = t0;
    int p = c->degree;
    for (int k = p + 1; k <= c->n && ok; k++) {
        double b = k == c->n ? t1 : fmin(c->knots[k], t1);
        if (!(b > a)) continue;
        int pieces = 2 * p; /* start with a few pieces per span so the midpoint test sees the shape */
        for (int q = 0; q < pieces && ok; q++) {
            double aa = a + (b - a) * q / pieces, bb = q == pieces - 1 ? b : a + (b - a) * (q + 1) / pieces;
            prw_dvec3 pb = prw_nurbs_curve_eval(c, bb);
            ok = flatten3(c, aa, bb, prev, pb, tol, 0, &l, e);
            prev = pb;
        }
        a = b;
    }
    if (!ok) {
        free(l.p);
        return false;
    }
    prw_dvec3 *q = prw_malloc(sizeof(prw_dvec3) * (size_t)l.n);
    int n = 0;
    double u = NAN, v = NAN, md = 0;
    prw_dvec3 lo, hi;
    prw_nurbs_surface_bounds(s, &lo, &hi);
    double restart = 1e-9 * prw_v3_len(prw_v3_sub(hi, lo));
    grid g = {0};
    double diag = surface_diag(s);
    for (int i = 0; i < l.n; i++) {
        double uc = u, vc = v, scale = diag + prw_v3_len(l.p[i]);
        double d = invert(s, &g, scale, l.p[i], i > 0, &uc, &vc);
        if (i > 0 && d > restart) {
            double ug = 0, vg = 0;
            double dg = invert(s, &g, scale, l.p[i], false, &ug, &vg);
            if (dg < d) d = dg, uc = ug, vc = vg;
        }
        md = fmax(md, d);
        u = uc;
        v = vc;
        if (n > 0 && q[n - 1].x == u && q[n - 1].y == v) continue;
        q[n++] = prw_v3(u, v, 0);
    }
    free(l.p);
    free(g.q);
    if (n < 2) {
        free(q);
        return prw_fail(e, "curve projection: the curve maps to a single (u, v) point");
    }
    ok = prw_nurbs_make_polyline(uv, 2, q, n, e);
    free(q);
    *max_dist = md;
    return ok;
}
