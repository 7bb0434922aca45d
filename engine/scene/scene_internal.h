/* Private helpers shared by the files of engine/scene (not part of the public API). */
#ifndef PRW_SCENE_INTERNAL_H
#define PRW_SCENE_INTERNAL_H

#include "prw_scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Element counts at one moment, to undo a failed load (loaders are all-or-nothing). */
typedef struct prw_scene_mark {
    uint32_t meshes, groups, materials, textures, nodes, cameras, lights, nurbs;
} prw_scene_mark;

prw_scene_mark prw_scene_mark_get(const prw_scene *s);
/* Frees and drops every element added after `m`.  Elements older than the mark are untouched. */
void prw_scene_rollback(prw_scene *s, prw_scene_mark m);

/* Frees what the baker attached to one NURBS entry (prw_lod_node.h) and zeroes it. */
struct prw_scene_nurbs_baked;
void prw_scene_nurbs_baked_free(struct prw_scene_nurbs_baked *b);

/* Copies a name, truncating to PRW_NAME_MAX-1 bytes (NULL -> ""). */
void prw_copy_name(char dst[PRW_NAME_MAX], const char *src);

#ifdef __cplusplus
}
#endif
#endif
