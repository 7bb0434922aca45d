/* prw_tess — a simple (non-LOD) tessellator for one trimmed surface, for tests and as the
 * finest-level reference until the seam-graph tessellator replaces it.
 *
 * Method (grid + boundary strip):
 *  1. Trim loops are flattened (prw_trim) to `trim_tol` in (u, v).
 *  2. A uniform grid over the domain: cells per direction from the chordal bound h²·|S''|/8 <=
 *     chord_tol (second derivatives sampled), at least one per knot span, clamped to
 *     [min_cells, max_cells].
 *  3. A cell is FULL when no loop edge comes within a quarter cell of it (bounding-box test,
 *     conservative) and its centre is inside the region; full cells give two triangles (diagonal
 *     (u0, v0)–(u1, v1) of the cell).  Diagonal-only contacts of full cells are removed so that their
 *     union has a simple boundary.
 *  4. The rest of the region (trim loops + the staircase boundary of the full cells, which never
 *     touch each other) is triangulated by ear clipping with hole bridging (prw_earclip), using
 *     every loop vertex, points splitting loop edges longer than a cell, and every staircase grid
 *     vertex.
 *  5. Vertices get exact surface positions and normals (prw_nurbs_surface_normal).  Triangles whose
 *     3-D area is zero to rounding (|cross| <= 1e-14·longest edge², e.g. at a collapsed edge) are
 *     dropped; every triangle lies in the trimmed region (its (u, v) triangle does).
 *  Reported as errors: loops that cross or overlap so the triangulated (u, v) area differs from the
 *  even-odd region area by more than 1e-9 relative; a surface with no non-degenerate triangle
 *  (zero-area patch); non-finite positions.
 */
#ifndef PRW_TESS_H
#define PRW_TESS_H

#include <stdint.h>

#include "prw_nurbs_model.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct prw_tess_options {
    double chord_tol; /* metres; 0: 1e-3 x control-hull diagonal */
    double trim_tol;  /* (u, v) units; 0: 1e-4 x the larger domain side */
    int min_cells;    /* 0: 4 */
    int max_cells;    /* 0: 256 */
} prw_tess_options;

typedef struct prw_tess_mesh {
    size_t nverts, ntris;
    double *pos; /* 3 per vertex */
    double *nrm; /* 3 per vertex, unit (or 0 where undefined) */
    double *uv;  /* 2 per vertex */
    uint32_t *tris;
    /* diagnostics */
    int cells_u, cells_v, full_cells;
    int normal_limit, normal_nearby, normal_undefined;
    int dropped_degenerate, forced_ears;
    double uv_area, region_area;
} prw_tess_mesh;

bool prw_tess_surface(const prw_trimmed_surface *t, const prw_tess_options *o, prw_tess_mesh *m, prw_error *e);
void prw_tess_mesh_free(prw_tess_mesh *m);

#ifdef __cplusplus
}
#endif
#endif
