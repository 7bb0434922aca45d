/* prw_trim_wrap — trim loops projected onto CLOSED surfaces (cylinders, cones, spheres, tori, any
 * NURBS whose opposite domain edges coincide): point inversion returns a parameter inside the
 * domain, so a loop that runs along or across the seam jumps by a period.  These functions undo
 * that, so the loop is one continuous (u, v) polygon.
 *
 * Promises:
 *  - prw_nurbs_surface_closed: true when S(u0, v) = S(u1, v) (dir 0) or S(u, v0) = S(u, v1)
 *    (dir 1) within tol at 33 samples along the edge.
 *  - prw_trim_unwrap_loop: the loop's degree-1 pieces (in loop order, end to end) are unwrapped in
 *    every closed direction (a point more than half a period away from its predecessor — the last
 *    point of the previous piece for a first point — is moved by whole periods to the nearest
 *    copy), then the whole loop is moved by the whole number of periods that overlaps the domain
 *    most.  Pieces of higher degree are moved as a whole (their start to the copy nearest the
 *    previous end).  range[dir] gets the loop's parameter range after the move.  Exact in 3-D:
 *    S(u + k·P, v) = S(u, v) on a closed surface, so every point still maps to the same place.
 *  - prw_nurbs_surface_reseat: a surface closed in dir gets the domain [a, a + P] in that
 *    direction, exactly (two copies joined C0 at the seam, then cut by knot insertion): for a loop
 *    that straddles the seam.  Fails (surface unchanged) when the seam rows' weights are not
 *    proportional (the copies cannot be joined without changing the surface).
 *  - prw_trim_drop_close_points: a degree-1 piece loses every control point within tol (in (u, v))
 *    of the point kept before it, its two ends always kept (an end within tol of its neighbour
 *    replaces it); knots go with their points, so the polyline is the same up to tol.  Point
 *    inversion at a domain edge returns v = 1, 1 - 1e-16, 1 for successive points, a zero-length
 *    back-and-forth the fixed tessellation cannot use (the public occt_OCC8842_cylinder_Ideas.igs
 *    lost its side face to it).  Other degrees are left alone.
 *  - prw_trim_join_bands: a loop that winds once around a closed direction (its end is its start
 *    moved by ±P there, the other coordinate within tol of where it began: a circle round a
 *    cylinder or cone) has no area under the even-odd rule; a band between two circles, each a
 *    boundary of its own (SolidWorks' bounded surfaces, the public halbrooks_hollowvase.igs), is
 *    the region between two such loops.  When a face has exactly two, starting at the same
 *    coordinate in that direction (within tol; the second moved by whole periods), they become one
 *    loop: the first, the seam line from its end to the second's start, the second (walked the
 *    other way round when it winds the same way), the seam line back — the band as one ring of the
 *    domain, the seam lines without model curves.  Anything else is left as it is.  Returns whether
 *    it joined.
 *  - prw_trim_cut_spikes: where a loop turns back on itself at a junction of two degree-1 pieces
 *    (the next piece's first points all within tol of the previous piece's polyline, in (u, v)
 *    scaled by 1 / the domain's side in each direction, for more than 4 tol of its length), both
 *    pieces are cut at the last such point (its nearest point on the previous piece becomes their
 *    common end): the zero-width spike, whose two sides cross each other wherever inversion noise
 *    puts them, is gone and the loop is simple there.  A plane cut tangent to a tube along a
 *    boundary line gives one (the ground ends of the public occt_bug22869_Spring.igs: its edge
 *    runs 2.6 of the 52 (u, v) units along the helix edge before it leaves it).  The region loses
 *    at most a sliver tol wide; a piece that would lose all its points is left alone, and so is
 *    anything else.  Model-space curves are not cut (nothing reads them past the projection).
 *    Returns the number of junctions cut.
 *  - Nothing prints; prw_nurbs_surface_reseat, prw_trim_join_bands and prw_trim_cut_spikes
 *    allocate.
 */
#ifndef PRW_TRIM_WRAP_H
#define PRW_TRIM_WRAP_H

#include "prw_nurbs_model.h"

#ifdef __cplusplus
extern "C" {
#endif

bool prw_nurbs_surface_closed(const prw_nurbs_surface *s, int dir, double tol);
/* closed[2]: the surface's closed directions (prw_nurbs_surface_closed). */
void prw_trim_unwrap_loop(const prw_nurbs_surface *s, const bool closed[2], prw_nurbs_curve *pieces, int n,
                          double range[2][2]);
/* Moves every piece of a loop by whole periods in dir so its range overlaps [a, a + P] most. */
void prw_trim_shift_loop(const prw_nurbs_surface *s, int dir, double a, prw_nurbs_curve *pieces, int n);
bool prw_nurbs_surface_reseat(prw_nurbs_surface *s, int dir, double a, prw_error *e);
void prw_trim_drop_close_points(prw_nurbs_curve *c, double tol);
bool prw_trim_join_bands(prw_trimmed_surface *t, const bool closed[2], double tol);
/* pieces: one loop's pieces in order (the last joins the first); dom: u0, u1, v0, v1. */
int prw_trim_cut_spikes(prw_nurbs_curve *pieces, int n, const double dom[4], double tol);

#ifdef __cplusplus
}
#endif
#endif
