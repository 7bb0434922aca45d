/* pipes — the renderer's descriptor-set and pipeline layouts and its keyed pipeline cache.
 *
 * Promises:
 *  - One cache for every graphics pipeline a pass or drawable binds, keyed by (recipe, material kind,
 *    two-sided, mirrored, clip plane, view mask, variant, features, the scene's light classes); the base
 *    fragment shaders are specialised on the light classes (shadow_plan.h: light slots; lights.glsl), so a
 *    change of the lights' kinds or shadows builds new pipelines, and on what the draw's material slot
 *    lacks (features >> PRW_PIPE_LACKS_SHIFT, scene_gpu.h; not for the floor and depth pre-pass).  A
 *    pipeline is built on first use from its recipe and kept until the renderer is destroyed or its
 *    recipe is forgotten (a pass's destroy).
 *  - A recipe is a named description function plus its pipeline layout; the base recipe's description
 *    (vertex layout, HDR colour target, reversed-Z D32 depth, the renderer's samples, back-face
 *    culling) is the starting point of every recipe that draws the scene's drawables
 *    (prw_pipes_describe_base).
 *  - Layouts: set 0 = per-view globals (uniform block + the shadow atlas with its compare sampler
 *    (binding 1) and for gathers (binding 2, PRW_SAMPLER_SHADOW_DEPTH), the LTC table (binding 3), the
 *    light-map atlas (binding 4, lightmap_gpu.h), the environment light (bindings 5-7, prw_env_gpu.h), the
 *    reflection probes (bindings 8-10, prw_probe_gpu.h)), set 1 = material (uniform block
 *    + seven textures: base colour, metal-rough, normal, emissive, clear coat, its roughness, its
 *    normal; binding 8: the scene's BTF words, a storage buffer, prw_btf_gpu.h); the base layout has
 *    128 bytes of push constants (112 per draw: prw_draw_push_model; then the clip plane of
 *    PRW_CLIP_PLANE pipelines, pushed by the pass), the shadow layout 64 (the light clip matrix) and
 *    sets 0 (unused) and 1 (the material of cut-out casters).  The storage2 layout (two
 *    storage images, 12 bytes of push constants) serves the box-filter downsample.
 */
#ifndef PRW_PIPES_H
#define PRW_PIPES_H

#include "prw_pass.h"

typedef struct prw_pipe_key {
    const struct prw_pipe_recipe *recipe;
    uint32_t material_kind;
    uint32_t two_sided, mirrored, clip;
    uint32_t view_mask;
    uint32_t variant;
    uint32_t features; /* PRW_PIPE_* of the draw's material and drawable */
    uint32_t light_classes; /* set by prw_pipes_get: the shadow plan's class sizes, 5 bits each */
} prw_pipe_key;

/* Pipeline features of a draw (prw_pipe_key.features, prw_draw_bind_features); 0 is the core glTF
 * material with the shaders of before the glTF extensions. */
enum {
    PRW_PIPE_EXT = 1u,    /* the glTF-extension shaders (PRW_GLTF_EXT; scene_gpu.h PRW_SG_EXT); uv set 1 at
                             location 4 from binding 1 (PRW_UV1_FLOATS per vertex) */
    PRW_PIPE_NO_UV1 = 2u, /* with EXT or MASK: location 4 reads binding 0's uv (drawables without uv set 1) */
    PRW_PIPE_BLEND = 4u,  /* base recipe: "over" blending into the radiance, depth tested but not written, no
                             G-buffer writes (PRW_DRAW_BLEND draws) */
    PRW_PIPE_BACK = 8u,   /* with BLEND: front faces culled (a two-sided blended mesh: its far side first) */
    PRW_PIPE_MASK = 16u,  /* shadow recipe: the alpha-tested caster (shadow_mask.vert + mask.frag, material set 1) */
    PRW_PIPE_COAT = 32u,  /* with EXT: the clear-coated shaders (PRW_GLTF_COAT) */
    PRW_PIPE_GI = 1u << 16, /* base recipe (and the clip-plane draws of a lightmapped recipe), plain / pre-pass /
                               EQUAL variants, not COAT or BLEND: the light-map shaders (PRW_GI:
                               gi_lightmap.glsl), bindings 0-2 of lightmap_gpu.h */
    PRW_PIPE_LACKS_SHIFT = 6, /* bits 6..: PRW_GPU_MAT_* (prw_constants.h), the base shaders' PRW_SC_MAT: what
                                 the material slot has no texture or lobe for (scene_gpu.h) */
    /* PRW_PIPE_MASK in the base recipe: the material is alpha-tested (its fragments may be discarded) */
};

typedef struct prw_pipe_recipe {
    const char *name;
    VkPipelineLayout layout;
    /* Fills d for key k (d arrives zeroed); false with e set when the key is impossible. */
    bool (*describe)(const struct prw_pipe_recipe *r, const prw_render_env *env, const prw_pipe_key *k,
                     prw_graphics_desc *d, prw_error *e);
    const void *user;
    bool lightmapped; /* its colour draws of light-mapped meshes use the light-map shaders (PRW_PIPE_GI):
                         the base recipe and those drawing the scene as the base pass does (the mirror's) */
} prw_pipe_recipe;

typedef struct prw_pipes {
    prw_gpu *gpu;
    const prw_render_env *env;
    VkDescriptorSetLayout globals_layout, material_layout, storage2_layout;
    VkPipelineLayout base_layout, shadow_layout, storage2_pl;
    prw_pipe_recipe base, shadow; /* the standard recipes */
    prw_pipe_recipe sky;          /* the environment's background (sky.vert/.frag; variant GBUFFER: the G-buffer
                                     outputs too), drawn by pass_base where nothing else is (prw_env_gpu.h) */
    VkPipeline downsample;        /* compute: N x N box filter (storage2 layout) */
    prw_pipeline_table *table;
    prw_gpu_image ltc;            /* the rect lights' LTC table (materials/prw_ltc.h), set 0 binding 3 */
    VkImageView lightmap_atlas;   /* set 0 binding 4 (lightmap_gpu.h; a black layer without light maps): set
                                     by the renderer before any globals set is written */
    const struct prw_env_gpu *envlight; /* set 0 bindings 5-7 (prw_env_gpu.h), set like lightmap_atlas; its
                                           `active` specialises the base shaders (PRW_SC_ENV) */
    const struct prw_probe_gpu *probes; /* set 0 bindings 8-10 (prw_probe_gpu.h), set like envlight; its `active`
                                           specialises the base shaders (PRW_SC_PROBES) */
} prw_pipes;

bool prw_pipes_create(const prw_render_env *env, prw_pipes **out, prw_error *e);
void prw_pipes_destroy(prw_pipes *p);
/* Writes the bindings of a globals set (globals_layout) that the pipes own: binding 3, the LTC table, and
 * binding 4, the light-map atlas.
 * Every globals set a base pipeline is drawn with needs it (bindings 0-2 are the caller's). */
void prw_pipes_write_globals(const prw_pipes *p, VkDescriptorSet set);
/* The pipeline for k (built on first use). */
bool prw_pipes_get(prw_pipes *p, const prw_pipe_key *k, VkPipeline *out, prw_error *e);
/* Destroys every pipeline built from recipe r. */
void prw_pipes_forget(prw_pipes *p, const prw_pipe_recipe *r);
/* The base recipe's description for key k with another layout (recipes derived from it). */
bool prw_pipes_describe_base(const prw_render_env *env, const prw_pipe_key *k, VkPipelineLayout layout,
                             prw_graphics_desc *d, prw_error *e);

/* The base pass's attachments (pass_base.c, and pass_floor.c, which must set up the same):
 * colour: cleared to (0, 0, 0, clear_alpha); with a resolve image (MSAA) resolved by `mode`, itself not
 * stored; without, stored.  Depth: cleared to 0 (reversed Z), stored. */
VkRenderingAttachmentInfo prw_pipes_color_attachment(prw_gpu_image *img, prw_gpu_image *resolve,
                                                     VkResolveModeFlagBits mode, float clear_alpha);
VkRenderingAttachmentInfo prw_pipes_depth_attachment(prw_gpu_image *depth);

/* Formats of the graph images every pass agrees on.  Radiance: float32 or half by the knob radiance_bits. */
static inline VkFormat prw_pipes_radiance_format(const prw_render_env *env)
{
    return env->desc->quality.radiance_bits == 16 ? VK_FORMAT_R16G16B16A16_SFLOAT : VK_FORMAT_R32G32B32A32_SFLOAT;
}
#define PRW_DEPTH_FORMAT VK_FORMAT_D32_SFLOAT
#define PRW_NORMAL_FORMAT VK_FORMAT_R16G16B16A16_SFLOAT /* G-buffer: camera-relative normal, roughness */
#define PRW_MATID_FORMAT VK_FORMAT_R32_UINT            /* G-buffer: material slot + 1 (0: nothing drawn) */

/* Recipe variants of the base recipe. */
enum {
    PRW_BASE_VARIANT_PLAIN = 0,
    PRW_BASE_VARIANT_GBUFFER = 1, /* + normal/roughness and material-id colour outputs */
    PRW_BASE_VARIANT_FLOOR = 2,   /* the base pipeline with floor.frag: a constant colour (pass_floor.c) */
    PRW_BASE_VARIANT_FLOOR_GBUFFER = 3, /* the same with the G-buffer outputs */
    PRW_BASE_VARIANT_PREPASS = 4, /* depth pre-pass: no fragment shader, no colour writes; alpha-tested
                                     (PRW_PIPE_MASK) draws write no depth either (they are left to the shading
                                     draws) */
    PRW_BASE_VARIANT_EQUAL = 5,   /* shading after the pre-pass: depth EQUAL, not written (PRW_PIPE_MASK draws:
                                     the plain state) */
    PRW_BASE_VARIANT_EQUAL_GBUFFER = 6, /* the same with the G-buffer outputs */
    PRW_BASE_VARIANT_PREPASS_GBUFFER = 7, /* the pre-pass in a rendering with the G-buffer attachments */
};

#endif
