/* prw_bake_scene — makes a scene READY for the renderer and the reference: every NURBS entry
 * (prw_scene_nurbs) gets its loaded model and its LOD hierarchy attached (prw_scene_nurbs_attach,
 * engine/scene/prw_lod_node.h), so both draw the same tessellations and neither loads or builds
 * anything.  app/ (and tests) call prw_bake_scene after loading a scene and before creating a
 * renderer or a reference; those fail with "NURBS entry '<name>' has no baked hierarchy: call
 * prw_bake_scene (engine/bake) first" on an entry left unbaked.
 *
 * Promises:
 *  - A file entry goes through prw_bake_run (the `prw bake` cache key); a procedural entry is cached
 *    under a key made from its content hash (prw_scene_nurbs_model_hash).  The seam chord is the
 *    entry's chord_rel (0: 2e-4) times the model's diagonal (with finest_rel > 0: at most half of
 *    finest_rel x diagonal, and level 0 is refined to finest_rel x diagonal) — level 0 of the
 *    hierarchy is the entry's finest tessellation.
 *  - The cache is an optimisation: a read-only cache only costs a rebuild; a corrupt entry is
 *    reported (one progress line) and rebuilt.
 *  - progress (may be NULL) gets, per entry, "lod: <name>: hierarchy from the cache" or
 *    "lod: <name>: hierarchy built in <s> s" (and any cache warning), and when patches failed
 *    "lod: <name>: N of M patches could not be tessellated and are not drawn (first: ...)"; nothing
 *    is printed here.
 *  - prw_bake_scene skips entries that already have an attachment (calling it twice builds nothing)
 *    and stops at the first entry that fails, with an error naming it ("NURBS model '<name>': ...");
 *    the entries before it stay attached.  A scene without NURBS entries is ready as it is.
 */
#ifndef PRW_BAKE_SCENE_H
#define PRW_BAKE_SCENE_H

#include "prw_bake.h"
#include "prw_lod_node.h"
#include "prw_scene.h"

#ifdef __cplusplus
extern "C" {
#endif

bool prw_bake_scene(prw_scene *s, prw_bake_progress_fn progress, void *user, prw_error *e);

/* One entry's hierarchy, not attached: m is the entry's loaded model (prw_scene_nurbs_load); *out is
 * destroyed with prw_lod_file_destroy.  progress as above. */
bool prw_bake_scene_entry(const prw_scene_nurbs *n, const prw_nurbs_model *m, prw_bake_progress_fn progress,
                          void *user, prw_baked_lod **out, prw_error *e);

#ifdef __cplusplus
}
#endif
#endif
