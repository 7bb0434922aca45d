/* prw_trim — trim loops flattened to polygons in (u, v), and the inside test.
 *
 * Promises:
 *  - prw_trim_region_build flattens every loop of a trimmed surface to a closed polygon: each
 *    segment's curve is cut at its knots and subdivided until the curve point at 1/3 and 2/3 of
 *    each piece is within `tol` (a (u, v) distance) of the chord; degree-1 segments are taken
 *    exactly.  A natural outer boundary becomes the domain rectangle (loop 0).  Points are clamped
 *    into the domain; consecutive points within 1e-3 tol of each other (per coordinate) are merged
 *    and so is the closing duplicate; where two edges of a loop cross or touch with a short path
 *    between them (<= 1e-2 of the larger domain side, <= a tenth of the loop's perimeter, <= 256
 *    points: trim curves whose ends overshoot each other at a corner), the path is replaced by the
 *    intersection point; loops with fewer than 3 points or zero area are dropped (counted in
 *    `dropped`).
 *  - Inside rule: EVEN-ODD over all loops (orientation-free: IGES does not guarantee it).  The
 *    trimmed region is the CLOSED set: a point exactly on a loop edge is PRW_TRIM_ON and counts
 *    as inside.  Where two loops touch or share edges, the shared edges count twice and cancel,
 *    which is the right answer for a hole touching the outer loop or the domain boundary.
 *  - Exactness: crossings use the half-open rule (an edge counts when exactly one endpoint is
 *    strictly above the point) and prw_orient2d (exact sign), so the classification of a point
 *    against the flattened polygons is exact; ON means exactly on an edge.
 *  - prw_trim_inside adds a tolerance: inside, on, or within `tol` of an edge.
 */
#ifndef PRW_TRIM_H
#define PRW_TRIM_H

#include "prw_nurbs_model.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct prw_trim_polygon {
    double *uv; /* 2 * n, not repeating the first point at the end */
    int n;
} prw_trim_polygon;

typedef struct prw_trim_region {
    prw_trim_polygon *loops;
    int count;
    int dropped;            /* degenerate loops removed */
    double u0, u1, v0, v1;  /* surface domain */
} prw_trim_region;

typedef enum prw_trim_class { PRW_TRIM_OUTSIDE = 0, PRW_TRIM_INSIDE = 1, PRW_TRIM_ON = 2 } prw_trim_class;

/* Appends the flattened curve (first point included) to *pts (2 doubles per point). */
bool prw_trim_flatten_curve(const prw_nurbs_curve *c, double tol, double **pts, int *n, int *cap, prw_error *e);
bool prw_trim_region_build(const prw_trimmed_surface *t, double tol, prw_trim_region *r, prw_error *e);
void prw_trim_region_free(prw_trim_region *r);
prw_trim_class prw_trim_classify(const prw_trim_region *r, double u, double v);
bool prw_trim_inside(const prw_trim_region *r, double u, double v, double tol);
/* Signed area of one polygon (shoelace about its first point). */
double prw_trim_polygon_area(const prw_trim_polygon *p);
/* Area of the region under the even-odd rule (nesting depth parity of each loop). */
double prw_trim_region_area(const prw_trim_region *r);

#ifdef __cplusplus
}
#endif
#endif
