/* prw_bake_scene — the hierarchy of a scene's NURBS entry (prw_scene_nurbs), shared by everything that
 * draws one (the rasterizer's LOD models, the reference path tracer), so both see the same
 * tessellations.  A file entry goes through prw_bake_run (the `prw bake` cache key); a procedural
 * entry is cached under a key made from its content hash (prw_scene_nurbs_model_hash).  The seam
 * chord is the entry's chord_rel (0: 2e-4) times the model's diagonal (with finest_rel > 0: at most half
 * of finest_rel x diagonal, and level 0 is refined to finest_rel x diagonal) — level 0 of the
 * hierarchy is the entry's finest tessellation.  The cache is an optimisation: a read-only or corrupt cache only
 * costs a rebuild. */
#ifndef PRW_BAKE_SCENE_H
#define PRW_BAKE_SCENE_H

#include "prw_bake.h"
#include "prw_scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* m: the entry's loaded model (prw_scene_nurbs_load).  progress (may be NULL) gets one line saying
 * whether the hierarchy came from the cache or how long building it took. */
bool prw_bake_scene_entry(const prw_scene_nurbs *n, const prw_nurbs_model *m, prw_bake_progress_fn progress,
                          void *user, prw_baked_lod **out, prw_error *e);

#ifdef __cplusplus
}
#endif
#endif
