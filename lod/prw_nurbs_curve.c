/* Rational B-spline curves: storage, validation, evaluation (A4.1), derivatives (A3.2 on the
 * homogeneous net + A4.2), bounds and affine maps. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_nurbs.h"

static const double binom3[3][3] = {{1, 0, 0}, {1, 1, 0}, {1, 2, 1}};

bool prw_nurbs_curve_alloc(prw_nurbs_curve *c, int dim, int degree, int n, prw_error *e)
{
    memset(c, 0, sizeof *c);
    if (dim != 2 && dim != 3) return prw_fail(e, "curve: dimension %d is not 2 or 3", dim);
    if (degree < 1 || degree > PRW_NURBS_MAX_DEGREE)
        return prw_fail(e, "curve: degree %d outside 1..%d", degree, PRW_NURBS_MAX_DEGREE);
    if (n < degree + 1 || n > PRW_NURBS_MAX_CTRL)
        return prw_fail(e, "curve: %d control points for degree %d (need %d..%d)", n, degree, degree + 1,
                        PRW_NURBS_MAX_CTRL);
    c->dim = dim;
    c->degree = degree;
    c->n = n;
    c->knots = prw_calloc((size_t)(n + degree + 1), sizeof(double));
    c->pw = prw_calloc((size_t)n * 4, sizeof(double));
    return true;
}

void prw_nurbs_curve_free(prw_nurbs_curve *c)
{
    if (!c) return;
    free(c->knots);
    free(c->pw);
    memset(c, 0, sizeof *c);
}

bool prw_nurbs_curve_copy(prw_nurbs_curve *dst, const prw_nurbs_curve *src, prw_error *e)
{
    if (!prw_nurbs_curve_alloc(dst, src->dim, src->degree, src->n, e)) return false;
    memcpy(dst->knots, src->knots, sizeof(double) * (size_t)(src->n + src->degree + 1));
    memcpy(dst->pw, src->pw, sizeof(double) * 4 * (size_t)src->n);
    return true;
}

bool prw_nurbs_curve_validate(const prw_nurbs_curve *c, prw_error *e)
{
    if (c->dim != 2 && c->dim != 3) return prw_fail(e, "curve: dimension %d is not 2 or 3", c->dim);
    if (!prw_knots_validate(c->knots, c->n, c->degree, "curve knots", e)) return false;
    for (int i = 0; i < c->n; i++) {
        const double *q = c->pw + 4 * i;
        if (!(isfinite(q[3]) && q[3] > 0)) return prw_fail(e, "curve: weight %d (%g) is not positive", i, q[3]);
        for (int k = 0; k < 3; k++)
            if (!isfinite(q[k]) || !isfinite(q[k] / q[3]))
                return prw_fail(e, "curve: control point %d is not finite", i);
    }
    return true;
}

void prw_nurbs_curve_set(prw_nurbs_curve *c, int i, prw_dvec3 p, double w)
{
    double *q = c->pw + 4 * i;
    q[0] = p.x * w;
    q[1] = p.y * w;
    q[2] = c->dim == 2 ? 0.0 : p.z * w;
    q[3] = w;
}

prw_dvec3 prw_nurbs_curve_point_at(const prw_nurbs_curve *c, int i)
{
    const double *q = c->pw + 4 * i;
    return prw_v3(q[0] / q[3], q[1] / q[3], q[2] / q[3]);
}

void prw_nurbs_curve_domain(const prw_nurbs_curve *c, double *t0, double *t1)
{
    *t0 = c->knots[c->degree];
    *t1 = c->knots[c->n];
}

static double clamp_param(double t, double a, double b)
{
    if (!(t >= a)) return a; /* NaN -> a */
    return t > b ? b : t;
}

prw_dvec3 prw_nurbs_curve_eval(const prw_nurbs_curve *c, double t)
{
    /* A4.1: homogeneous point Cw(t) = Σ N_{i,p}(t) Pw_i, then project. */
    double N[PRW_NURBS_MAX_DEGREE + 1];
    int p = c->degree;
    t = clamp_param(t, c->knots[p], c->knots[c->n]);
    int k = prw_knots_find_span(c->knots, c->n, p, t);
    prw_knots_basis(c->knots, p, k, t, N);
    double cw[4] = {0, 0, 0, 0};
    for (int j = 0; j <= p; j++) {
        const double *q = c->pw + 4 * (k - p + j);
        for (int d = 0; d < 4; d++) cw[d] += N[j] * q[d];
    }
    return prw_v3(cw[0] / cw[3], cw[1] / cw[3], cw[2] / cw[3]);
}

void prw_nurbs_curve_derivs(const prw_nurbs_curve *c, double t, int nd, prw_dvec3 *d)
{
    enum { W = PRW_NURBS_MAX_DEGREE + 1 };
    double ders[(PRW_NURBS_MAX_DERIV + 1) * W];
    double aw[PRW_NURBS_MAX_DERIV + 1][4];
    int p = c->degree;
    if (nd > PRW_NURBS_MAX_DERIV) nd = PRW_NURBS_MAX_DERIV;
    t = clamp_param(t, c->knots[p], c->knots[c->n]);
    int k = prw_knots_find_span(c->knots, c->n, p, t);
    prw_knots_basis_ders(c->knots, p, k, t, nd, ders);
    /* A3.2 on the homogeneous net: Cw^(m)(t) = Σ N^(m)_{i,p}(t) Pw_i. */
    for (int m = 0; m <= nd; m++) {
        for (int q = 0; q < 4; q++) aw[m][q] = 0;
        for (int j = 0; j <= p; j++) {
            const double *pt = c->pw + 4 * (k - p + j);
            for (int q = 0; q < 4; q++) aw[m][q] += ders[m * (p + 1) + j] * pt[q];
        }
    }
    /* A4.2: C^(m) = (A^(m) - Σ_{i=1..m} binom(m,i) w^(i) C^(m-i)) / w. */
    for (int m = 0; m <= nd; m++) {
        double v[3] = {aw[m][0], aw[m][1], aw[m][2]};
        for (int i = 1; i <= m; i++) {
            double f = binom3[m][i] * aw[i][3];
            v[0] -= f * d[m - i].x;
            v[1] -= f * d[m - i].y;
            v[2] -= f * d[m - i].z;
        }
        d[m] = prw_v3(v[0] / aw[0][3], v[1] / aw[0][3], v[2] / aw[0][3]);
    }
}

void prw_nurbs_curve_bounds(const prw_nurbs_curve *c, prw_dvec3 *lo, prw_dvec3 *hi)
{
    *lo = prw_v3(INFINITY, INFINITY, INFINITY);
    *hi = prw_v3(-INFINITY, -INFINITY, -INFINITY);
    for (int i = 0; i < c->n; i++) {
        prw_dvec3 q = prw_nurbs_curve_point_at(c, i);
        *lo = prw_v3_min(*lo, q);
        *hi = prw_v3_max(*hi, q);
    }
}

void prw_nurbs_curve_transform(prw_nurbs_curve *c, const prw_dmat4 *m)
{
    for (int i = 0; i < c->n; i++) {
        double w = c->pw[4 * i + 3];
        prw_dvec3 q = prw_dm4_point(*m, prw_nurbs_curve_point_at(c, i));
        prw_nurbs_curve_set(c, i, q, w);
    }
}
