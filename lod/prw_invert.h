/* prw_invert — point inversion and curve projection onto a NURBS surface (NURBS Book §6.1).
 *
 * Promises:
 *  - prw_nurbs_surface_invert finds (u, v) minimising |S(u, v) − P|: start at the nearest point of
 *    a coarse parameter grid (or at *u, *v when `use_start`), then Newton iterations on
 *    f = Su·r, g = Sv·r (eq. 6.6, r = S − P, second derivatives in the Jacobian), clamped to the
 *    domain; stops when |r| <= 1e-12·scale, both cosines |f|/(|Su||r|), |g|/(|Sv||r|) <= 1e-10,
 *    or the step is below 1e-15 of the domain; at most 50 iterations.  When it stops on a pole
 *    (S_u or S_v zero, point not reached) it runs once more from the nearest grid point off the
 *    collapsed rows and keeps the nearer answer.  Returns the distance.
 *  - prw_nurbs_surface_project_curve flattens a model-space curve (3-D chordal tolerance tol)
 *    and inverts each point (continuation from the previous point; a coarse-grid restart when that
 *    is worse than the grid start), giving a degree-1 (u, v) curve and the largest distance.  The
 *    flattening stops with an error beyond max_points points (at most 200000; <= 0: 200000), before
 *    any point is inverted, so a caller's budget bounds the work.
 *    Limitation: loops that cross the seam of a closed surface are not unwrapped.
 */
#ifndef PRW_INVERT_H
#define PRW_INVERT_H

#include "prw_nurbs.h"

#ifdef __cplusplus
extern "C" {
#endif

double prw_nurbs_surface_invert(const prw_nurbs_surface *s, prw_dvec3 p, bool use_start, double *u, double *v);
bool prw_nurbs_surface_project_curve(const prw_nurbs_surface *s, const prw_nurbs_curve *c, double tol, int max_points,
                                     prw_nurbs_curve *uv, double *max_dist, prw_error *e);

#ifdef __cplusplus
}
#endif
#endif
