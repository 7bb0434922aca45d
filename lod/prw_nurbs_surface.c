/* Rational B-spline surfaces: storage, validation, evaluation (A4.3), derivatives (A3.6 on the
 * homogeneous net + A4.4), normals with a defined value at degenerate points, bounds. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_nurbs.h"

static const double binom3[3][3] = {{1, 0, 0}, {1, 1, 0}, {1, 2, 1}};

bool prw_nurbs_surface_alloc(prw_nurbs_surface *s, int degree_u, int degree_v, int nu, int nv, prw_error *e)
{
    memset(s, 0, sizeof *s);
    if (degree_u < 1 || degree_u > PRW_NURBS_MAX_DEGREE || degree_v < 1 || degree_v > PRW_NURBS_MAX_DEGREE)
        return prw_fail(e, "surface: degrees %d x %d outside 1..%d", degree_u, degree_v, PRW_NURBS_MAX_DEGREE);
    if (nu < degree_u + 1 || nv < degree_v + 1 || nu > PRW_NURBS_MAX_CTRL || nv > PRW_NURBS_MAX_CTRL ||
        (double)nu * nv > PRW_NURBS_MAX_CTRL)
        return prw_fail(e, "surface: %d x %d control points for degrees %d x %d", nu, nv, degree_u, degree_v);
    s->degree_u = degree_u;
    s->degree_v = degree_v;
    s->nu = nu;
    s->nv = nv;
    s->knots_u = prw_calloc((size_t)(nu + degree_u + 1), sizeof(double));
    s->knots_v = prw_calloc((size_t)(nv + degree_v + 1), sizeof(double));
    s->pw = prw_calloc((size_t)nu * (size_t)nv * 4, sizeof(double));
    return true;
}

void prw_nurbs_surface_free(prw_nurbs_surface *s)
{
    if (!s) return;
    free(s->knots_u);
    free(s->knots_v);
    free(s->pw);
    memset(s, 0, sizeof *s);
}

bool prw_nurbs_surface_copy(prw_nurbs_surface *dst, const prw_nurbs_surface *src, prw_error *e)
{
    if (!prw_nurbs_surface_alloc(dst, src->degree_u, src->degree_v, src->nu, src->nv, e)) return false;
    memcpy(dst->knots_u, src->knots_u, sizeof(double) * (size_t)(src->nu + src->degree_u + 1));
    memcpy(dst->knots_v, src->knots_v, sizeof(double) * (size_t)(src->nv + src->degree_v + 1));
    memcpy(dst->pw, src->pw, sizeof(double) * 4 * (size_t)src->nu * (size_t)src->nv);
    return true;
}

bool prw_nurbs_surface_validate(const prw_nurbs_surface *s, prw_error *e)
{
    if (!prw_knots_validate(s->knots_u, s->nu, s->degree_u, "surface knots_u", e)) return false;
    if (!prw_knots_validate(s->knots_v, s->nv, s->degree_v, "surface knots_v", e)) return false;
    size_t n = (size_t)s->nu * (size_t)s->nv;
    for (size_t i = 0; i < n; i++) {
        const double *q = s->pw + 4 * i;
        if (!(isfinite(q[3]) && q[3] > 0))
            return prw_fail(e, "surface: weight (%d, %d) = %g is not positive", (int)(i % (size_t)s->nu),
                            (int)(i / (size_t)s->nu), q[3]);
        for (int k = 0; k < 3; k++)
            if (!isfinite(q[k]) || !isfinite(q[k] / q[3]))
                return prw_fail(e, "surface: control point (%d, %d) is not finite", (int)(i % (size_t)s->nu),
                                (int)(i / (size_t)s->nu));
    }
    return true;
}

void prw_nurbs_surface_set(prw_nurbs_surface *s, int i, int j, prw_dvec3 p, double w)
{
    double *q = s->pw + 4 * ((size_t)j * (size_t)s->nu + (size_t)i);
    q[0] = p.x * w;
    q[1] = p.y * w;
    q[2] = p.z * w;
    q[3] = w;
}

void prw_nurbs_surface_domain(const prw_nurbs_surface *s, double *u0, double *u1, double *v0, double *v1)
{
    *u0 = s->knots_u[s->degree_u];
    *u1 = s->knots_u[s->nu];
    *v0 = s->knots_v[s->degree_v];
    *v1 = s->knots_v[s->nv];
}

static double clamp_param(double t, double a, double b)
{
    if (!(t >= a)) return a;
    return t > b ? b : t;
}

prw_dvec3 prw_nurbs_surface_eval(const prw_nurbs_surface *s, double u, double v)
{
    /* A4.3: Sw(u,v) = Σ_l N_l(v) Σ_k N_k(u) Pw_{k,l}, then project. */
    double Nu[PRW_NURBS_MAX_DEGREE + 1], Nv[PRW_NURBS_MAX_DEGREE + 1];
    int p = s->degree_u, q = s->degree_v;
    u = clamp_param(u, s->knots_u[p], s->knots_u[s->nu]);
    v = clamp_param(v, s->knots_v[q], s->knots_v[s->nv]);
    int ku = prw_knots_find_span(s->knots_u, s->nu, p, u);
    int kv = prw_knots_find_span(s->knots_v, s->nv, q, v);
    prw_knots_basis(s->knots_u, p, ku, u, Nu);
    prw_knots_basis(s->knots_v, q, kv, v, Nv);
    double sw[4] = {0, 0, 0, 0};
    for (int l = 0; l <= q; l++) {
        double tmp[4] = {0, 0, 0, 0};
        const double *row = s->pw + 4 * ((size_t)(kv - q + l) * (size_t)s->nu + (size_t)(ku - p));
        for (int k = 0; k <= p; k++)
            for (int d = 0; d < 4; d++) tmp[d] += Nu[k] * row[4 * k + d];
        for (int d = 0; d < 4; d++) sw[d] += Nv[l] * tmp[d];
    }
    return prw_v3(sw[0] / sw[3], sw[1] / sw[3], sw[2] / sw[3]);
}

void prw_nurbs_surface_derivs(const prw_nurbs_surface *s, double u, double v, int nd, prw_dvec3 *skl)
{
    enum { W = PRW_NURBS_MAX_DEGREE + 1, D = PRW_NURBS_MAX_DERIV + 1 };
    double du[D * W], dv[D * W];
    double aw[D][D][4];
    int p = s->degree_u, q = s->degree_v;
    if (nd > PRW_NURBS_MAX_DERIV) nd = PRW_NURBS_MAX_DERIV;
    u = clamp_param(u, s->knots_u[p], s->knots_u[s->nu]);
    v = clamp_param(v, s->knots_v[q], s->knots_v[s->nv]);
    int ku = prw_knots_find_span(s->knots_u, s->nu, p, u);
    int kv = prw_knots_find_span(s->knots_v, s->nv, q, v);
    prw_knots_basis_ders(s->knots_u, p, ku, u, nd, du);
    prw_knots_basis_ders(s->knots_v, q, kv, v, nd, dv);
    /* A3.6 on the homogeneous net. */
    for (int k = 0; k <= nd; k++) {
        double tmp[W][4];
        for (int l = 0; l <= q; l++) {
            const double *row = s->pw + 4 * ((size_t)(kv - q + l) * (size_t)s->nu + (size_t)(ku - p));
            for (int d = 0; d < 4; d++) tmp[l][d] = 0;
            for (int r = 0; r <= p; r++)
                for (int d = 0; d < 4; d++) tmp[l][d] += du[k * (p + 1) + r] * row[4 * r + d];
        }
        for (int l = 0; l <= nd - k; l++) {
            for (int d = 0; d < 4; d++) aw[k][l][d] = 0;
            for (int ss = 0; ss <= q; ss++)
                for (int d = 0; d < 4; d++) aw[k][l][d] += dv[l * (q + 1) + ss] * tmp[ss][d];
        }
    }
    /* A4.4: the rational quotient rule in two variables. */
    prw_dvec3 out[D][D];
    double w = aw[0][0][3];
    for (int k = 0; k <= nd; k++)
        for (int l = 0; l <= nd - k; l++) {
            double vv[3] = {aw[k][l][0], aw[k][l][1], aw[k][l][2]};
            for (int j = 1; j <= l; j++) {
                double f = binom3[l][j] * aw[0][j][3];
                vv[0] -= f * out[k][l - j].x;
                vv[1] -= f * out[k][l - j].y;
                vv[2] -= f * out[k][l - j].z;
            }
            for (int i = 1; i <= k; i++) {
                double f = binom3[k][i] * aw[i][0][3];
                vv[0] -= f * out[k - i][l].x;
                vv[1] -= f * out[k - i][l].y;
                vv[2] -= f * out[k - i][l].z;
                double v2[3] = {0, 0, 0};
                for (int j = 1; j <= l; j++) {
                    double g = binom3[l][j] * aw[i][j][3];
                    v2[0] += g * out[k - i][l - j].x;
                    v2[1] += g * out[k - i][l - j].y;
                    v2[2] += g * out[k - i][l - j].z;
                }
                vv[0] -= binom3[k][i] * v2[0];
                vv[1] -= binom3[k][i] * v2[1];
                vv[2] -= binom3[k][i] * v2[2];
            }
            out[k][l] = prw_v3(vv[0] / w, vv[1] / w, vv[2] / w);
            skl[k * (nd + 1) + l] = out[k][l];
        }
}

static bool normal_ok(prw_dvec3 n, prw_dvec3 a, prw_dvec3 b)
{
    double la = prw_v3_len(a), lb = prw_v3_len(b);
    double ln = prw_v3_len(n);
    double ref = (la + lb) * (la + lb);
    return isfinite(ln) && ln > 0 && ln > 1e-10 * ref;
}

prw_dvec3 prw_nurbs_surface_normal(const prw_nurbs_surface *s, double u, double v, prw_normal_kind *kind)
{
    double u0, u1, v0, v1;
    prw_nurbs_surface_domain(s, &u0, &u1, &v0, &v1);
    u = clamp_param(u, u0, u1);
    v = clamp_param(v, v0, v1);
    prw_dvec3 d[9];
    prw_nurbs_surface_derivs(s, u, v, 2, d);
    prw_dvec3 su = d[1 * 3 + 0], sv = d[0 * 3 + 1];
    prw_dvec3 suu = d[2 * 3 + 0], suv = d[1 * 3 + 1], svv = d[0 * 3 + 2];
    (void)suu;
    (void)svv;
    prw_dvec3 n = prw_v3_cross(su, sv);
    if (normal_ok(n, su, sv)) {
        if (kind) *kind = PRW_NORMAL_REGULAR;
        return prw_v3_norm(n);
    }
    /* (1) Limit: the direction that moves into the domain from (u, v). */
    double su_len = prw_v3_len(su), sv_len = prw_v3_len(sv);
    double sgn_v = (v - v0) <= (v1 - v) ? 1.0 : -1.0;
    double sgn_u = (u - u0) <= (u1 - u) ? 1.0 : -1.0;
    prw_dvec3 cand;
    if (su_len <= sv_len) /* Su vanishes: Su(u, v+δ) ≈ δ Suv */
        cand = prw_v3_scale(prw_v3_cross(suv, sv), sgn_v);
    else /* Sv vanishes: Sv(u+δ, v) ≈ δ Suv */
        cand = prw_v3_scale(prw_v3_cross(su, suv), sgn_u);
    if (normal_ok(cand, su_len <= sv_len ? suv : su, su_len <= sv_len ? sv : suv)) {
        if (kind) *kind = PRW_NORMAL_LIMIT;
        return prw_v3_norm(cand);
    }
    /* (2) Nearby parameters, moved toward the domain centre. */
    double uc = 0.5 * (u0 + u1), vc = 0.5 * (v0 + v1);
    static const double steps[2] = {1e-6, 1e-3};
    for (int i = 0; i < 2; i++) {
        double uu = u + (uc - u) * steps[i] * 2.0, vvv = v + (vc - v) * steps[i] * 2.0;
        if (uu == u) uu = u + (uc >= u ? 1 : -1) * steps[i] * (u1 - u0);
        if (vvv == v) vvv = v + (vc >= v ? 1 : -1) * steps[i] * (v1 - v0);
        prw_dvec3 e1[3];
        prw_nurbs_surface_derivs(s, uu, vvv, 1, e1);
        /* e1 holds k*(nd+1)+l: [0]=S, [1]=Sv, [2]=Su */
        prw_dvec3 m = prw_v3_cross(e1[2], e1[1]);
        if (normal_ok(m, e1[2], e1[1])) {
            if (kind) *kind = PRW_NORMAL_NEARBY;
            return prw_v3_norm(m);
        }
    }
    if (kind) *kind = PRW_NORMAL_UNDEFINED;
    return prw_v3(0, 0, 0);
}

void prw_nurbs_surface_bounds(const prw_nurbs_surface *s, prw_dvec3 *lo, prw_dvec3 *hi)
{
    *lo = prw_v3(INFINITY, INFINITY, INFINITY);
    *hi = prw_v3(-INFINITY, -INFINITY, -INFINITY);
    size_t n = (size_t)s->nu * (size_t)s->nv;
    for (size_t i = 0; i < n; i++) {
        const double *q = s->pw + 4 * i;
        prw_dvec3 p = prw_v3(q[0] / q[3], q[1] / q[3], q[2] / q[3]);
        *lo = prw_v3_min(*lo, p);
        *hi = prw_v3_max(*hi, p);
    }
}

void prw_nurbs_surface_transform(prw_nurbs_surface *s, const prw_dmat4 *m)
{
    size_t n = (size_t)s->nu * (size_t)s->nv;
    for (size_t i = 0; i < n; i++) {
        double *q = s->pw + 4 * i;
        double w = q[3];
        prw_dvec3 p = prw_dm4_point(*m, prw_v3(q[0] / w, q[1] / w, q[2] / w));
        q[0] = p.x * w;
        q[1] = p.y * w;
        q[2] = p.z * w;
    }
}
