/* prw_nurbs — rational B-spline curves and surfaces of any degree, in double precision.
 *
 * Promises:
 *  - Control points are stored HOMOGENEOUS, four doubles each: (w·x, w·y, w·z, w).  A 2-D curve
 *    (trim curve in (u,v)) keeps z = 0 and has dim = 2.  Weights are finite and > 0.
 *  - A knot vector is valid when it has n + p + 1 finite, non-decreasing entries, every
 *    multiplicity is ≤ p + 1 and the domain [U[p], U[n]] is not empty (n = control points).
 *    Clamped and unclamped vectors are both accepted; the domain is [U[p], U[n]] either way.
 *  - Evaluation clamps the parameter into the domain.  Point evaluation: NURBS Book A4.1 / A4.3
 *    on the homogeneous net (spans by A2.1, basis by A2.2).  Derivatives: A2.3 + A3.2 / A3.6 on
 *    the homogeneous net, then the rational quotient rule A4.2 / A4.4 — up to order 2 here
 *    (any order ≤ PRW_NURBS_MAX_DERIV).
 *  - Surface control points are indexed i + j·nu (u varies fastest, as IGES 128 stores them).
 *  - Degree ≤ PRW_NURBS_MAX_DEGREE; larger degrees are rejected by validation.
 *  - Nothing here allocates except the functions that say so; nothing prints.
 */
#ifndef PRW_NURBS_H
#define PRW_NURBS_H

#include <stdbool.h>
#include <stddef.h>

#include "prw_core.h"
#include "prw_math.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PRW_NURBS_MAX_DEGREE 31
#define PRW_NURBS_MAX_DERIV 2
/* A single curve / surface direction may have at most this many control points (keeps every
 * size computation far from overflow; IGES counts beyond it are rejected as malformed). */
#define PRW_NURBS_MAX_CTRL 1000000

typedef struct prw_nurbs_curve {
    int dim;       /* 2 or 3: meaningful Cartesian coordinates */
    int degree;    /* p >= 1 */
    int n;         /* number of control points, >= p + 1 */
    double *knots; /* n + p + 1 */
    double *pw;    /* 4 * n homogeneous control points */
} prw_nurbs_curve;

typedef struct prw_nurbs_surface {
    int degree_u, degree_v;
    int nu, nv;
    double *knots_u; /* nu + degree_u + 1 */
    double *knots_v; /* nv + degree_v + 1 */
    double *pw;      /* 4 * nu * nv, index (i + j*nu) */
} prw_nurbs_surface;

/* ---- knot vectors (prw_knots.c) ------------------------------------------------------------- */

/* Checks the rules above; the message names `what` ("knots_u", ...). */
bool prw_knots_validate(const double *U, int n, int p, const char *what, prw_error *e);
/* A2.1 FindSpan, generalised: the span index k in [p, n-1] with U[k] <= u < U[k+1] and
 * U[k] < U[k+1]; parameters at or beyond the domain ends map to the first / last non-empty span. */
int prw_knots_find_span(const double *U, int n, int p, double u);
/* A2.2: the p + 1 non-zero basis functions at u in span k. */
void prw_knots_basis(const double *U, int p, int k, double u, double *N);
/* A2.3: ders[d*(p+1) + j] = d-th derivative of N_{k-p+j,p}(u), d = 0..nd (nd <= p handled;
 * orders above p are zero). */
void prw_knots_basis_ders(const double *U, int p, int k, double u, int nd, double *ders);
/* Multiplicity of the value u in U (exact comparison). */
int prw_knots_multiplicity(const double *U, int count, double u);

/* ---- curves (prw_nurbs_curve.c) ------------------------------------------------------------- */

/* Allocates knots and pw for n control points (zeroed); fails only on bad sizes. */
bool prw_nurbs_curve_alloc(prw_nurbs_curve *c, int dim, int degree, int n, prw_error *e);
void prw_nurbs_curve_free(prw_nurbs_curve *c);
bool prw_nurbs_curve_copy(prw_nurbs_curve *dst, const prw_nurbs_curve *src, prw_error *e);
/* Knots, weights (> 0, finite), coordinates (finite). */
bool prw_nurbs_curve_validate(const prw_nurbs_curve *c, prw_error *e);
/* Sets control point i from Cartesian coordinates and a weight. */
void prw_nurbs_curve_set(prw_nurbs_curve *c, int i, prw_dvec3 p, double w);
prw_dvec3 prw_nurbs_curve_point_at(const prw_nurbs_curve *c, int i); /* Cartesian */
void prw_nurbs_curve_domain(const prw_nurbs_curve *c, double *t0, double *t1);
prw_dvec3 prw_nurbs_curve_eval(const prw_nurbs_curve *c, double t);
/* d[0..nd] = C, C', C'' ... (nd <= PRW_NURBS_MAX_DERIV). */
void prw_nurbs_curve_derivs(const prw_nurbs_curve *c, double t, int nd, prw_dvec3 *d);
/* Control-hull bounding box (the curve lies inside it: convex hull property, weights > 0). */
void prw_nurbs_curve_bounds(const prw_nurbs_curve *c, prw_dvec3 *lo, prw_dvec3 *hi);
/* Affine map of the control points (exact for NURBS). */
void prw_nurbs_curve_transform(prw_nurbs_curve *c, const prw_dmat4 *m);

/* ---- surfaces (prw_nurbs_surface.c) --------------------------------------------------------- */

bool prw_nurbs_surface_alloc(prw_nurbs_surface *s, int degree_u, int degree_v, int nu, int nv, prw_error *e);
void prw_nurbs_surface_free(prw_nurbs_surface *s);
bool prw_nurbs_surface_copy(prw_nurbs_surface *dst, const prw_nurbs_surface *src, prw_error *e);
bool prw_nurbs_surface_validate(const prw_nurbs_surface *s, prw_error *e);
void prw_nurbs_surface_set(prw_nurbs_surface *s, int i, int j, prw_dvec3 p, double w);
void prw_nurbs_surface_domain(const prw_nurbs_surface *s, double *u0, double *u1, double *v0, double *v1);
prw_dvec3 prw_nurbs_surface_eval(const prw_nurbs_surface *s, double u, double v);
/* skl[k*(nd+1) + l] = ∂^(k+l) S / ∂u^k ∂v^l for k + l <= nd (nd <= PRW_NURBS_MAX_DERIV);
 * entries with k + l > nd are left untouched. */
void prw_nurbs_surface_derivs(const prw_nurbs_surface *s, double u, double v, int nd, prw_dvec3 *skl);

typedef enum prw_normal_kind {
    PRW_NORMAL_REGULAR = 0,  /* Su × Sv */
    PRW_NORMAL_LIMIT = 1,    /* a first derivative vanishes: limit from second derivatives */
    PRW_NORMAL_NEARBY = 2,   /* fallback: normal at a nearby parameter toward the interior */
    PRW_NORMAL_UNDEFINED = 3 /* nothing worked (zero-area patch): n = (0,0,0) */
} prw_normal_kind;

/* Unit normal, oriented as Su × Sv.  Degenerate points (sphere poles, collapsed edges) — where
 * |Su × Sv| <= 1e-10·(|Su| + |Sv|)² — use, in order: (1) the limit of the normal as the parameter
 * moves into the domain from the point: if Su vanishes, Su(u, v+δ) ≈ δ·Suv so n ∥ sign(δ)·Suv × Sv
 * (δ points into the domain), symmetrically Su × Suv·sign(δ) if Sv vanishes; (2) the normal at a
 * parameter moved toward the domain centre by 1e-6, then 1e-3 of the domain size.  Never NaN. */
prw_dvec3 prw_nurbs_surface_normal(const prw_nurbs_surface *s, double u, double v, prw_normal_kind *kind);
void prw_nurbs_surface_bounds(const prw_nurbs_surface *s, prw_dvec3 *lo, prw_dvec3 *hi);
void prw_nurbs_surface_transform(prw_nurbs_surface *s, const prw_dmat4 *m);

/* ---- refinement (prw_nurbs_refine.c) -------------------------------------------------------- */

/* A5.1: inserts t r times (so that its multiplicity stays <= degree); t strictly inside the
 * domain.  The curve is unchanged as a point set and as a parameterisation. */
bool prw_nurbs_curve_insert_knot(prw_nurbs_curve *c, double t, int r, prw_error *e);
/* A5.3 (one direction at a time): dir 0 = u, 1 = v. */
bool prw_nurbs_surface_insert_knot(prw_nurbs_surface *s, int dir, double t, int r, prw_error *e);
/* The piece over [t0, t1] (inside the domain, t0 < t1) as a clamped curve: knot insertion to
 * full multiplicity at both ends. */
bool prw_nurbs_curve_extract(const prw_nurbs_curve *c, double t0, double t1, prw_nurbs_curve *out, prw_error *e);
bool prw_nurbs_surface_extract(const prw_nurbs_surface *s, double u0, double u1, double v0, double v1,
                               prw_nurbs_surface *out, prw_error *e);
/* Degree elevation to `degree` by Bézier decomposition (A5.6 via repeated A5.1), elevation of each
 * segment (NURBS Book eq. 5.36) and reassembly with C0 knots: exact, not knot-minimal. */
bool prw_nurbs_curve_elevate(const prw_nurbs_curve *c, int degree, prw_nurbs_curve *out, prw_error *e);
/* Affine reparameterisation of the knots onto [a, b]. */
void prw_nurbs_curve_reparam(prw_nurbs_curve *c, double a, double b);
/* Reversed direction: knots mirrored, control points reversed. */
void prw_nurbs_curve_reverse(prw_nurbs_curve *c);
/* Makes two clamped curves compatible (same degree and knot vector on [0, 1]) in place, for ruled
 * surfaces: reparameterise, elevate the lower degree, merge knots by insertion. */
bool prw_nurbs_curves_make_compatible(prw_nurbs_curve *a, prw_nurbs_curve *b, prw_error *e);
/* Clamps an unclamped curve (full-multiplicity insertion at the domain ends, then trimming). */
bool prw_nurbs_curve_clamp(prw_nurbs_curve *c, prw_error *e);

#ifdef __cplusplus
}
#endif
#endif
