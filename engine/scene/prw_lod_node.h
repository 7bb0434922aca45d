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
 *  - Attachments: the baker (engine/bake/prw_bake_scene.h) attaches to each entry its loaded model
 *    and its LOD hierarchy (the in-memory .lod, prw_lod_file.h); the scene owns them from then on
 *    and frees them with the entry (prw_scene_destroy, or a failed load's rollback).  The renderer
 *    and the reference only read them (prw_scene_nurbs_baked), so both draw the same tessellations
 *    and neither loads nor builds anything.  An attachment never moves while the scene lives
 *    (pointers to it stay valid when entries are added).
 */
#ifndef PRW_LOD_NODE_H
#define PRW_LOD_NODE_H

#include "prw_lod_file.h"
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

/* What prw_scene_nurbs_attach stores per entry (read it through prw_scene_nurbs_baked). */
struct prw_scene_nurbs_baked {
    prw_nurbs_model *model; /* NULL: not baked */
    prw_baked_lod *lod;
};
/* Attaches model and hierarchy to entry i.  Takes both in every case: *m is moved into the scene
 * (left empty, as after prw_nurbs_model_init) and lod is owned by the scene — or freed when the call
 * fails (i is not an entry, or lod's patch count is not m's surface count).  Replaces (frees) an
 * earlier attachment. */
bool prw_scene_nurbs_attach(prw_scene *s, uint32_t i, prw_nurbs_model *m, prw_baked_lod *lod, prw_error *e);
/* Entry i's attached model and hierarchy (borrowed: valid while the scene lives).  Fails with
 * "NURBS entry '<name>' has no baked hierarchy: call prw_bake_scene (engine/bake) first" when
 * nothing is attached.  m or lod may be NULL. */
bool prw_scene_nurbs_baked(const prw_scene *s, uint32_t i, const prw_nurbs_model **m, const prw_baked_lod **lod,
                           prw_error *e);

#ifdef __cplusplus
}
#endif
#endif
