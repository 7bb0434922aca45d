/* prw_lod_orient — one consistent orientation for the patches of a LOD model.
 *
 * Patches of one model need not agree on their orientation (the procedural box's fillets and
 * corners face inward).  prw_lod_orient decides, per patch, whether its emission is drawn with
 * reversed winding (and normals):
 *  - across every shared segment whose two exact normals at its middle are clearly parallel or
 *    antiparallel (|cos| > 0.3; G1 seams — creases near 90 degrees are skipped), the two patches
 *    must agree: a breadth-first walk over the patches' boundary segments assigns flips, every
 *    contradiction found is counted in *conflicts;
 *  - then per connected component: closed (every segment shared or degenerate) -> the orientation
 *    with positive enclosed volume (outward; the signed volume of each patch's level-0 emission,
 *    relative to the centre of the NURBS model's box); open -> the orientation most of its patches
 *    already had.
 * Deterministic: the same hierarchy and model always give the same flips (the bake stores the proxy
 * built with them; engine/render/lod_gpu.c recomputes them at create).  Needs the NURBS model (exact
 * normals); lm->npatches must equal m->count.
 */
#ifndef PRW_LOD_ORIENT_H
#define PRW_LOD_ORIENT_H

#include "prw_lod.h"
#include "prw_nurbs_model.h"

#ifdef __cplusplus
extern "C" {
#endif

/* flip: lm->npatches bytes (1 = reversed); conflicts (may be NULL): contradictions found. */
void prw_lod_orient(const prw_lod_model *lm, const prw_nurbs_model *m, unsigned char *flip, int *conflicts);

#ifdef __cplusplus
}
#endif
#endif
