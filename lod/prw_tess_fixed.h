/* prw_tess_fixed — triangulation of a trimmed surface whose boundary vertices are GIVEN (the seam
 * graph's sewing points in this patch's (u, v)): no boundary point is added, moved or dropped.
 *
 * Method (as prw_tess, minus the boundary refinement): a uniform (u, v) grid with cells from the
 * chordal bound h²·|S''|/8 <= chord (second derivatives sampled; 2 .. max_cells per direction); a
 * cell is full when no boundary edge comes within a quarter cell of it and its centre is inside
 * (even-odd, exact predicates); diagonal-only contacts are removed; full cells give two triangles;
 * the rest (boundary loops + staircase loops) is ear-clipped (prw_earclip).
 * Output vertices: the boundary points first (same indices as given), then grid vertices.  Every
 * triangle is counter-clockwise in (u, v) with positive area.
 * Errors: a loop with fewer than 3 points, a boundary point left unused by the triangulation
 * (duplicate points), or a triangulated area differing from the even-odd area by > 1e-9 relative
 * (crossing loops).
 */
#ifndef PRW_TESS_FIXED_H
#define PRW_TESS_FIXED_H

#include "prw_nurbs.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct prw_tess_fixed_mesh {
    double *uv; /* 2 per vertex */
    int nverts;
    int *tris; /* 3 per triangle */
    int ntris;
    int cells_u, cells_v, full_cells, forced_ears;
} prw_tess_fixed_mesh;

/* Loop k is the boundary points [start[k], start[k+1]) of uv (2 doubles per point). */
/* cell_scale multiplies the cell counts (1: as described); callers retry with other scales when
 * ear clipping leaves collinear boundary chains unused. */
bool prw_tess_fixed(const prw_nurbs_surface *s, const double *uv, const int *start, int nloops, double chord,
                    int max_cells, double cell_scale, prw_tess_fixed_mesh *m, prw_error *e);
void prw_tess_fixed_free(prw_tess_fixed_mesh *m);

#ifdef __cplusplus
}
#endif
#endif
