/* scene_gpu — the GPU copy of a scene: one interleaved vertex buffer (PRW_VERTEX_FLOATS floats per
 * vertex) and one index buffer for every mesh plus the rect-light quad, textures with mip chains, and
 * one uniform block + descriptor set (set 1 of the base layout) per material slot.
 *
 * Promises:
 *  - Material slots: the scene's materials (at least one: the default), then one per light, used by
 *    rect lights as their visible surface (emission = colour x intensity, black base colour).
 *  - The rect-light quad is a unit quad in the light's frame (x, y in [-1, 1], facing -Z) at the start
 *    of the buffers.
 *  - Read-only after create; the renderer re-creates it when the scene is synced.
 */
#ifndef PRW_SCENE_GPU_H
#define PRW_SCENE_GPU_H

#include "prw_gpu.h"
#include "prw_scene.h"

typedef struct prw_gpu_mesh {
    uint32_t first_index, index_count;
    int32_t vertex_offset;
    int material;
} prw_gpu_mesh;

typedef struct prw_scene_gpu {
    prw_buffer vertices, indices;
    prw_gpu_mesh *meshes;
    uint32_t mesh_count;
    prw_gpu_mesh light_quad;
    uint32_t scene_material_slots; /* max(1, scene material count); light slots follow */
    prw_gpu_image *textures;
    uint32_t texture_count;
    prw_gpu_image white_srgb, white_linear, flat_normal;
    prw_buffer material_ubo;
    VkDeviceSize material_stride;
    VkDescriptorSet *material_sets;
} prw_scene_gpu;

bool prw_scene_gpu_create(prw_gpu *gpu, const prw_scene *s, VkDescriptorSetLayout material_layout,
                          prw_desc_pool *pool, prw_scene_gpu **out, prw_error *e);
void prw_scene_gpu_destroy(prw_gpu *gpu, prw_scene_gpu *g);
/* The material slot of scene material index m (out of range: 0). */
uint32_t prw_scene_gpu_slot(const prw_scene *s, int m);

#endif
