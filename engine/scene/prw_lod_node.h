/* prw_lod_node — where a scene's NURBS model (prw_scene_nurbs, issue 7) comes from: the one place
 * that turns an entry into a prw_nurbs_model, for the manifest reader (validation, bounds) and the
 * renderer (hierarchy build).
 *
 * Promises:
 *  - prw_scene_nurbs_load: a file entry is read by extension (.igs / .iges: IGES 5.3, .json: the
 *    NURBS JSON form, lod/nurbs_json.md); a procedural entry builds "car_shell"
 *    (prw_procedural_car_shell), "box" (prw_procedural_filleted_box, half 1 m, fillet 0.3 m) or
 *    "plate" (prw_procedural_plate).  Errors name the file (or the procedural name) and the reason;
 *    on failure *m is empty (freed).
 *  - prw_scene_nurbs_model_hash: a 64-bit content hash of every surface, trim curve and colour of a
 *    model (FNV-1a over the numbers), so a cache key follows the geometry, not the name.
 */
#ifndef PRW_LOD_NODE_H
#define PRW_LOD_NODE_H

#include "prw_nurbs_model.h"
#include "prw_scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* true when name is one of the procedural models ("car_shell", "box", "plate"). */
bool prw_scene_nurbs_procedural_known(const char *name);
/* Initialises *m and loads the entry's model into it (model metres, before the node transform). */
bool prw_scene_nurbs_load(const prw_scene_nurbs *n, prw_nurbs_model *m, prw_error *e);
uint64_t prw_scene_nurbs_model_hash(const prw_nurbs_model *m);

#ifdef __cplusplus
}
#endif
#endif
