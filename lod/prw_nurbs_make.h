/* prw_nurbs_make — exact NURBS constructions of lines, circular arcs and the IGES analytic
 * surfaces (plane patch, ruled surface, surface of revolution, tabulated cylinder), plus the test
 * primitives sphere and torus.
 *
 * Promises: every result is an exact representation (up to floating-point rounding of the control
 * points) of the named geometry; outputs are allocated (free with the matching _free) and
 * validated.  Circles and arcs follow NURBS Book A7.1: rational quadratic, 1–4 arcs of at most
 * 90° each, inner weights cos(Δθ/2); surfaces of revolution follow A8.1 (a circle per generatrix
 * control point; control points on the axis collapse to a pole). */
#ifndef PRW_NURBS_MAKE_H
#define PRW_NURBS_MAKE_H

#include "prw_nurbs.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Degree-1 segment P0 -> P1 on [0, 1]. */
bool prw_nurbs_make_line(prw_nurbs_curve *c, int dim, prw_dvec3 p0, prw_dvec3 p1, prw_error *e);
/* Degree-1 polyline through pts on [0, n-1] (uniform parameter per segment). */
bool prw_nurbs_make_polyline(prw_nurbs_curve *c, int dim, const prw_dvec3 *pts, int n, prw_error *e);
/* Arc O + r(cos θ X + sin θ Y), θ from ths to the (the > ths, the - ths <= 2π); X, Y orthonormal.
 * Parameter range [0, 1]. */
bool prw_nurbs_make_arc(prw_nurbs_curve *c, int dim, prw_dvec3 o, prw_dvec3 x, prw_dvec3 y, double r, double ths,
                        double the, prw_error *e);
/* Generatrix g (u) revolved about the axis through `s` with unit direction `t`, angles
 * theta0..theta1 (v on [0, 1]), counter-clockwise about t. */
bool prw_nurbs_make_revolution(prw_nurbs_surface *out, const prw_nurbs_curve *g, prw_dvec3 s, prw_dvec3 t,
                               double theta0, double theta1, prw_error *e);
/* Ruled surface between a (v = 0) and b (v = 1): degree (p, 1); the curves are made compatible
 * first (the ruling joins equal relative parameters). */
bool prw_nurbs_make_ruled(prw_nurbs_surface *out, const prw_nurbs_curve *a, const prw_nurbs_curve *b, prw_error *e);
/* Tabulated cylinder: S(u, v) = C(u) + v·d, v in [0, 1]. */
bool prw_nurbs_make_extrusion(prw_nurbs_surface *out, const prw_nurbs_curve *c, prw_dvec3 d, prw_error *e);
/* Bilinear patch: S(0,0) = p00, S(1,0) = p10, S(0,1) = p01, S(1,1) = p11 on [0, 1]². */
bool prw_nurbs_make_bilinear(prw_nurbs_surface *out, prw_dvec3 p00, prw_dvec3 p10, prw_dvec3 p01, prw_dvec3 p11,
                             prw_error *e);
/* Sphere: a semicircle (north to south pole, 2 arcs) revolved through 2π (4 arcs) about z.
 * u in [0, 1] from the north pole, v in [0, 1] around; poles are collapsed edges; Su × Sv points
 * outward. */
bool prw_nurbs_make_sphere(prw_nurbs_surface *out, prw_dvec3 centre, double r, prw_error *e);
/* Torus about z: tube circle (4 arcs) of radius r at distance R, revolved through 2π; Su × Sv
 * points outward. */
bool prw_nurbs_make_torus(prw_nurbs_surface *out, prw_dvec3 centre, double R, double r, prw_error *e);

#ifdef __cplusplus
}
#endif
#endif
