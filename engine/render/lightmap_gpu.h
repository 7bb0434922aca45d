/* lightmap_gpu — the GPU copy of the light maps (prw_lightmap.h): the atlases as one RGBA32F 2-D array
 * (one layer per atlas, the largest atlas's size; uvs rescaled to it), and the light-mapped instances'
 * drawn vertices (copies of their mesh's, split where the light-map uv differs per corner) in buffers
 * of their own: the vertex layout of scene_gpu (binding 0), uv set 1 (binding 1, always present) and
 * the light-map stream (binding 2, PRW_LIGHTMAP_STREAM_FLOATS per vertex: ATLAS (u, v, layer, 0),
 * VERTEX (E_ind, 1 + environment visibility); then the VERTEX open cone (b, f), (0, 0, 0, -1) for ATLAS
 * or none); the atlas texels are (E_ind, environment visibility);
 * layers atlas_count + i hold atlas i's open cones (b, f), (0, 0, 0, -1) where it has none.
 *
 * Promises:
 *  - Without light maps (NULL or no instance with a mode) `active` is false, no buffer exists and the
 *    atlas is a 1 x 1 black layer (set 0 binding 4 of every globals set must name an image).
 *  - prw_lightmap_gpu_draw gives the draw range of (node, mesh) when it is light-mapped.
 *  - The input is checked (prw_lightmap.h's promises); an error names the instance or atlas.
 */
#ifndef PRW_LIGHTMAP_GPU_H
#define PRW_LIGHTMAP_GPU_H

#include "prw_gpu.h"
#include "prw_lightmap.h"
#include "prw_scene.h"
#include "scene_gpu.h"

#define PRW_LIGHTMAP_STREAM_FLOATS 8

typedef struct prw_lightmap_gpu {
    bool active;
    prw_gpu_image atlas;
    prw_buffer vertices, uv1, stream, indices;
    prw_gpu_mesh *draws;  /* per light-mapped instance: range in the buffers above */
    int32_t *draw_of;     /* per (node, mesh of its group), node_first[node] + (mesh - group first): index into
                             draws, -1 when not light-mapped */
    uint32_t *node_first;
    uint32_t node_count, slot_count; /* of the scene at create (a later edit of the scene is not light-mapped) */
    uint32_t instance_count;
} prw_lightmap_gpu;

bool prw_lightmap_gpu_create(prw_gpu *gpu, const prw_scene *s, const prw_lightmaps *lm, prw_lightmap_gpu **out,
                             prw_error *e);
void prw_lightmap_gpu_destroy(prw_gpu *gpu, prw_lightmap_gpu *g);
/* The draw of mesh `mesh` (a scene mesh index in node's group) of node `node`, or NULL. */
const prw_gpu_mesh *prw_lightmap_gpu_draw(const prw_lightmap_gpu *g, const prw_scene *s, uint32_t node, uint32_t mesh);

#endif
