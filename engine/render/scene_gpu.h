/* scene_gpu — the GPU copy of a scene: one interleaved vertex buffer (PRW_VERTEX_FLOATS floats per
 * vertex) and one index buffer for every mesh plus the rect-light quad, textures with mip chains, and
 * one uniform block + descriptor set (set 1 of the base layout) per material slot.
 *
 * Promises:
 *  - Material slots: the scene's materials (at least one: the default), then one per light, used by
 *    rect lights as their visible surface (emission = colour x intensity, black base colour).
 *  - The rect-light quad is a unit quad in the light's frame (x, y in [-1, 1], facing -Z) at the start
 *    of the buffers.
 *  - glTF extension features: each slot has flags (PRW_SG_*): EXT when the material needs the
 *    extension shaders (alpha MASK or BLEND, a texture read through a transform or from uv set 1, a
 *    clear coat), MASK / BLEND for its alpha mode; a material without EXT is drawn exactly as before.
 *    When a mesh has an EXT material, `uv1` holds uv set 1 for every vertex of the vertex buffer (same
 *    indexing; the vertex's set 0 where its mesh has no TEXCOORD_1, prw_shading.h), else it is not
 *    created.  Material slots' blocks carry the extension members and descriptor sets all seven
 *    textures (white / flat-normal fallbacks).  Each slot's flags also say which textures it lacks and
 *    whether its metallic is exactly 0 or 1 (PRW_SG_LACKS_SHIFT), and its block carries the GGX fits'
 *    rows at its factor roughness, so a pipeline specialised on them (PRW_PIPE_LACKS_SHIFT) draws it
 *    with the same values without those fetches.
 *  - BTF materials (PRW_MATERIAL_BTF): each file is read (errors name the scene, material and file) and
 *    packed once into `btf`; the slot's block holds the material's word offset (alpha.z, its bits) and
 *    1 / texel size (alpha.w) for base_btf.frag; its flags carry no extension feature.
 *  - Read-only after create; the renderer re-creates it when the scene is synced.
 */
#ifndef PRW_SCENE_GPU_H
#define PRW_SCENE_GPU_H

#include "prw_constants.h" /* PRW_GPU_MAT_* */
#include "prw_gpu.h"
#include "prw_scene.h"

typedef struct prw_gpu_mesh {
    uint32_t first_index, index_count;
    int32_t vertex_offset;
    int material;
} prw_gpu_mesh;

enum {
    PRW_SG_EXT = 1u,   /* drawn with the glTF-extension shaders (PRW_PIPE_EXT) */
    PRW_SG_MASK = 2u,  /* alpha MASK: cut out in the base pass and in the shadow pass */
    PRW_SG_BLEND = 4u, /* alpha BLEND: drawn by PRW_DRAW_BLEND, back to front, over the opaque image */
    PRW_SG_COAT = 8u,  /* a clear coat (PRW_PIPE_COAT) */
    PRW_SG_LACKS_SHIFT = 4, /* bits 4..: PRW_GPU_MAT_* (prw_constants.h), what the slot has no texture or lobe for */
};

typedef struct prw_scene_gpu {
    prw_buffer vertices, indices;
    prw_buffer uv1;          /* PRW_UV1_FLOATS per vertex; buffer VK_NULL_HANDLE when no mesh needs it */
    uint32_t *slot_flags;    /* PRW_SG_* per material slot */
    bool alpha_meshes;       /* a mesh or NURBS entry has a MASK or BLEND material */
    bool blend_meshes;       /* a mesh has a BLEND material */
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
    prw_buffer btf;          /* the BTF materials' words (prw_btf_gpu.h), set 1 binding 8 of every slot */
    VkBufferView btf_rgb;    /* the same words as 4 x 32-bit texels (prw_btf_gpu.h's RGB blocks), binding 9 */
    uint32_t btf_materials;  /* BTF files packed */
} prw_scene_gpu;

bool prw_scene_gpu_create(prw_gpu *gpu, const prw_scene *s, VkDescriptorSetLayout material_layout,
                          prw_desc_pool *pool, prw_scene_gpu **out, prw_error *e);
void prw_scene_gpu_destroy(prw_gpu *gpu, prw_scene_gpu *g);
/* PRW_GPU_MAT_* of m: the textures it does not have (absent, or an index past the scene's texture_count)
 * and whether its metallic is exactly 0 or 1. */
uint32_t prw_scene_gpu_material_lacks(const prw_material *m, uint32_t texture_count);
/* The material slot of scene material index m (out of range: 0). */
uint32_t prw_scene_gpu_slot(const prw_scene *s, int m);
/* Vertex v of mesh m in the GPU layout (PRW_VERTEX_FLOATS floats at d): position, normal, uv (0 when the
 * mesh has none), tangent ((1, 0, 0, 1) when none). */
void prw_scene_gpu_vertex(const prw_mesh *m, uint32_t v, float *d);
/* PRW_SG_* of a material (see the top). */
uint32_t prw_scene_gpu_material_flags(const prw_material *m);

#endif
