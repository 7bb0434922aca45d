/* prw_earclip — triangulation of a planar region bounded by polygons, by ear clipping.
 *
 * Promises:
 *  - The region is the even-odd interior of the given loops; loops must not cross each other or
 *    themselves (they may touch at vertices).  Loop orientation is free: nesting depth is found by
 *    exact point-in-polygon tests, even-depth loops become counter-clockwise outer boundaries and
 *    odd-depth loops clockwise holes of their innermost container.
 *  - Holes are joined to their outer boundary by bridges (Eberly, "Triangulation by Ear
 *    Clipping": the hole's rightmost vertex is connected to the visible outer vertex found by a
 *    +x ray and the reflex-vertex angle test), then ears are clipped.  Only strictly convex ears
 *    (exact prw_orient2d > 0) are emitted, so every triangle has positive (u, v) area and is
 *    counter-clockwise; an ear is valid when no other vertex lies in the closed triangle (first
 *    pass) or strictly inside it (second pass).  If neither finds an ear (degenerate input) the
 *    largest convex vertex is clipped anyway and counted in `forced`.
 *  - No new points are created: triangle indices refer to the caller's points.
 *  - The ear tests look only at the vertices and edges near the ear (a uniform grid over the ring,
 *    lod/prw_cellgrid.h) and give the answers a scan of the whole ring gives, so the triangles are
 *    those of the quadratic clipper; the cost grows with the ring's size times the vertices and
 *    edges an ear's triangle meets, near-linear for the boundary of a region of dense, short edges.
 */
#ifndef PRW_EARCLIP_H
#define PRW_EARCLIP_H

#include "prw_core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct prw_earclip_stats {
    int forced;   /* ears clipped without the emptiness test */
    int leftover; /* vertices left when only degenerate (collinear) pieces remained */
} prw_earclip_stats;

/* xy: 2 doubles per point.  Loop k is idx[start[k] .. start[k+1]) (start has nloops + 1
 * entries).  *tris (3 ints per triangle) is allocated; *ntris counts triangles. */
bool prw_earclip(const double *xy, const int *idx, const int *start, int nloops, int **tris, int *ntris,
                 prw_earclip_stats *st, prw_error *e);

#ifdef __cplusplus
}
#endif
#endif
