/* prw_cellgrid — a uniform grid of cells over a 2-D box, and the cells a convex polygon touches.
 *
 * Promises:
 *  - prw_cellgrid_init makes nx x ny cells, about `target` of them (1 <= nx, ny and
 *    nx * ny <= max(target, 1) + nx / 2), shaped after the box's aspect ratio; a box of zero (or
 *    non-finite) width or height gets one column or one row.
 *  - prw_cellgrid_cell maps every point (outside the box too, NaN included) to a cell index in
 *    [0, cells): points outside are clamped to the border cells.
 *  - prw_cellgrid_cover lists cells touched by the convex polygon of k points (k = 1: a point,
 *    2: a segment, 3: a triangle, ... up to 8; the points in either order): every point in the
 *    closed polygon (exactly) has its cell listed, whatever the rounding: prw_cellgrid_cell(p) for
 *    a point p of doubles, the cell holding the exact coordinates for any real point (where two
 *    segments cross, say).  The list is conservative (padded by a margin that covers rounding, at
 *    least 1e-3 of a cell), with no repeated cell; its length is about the number of cells the
 *    polygon crosses plus its column count, not its bounding box.
 */
#ifndef PRW_CELLGRID_H
#define PRW_CELLGRID_H

#include "prw_core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct prw_cellgrid {
    double x0, y0; /* box corner */
    double ix, iy; /* cells per unit (0 for a flat direction) */
    double pad;    /* margin in cell units */
    int nx, ny;
} prw_cellgrid;

void prw_cellgrid_init(prw_cellgrid *g, const double lo[2], const double hi[2], int target);
int prw_cellgrid_cell(const prw_cellgrid *g, const double p[2]);
/* xy: k points (2 doubles each).  Cell indices go into *cells (grown with prw_realloc, *cap its
 * capacity); returns their count. */
int prw_cellgrid_cover(const prw_cellgrid *g, const double *xy, int k, int **cells, int *cap);

#ifdef __cplusplus
}
#endif
#endif
