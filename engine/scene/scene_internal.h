/* Private helpers shared by the files of engine/scene (not part of the public API). */
#ifndef PRW_SCENE_INTERNAL_H
#define PRW_SCENE_INTERNAL_H

#include "prw_scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Element counts at one moment, to undo a failed load (loaders are all-or-nothing). */
typedef struct prw_scene_mark {
    uint32_t meshes, groups, materials, textures, nodes, cameras, lights, nurbs, warnings;
} prw_scene_mark;

prw_scene_mark prw_scene_mark_get(const prw_scene *s);
/* Frees and drops every element added after `m`.  Elements older than the mark are untouched. */
void prw_scene_rollback(prw_scene *s, prw_scene_mark m);

/* Frees what the baker attached to one NURBS entry (prw_lod_node.h) and zeroes it. */
struct prw_scene_nurbs_baked;
void prw_scene_nurbs_baked_free(struct prw_scene_nurbs_baked *b);

/* Adds PRW_WARN_NO_LIGHT / PRW_WARN_NO_CAMERA ("<file>: no light ...") when the scene as it now is
 * has nothing that emits light / no camera, unless such a warning is already there.  Top-level
 * loaders call it once at their end. */
void prw_scene_note_missing(prw_scene *s, const char *file);

/* prw_scene_import_gltf without the final prw_scene_note_missing (the manifest loader imports its
 * glTF entries with it and checks the whole scene at its end). */
bool prw_gltf_import(prw_scene *s, const char *path, int parent, prw_error *e);

/* Copies a name, truncating to PRW_NAME_MAX-1 bytes (NULL -> ""). */
void prw_copy_name(char dst[PRW_NAME_MAX], const char *src);

#ifdef __cplusplus
}
#endif
#endif
