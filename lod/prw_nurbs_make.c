/* Exact NURBS constructions: lines, polylines, circular arcs (NURBS Book A7.1), surfaces of
 * revolution (A8.1), ruled surfaces (§8.4), tabulated cylinders (§8.3), bilinear patches, and the
 * sphere / torus test primitives. */
#include <math.h>
#include <string.h>

#include "prw_nurbs_make.h"

bool prw_nurbs_make_line(prw_nurbs_curve *c, int dim, prw_dvec3 p0, prw_dvec3 p1, prw_error *e)
{
    if (!prw_nurbs_curve_alloc(c, dim, 1, 2, e)) return false;
    double U[4] = {0, 0, 1, 1};
    memcpy(c->knots, U, sizeof U);
    prw_nurbs_curve_set(c, 0, p0, 1);
    prw_nurbs_curve_set(c, 1, p1, 1);
    return true;
}

bool prw_nurbs_make_polyline(prw_nurbs_curve *c, int dim, const prw_dvec3 *pts, int n, prw_error *e)
{
    if (n < 2) return prw_fail(e, "polyline: %d points (need 2)", n);
    if (!prw_nurbs_curve_alloc(c, dim, 1, n, e)) return false;
    c->knots[0] = 0;
    for (int i = 0; i < n; i++) {
        c->knots[i + 1] = i;
        prw_nurbs_curve_set(c, i, pts[i], 1);
    }
    c->knots[n + 1] = n - 1;
    return true;
}

/* A7.1 layout: number of arcs, the knot vector on [0, 1] (2·narcs + 4 knots). */
static int arc_layout(double ths, double the, double *U)
{
    double theta = the - ths;
    int narcs = theta <= 0.5 * PRW_PI + 1e-12 ? 1 : theta <= PRW_PI + 1e-12 ? 2 : theta <= 1.5 * PRW_PI + 1e-12 ? 3 : 4;
    int n = 2 * narcs + 1; /* control points */
    for (int i = 0; i < 3; i++) {
        U[i] = 0;
        U[n + i] = 1;
    }
    for (int a = 1; a < narcs; a++) U[2 * a + 1] = U[2 * a + 2] = (double)a / narcs;
    return narcs;
}

/* Cartesian control point k (0..2·narcs) of the unit arc, as (cos, sin) multiplier and weight. */
static void arc_point(double ths, double the, int narcs, int k, double *cs, double *sn, double *w)
{
    double dth = (the - ths) / narcs;
    if (k % 2 == 0) {
        double a = k == 2 * narcs ? the : ths + dth * (k / 2);
        *cs = cos(a);
        *sn = sin(a);
        *w = 1;
    } else {
        double mid = ths + dth * (k / 2) + 0.5 * dth;
        double h = cos(0.5 * dth);
        *cs = cos(mid) / h; /* the tangent lines meet at r / cos(Δθ/2) on the bisector */
        *sn = sin(mid) / h;
        *w = h;
    }
}

static bool check_angles(double ths, double the, prw_error *e)
{
    if (!isfinite(ths) || !isfinite(the) || !(the > ths) || the - ths > 2 * PRW_PI * (1 + 1e-12))
        return prw_fail(e, "arc: angles %g..%g do not span (0, 2π]", ths, the);
    return true;
}

bool prw_nurbs_make_arc(prw_nurbs_curve *c, int dim, prw_dvec3 o, prw_dvec3 x, prw_dvec3 y, double r, double ths,
                        double the, prw_error *e)
{
    if (!check_angles(ths, the, e)) return false;
    if (!(r > 0) || !isfinite(r)) return prw_fail(e, "arc: radius %g is not positive", r);
    double U[12];
    int narcs = arc_layout(ths, the, U);
    int n = 2 * narcs + 1;
    if (!prw_nurbs_curve_alloc(c, dim, 2, n, e)) return false;
    memcpy(c->knots, U, sizeof(double) * (size_t)(n + 3));
    for (int k = 0; k < n; k++) {
        double cs, sn, w;
        arc_point(ths, the, narcs, k, &cs, &sn, &w);
        prw_dvec3 p = prw_v3_add(o, prw_v3_add(prw_v3_scale(x, r * cs), prw_v3_scale(y, r * sn)));
        prw_nurbs_curve_set(c, k, p, w);
    }
    return true;
}

bool prw_nurbs_make_revolution(prw_nurbs_surface *out, const prw_nurbs_curve *g, prw_dvec3 s, prw_dvec3 t,
                               double theta0, double theta1, prw_error *e)
{
    if (!check_angles(theta0, theta1, e)) return false;
    double tl = prw_v3_len(t);
    if (!(tl > 0) || !isfinite(tl)) return prw_fail(e, "revolution: axis direction is zero");
    t = prw_v3_scale(t, 1 / tl);
    double V[12];
    int narcs = arc_layout(theta0, theta1, V);
    int nv = 2 * narcs + 1;
    if (!prw_nurbs_surface_alloc(out, g->degree, 2, g->n, nv, e)) return false;
    memcpy(out->knots_u, g->knots, sizeof(double) * (size_t)(g->n + g->degree + 1));
    memcpy(out->knots_v, V, sizeof(double) * (size_t)(nv + 3));
    for (int i = 0; i < g->n; i++) {
        prw_dvec3 p = prw_nurbs_curve_point_at(g, i);
        double wj = g->pw[4 * i + 3];
        prw_dvec3 o = prw_v3_add(s, prw_v3_scale(t, prw_v3_dot(prw_v3_sub(p, s), t)));
        prw_dvec3 x = prw_v3_sub(p, o);
        double r = prw_v3_len(x);
        prw_dvec3 y = prw_v3(0, 0, 0);
        if (r <= 1e-14 * prw_v3_len(prw_v3_sub(p, s))) r = 0; /* on the axis up to rounding */
        if (r > 0) {
            x = prw_v3_scale(x, 1 / r);
            y = prw_v3_cross(t, x);
        }
        for (int k = 0; k < nv; k++) {
            double cs, sn, w;
            arc_point(theta0, theta1, narcs, k, &cs, &sn, &w);
            /* a point on the axis stays there: the pole of a collapsed edge */
            prw_dvec3 q = r > 0 ? prw_v3_add(o, prw_v3_add(prw_v3_scale(x, r * cs), prw_v3_scale(y, r * sn))) : p;
            prw_nurbs_surface_set(out, i, k, q, w * wj);
        }
    }
    return prw_nurbs_surface_validate(out, e) || (prw_nurbs_surface_free(out), false);
}

bool prw_nurbs_make_ruled(prw_nurbs_surface *out, const prw_nurbs_curve *a, const prw_nurbs_curve *b, prw_error *e)
{
    prw_nurbs_curve ca, cb;
    if (!prw_nurbs_curve_copy(&ca, a, e)) return false;
    if (!prw_nurbs_curve_copy(&cb, b, e)) {
        prw_nurbs_curve_free(&ca);
        return false;
    }
    bool ok = prw_nurbs_curves_make_compatible(&ca, &cb, e) &&
              prw_nurbs_surface_alloc(out, ca.degree, 1, ca.n, 2, e);
    if (ok) {
        memcpy(out->knots_u, ca.knots, sizeof(double) * (size_t)(ca.n + ca.degree + 1));
        double V[4] = {0, 0, 1, 1};
        memcpy(out->knots_v, V, sizeof V);
        for (int i = 0; i < ca.n; i++) {
            memcpy(out->pw + 4 * i, ca.pw + 4 * i, 4 * sizeof(double));
            memcpy(out->pw + 4 * (ca.n + i), cb.pw + 4 * i, 4 * sizeof(double));
            if (ca.dim == 2) out->pw[4 * i + 2] = 0;
        }
        ok = prw_nurbs_surface_validate(out, e) || (prw_nurbs_surface_free(out), false);
    }
    prw_nurbs_curve_free(&ca);
    prw_nurbs_curve_free(&cb);
    return ok;
}

bool prw_nurbs_make_extrusion(prw_nurbs_surface *out, const prw_nurbs_curve *c, prw_dvec3 d, prw_error *e)
{
    if (!prw_nurbs_surface_alloc(out, c->degree, 1, c->n, 2, e)) return false;
    memcpy(out->knots_u, c->knots, sizeof(double) * (size_t)(c->n + c->degree + 1));
    double V[4] = {0, 0, 1, 1};
    memcpy(out->knots_v, V, sizeof V);
    for (int i = 0; i < c->n; i++) {
        prw_dvec3 p = prw_nurbs_curve_point_at(c, i);
        double w = c->pw[4 * i + 3];
        prw_nurbs_surface_set(out, i, 0, p, w);
        prw_nurbs_surface_set(out, i, 1, prw_v3_add(p, d), w);
    }
    return prw_nurbs_surface_validate(out, e) || (prw_nurbs_surface_free(out), false);
}

bool prw_nurbs_make_bilinear(prw_nurbs_surface *out, prw_dvec3 p00, prw_dvec3 p10, prw_dvec3 p01, prw_dvec3 p11,
                             prw_error *e)
{
    if (!prw_nurbs_surface_alloc(out, 1, 1, 2, 2, e)) return false;
    double U[4] = {0, 0, 1, 1};
    memcpy(out->knots_u, U, sizeof U);
    memcpy(out->knots_v, U, sizeof U);
    prw_nurbs_surface_set(out, 0, 0, p00, 1);
    prw_nurbs_surface_set(out, 1, 0, p10, 1);
    prw_nurbs_surface_set(out, 0, 1, p01, 1);
    prw_nurbs_surface_set(out, 1, 1, p11, 1);
    return prw_nurbs_surface_validate(out, e) || (prw_nurbs_surface_free(out), false);
}

bool prw_nurbs_make_sphere(prw_nurbs_surface *out, prw_dvec3 centre, double r, prw_error *e)
{
    prw_nurbs_curve g;
    if (!prw_nurbs_make_arc(&g, 3, centre, prw_v3(1, 0, 0), prw_v3(0, 0, -1), r, -0.5 * PRW_PI, 0.5 * PRW_PI, e))
        return false;
    bool ok = prw_nurbs_make_revolution(out, &g, centre, prw_v3(0, 0, 1), 0, 2 * PRW_PI, e);
    prw_nurbs_curve_free(&g);
    return ok;
}

bool prw_nurbs_make_torus(prw_nurbs_surface *out, prw_dvec3 centre, double R, double r, prw_error *e)
{
    prw_nurbs_curve g;
    if (!(R > r)) return prw_fail(e, "torus: major radius %g must exceed minor radius %g", R, r);
    if (!prw_nurbs_make_arc(&g, 3, prw_v3_add(centre, prw_v3(R, 0, 0)), prw_v3(1, 0, 0), prw_v3(0, 0, -1), r, 0,
                            2 * PRW_PI, e))
        return false;
    bool ok = prw_nurbs_make_revolution(out, &g, centre, prw_v3(0, 0, 1), 0, 2 * PRW_PI, e);
    prw_nurbs_curve_free(&g);
    return ok;
}
