/* prw_nurbs_procedural — multi-patch trimmed NURBS models built in code, for the seam-graph and
 * LOD tests and benchmarks.
 *
 * Promises (every model is appended to an initialised prw_nurbs_model; lengths in metres):
 *  - Filleted box: the cube [-a, a]³ with edge fillets of radius r (a = half + radius):
 *    6 flat faces (bilinear planes over [-a, a]² trimmed by a square polyline loop to the flat
 *    part), 12 quarter-cylinder fillets (extrusions of rational quadratic arcs, untrimmed) and
 *    8 sphere octants at the corners (A8.1 revolutions, each with a collapsed edge — a pole — at
 *    the corner of its face).  26 patches, closed: no true border.
 *  - Shell: a height field over [0, width] × [0, depth] as ONE clamped bicubic B-spline with
 *    nx × ny uniform spans, split into nx × ny Bézier patches by knot insertion
 *    (prw_nurbs_surface_extract), so neighbours meet exactly (up to rounding).  The height is a
 *    car-roof-like dome plus bumps (`height` = dome height, 0 = flat).  `holes` circular
 *    inner trim loops (rational quadratic circles in (u, v)), each inside one patch.  The outer
 *    rectangle and the holes are true borders.
 *  - prw_procedural_plate: a gently curved 3 × 2-patch plate with 4 holes (shell with fixed knobs).
 *  - prw_procedural_car_shell: a 12 × 10-patch (120) dome with 6 windows.
 */
#ifndef PRW_NURBS_PROCEDURAL_H
#define PRW_NURBS_PROCEDURAL_H

#include "prw_nurbs_model.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct prw_procedural_hole {
    int pi, pj;       /* patch column / row */
    double cu, cv, r; /* centre and radius relative to the patch's (u, v) span (0..1) */
} prw_procedural_hole;

bool prw_procedural_filleted_box(prw_nurbs_model *m, double half, double radius, prw_error *e);
bool prw_procedural_shell(prw_nurbs_model *m, int nx, int ny, double width, double depth, double height,
                          const prw_procedural_hole *holes, int nholes, prw_error *e);
bool prw_procedural_plate(prw_nurbs_model *m, prw_error *e);
bool prw_procedural_car_shell(prw_nurbs_model *m, prw_error *e);

#ifdef __cplusplus
}
#endif
#endif
