/* render_internal — the renderer's state shared by its pass files.  Not a public header. */
#ifndef PRW_RENDER_INTERNAL_H
#define PRW_RENDER_INTERNAL_H

#include "prw_render.h"

#define PRW_MAX_LIGHTS 16
#define PRW_MAX_SHADOW_VIEWS 32

/* Resources named in pass declarations. */
enum {
    PRW_RES_SCENE = 1u << 0,  /* geometry, materials, lights (external) */
    PRW_RES_SHADOW = 1u << 1, /* shadow-map array */
    PRW_RES_HDR = 1u << 2,    /* per-view resolved HDR radiance */
    PRW_RES_LDR = 1u << 3,    /* per-view display-encoded image */
    PRW_RES_HDR_SS = 1u << 4, /* per-view supersampled HDR (N*W x N*H) */
    PRW_RES_TM_STATS = 1u << 5, /* tone-mapping frame statistics (pass_tonemap.c) */
};

/* std140 mirror of shaders/common.glsl */
typedef struct prw_gpu_light {
    float pos_type[4];
    float dir_range[4];
    float radiance[4];
    float cone_shadow[4];
    float axis_u[4];
    float axis_v[4];
    float shadow[4];
} prw_gpu_light;

typedef struct prw_gpu_globals {
    prw_mat4 view_proj;
    float eye_rel[4];
    float params[4];
    prw_gpu_light lights[PRW_MAX_LIGHTS];
    prw_mat4 shadow_mats[PRW_MAX_SHADOW_VIEWS];
} prw_gpu_globals;

typedef struct prw_gpu_material {
    float base_color[4];
    float emission[4];
    float mr[4];
    float extra[4]; /* x: specular */
} prw_gpu_material;

typedef struct prw_draw_mesh {
    uint32_t first_index, index_count;
    int32_t vertex_offset;
    int material;
} prw_draw_mesh;

typedef struct prw_shadow_view {
    int light;
    prw_dmat4 view_proj;   /* absolute world -> light clip */
    double texel_per_unit; /* shadow-map width in metres at unit distance (ortho: absolute); / size = texel */
} prw_shadow_view;

typedef struct prw_view_targets {
    prw_gpu_image msaa_color, depth, hdr, ldr;
    prw_gpu_image hdr_ss; /* supersampling only: the base pass renders here */
    prw_gpu_image extra_color; /* desc.extra_gpu_work > 0 only: pass_extra_work's scratch colour target */
    prw_buffer globals;   /* UPLOAD */
    VkDescriptorSet globals_set, downsample_set;
} prw_view_targets;

struct prw_frame_ctx {
    prw_renderer *r;
    const prw_view *views;
    uint32_t view_count;
    prw_dvec3 origin; /* camera-relative frame */
    uint64_t triangles;
    uint32_t draws;
    VkPipeline (*pipes)[2]; /* prw_base_record_draws: [double-sided][mirrored]; NULL = r->base_pipes */
};

struct prw_renderer {
    prw_gpu *gpu;
    const prw_scene *scene;
    prw_render_desc desc;
    VkSampleCountFlagBits samples;

    /* geometry */
    prw_buffer vertices, indices;
    prw_draw_mesh *meshes;
    uint32_t mesh_count;
    /* Rect lights are drawn as emissive quads (their visible surface): one unit quad in the
     * geometry buffers, one material slot per rect light after the scene's materials. */
    prw_draw_mesh light_quad;
    uint32_t scene_material_slots; /* max(1, scene material count) */

    /* materials and textures */
    prw_gpu_image *textures;
    uint32_t texture_count;
    prw_gpu_image white_srgb, white_linear, flat_normal;
    prw_buffer material_ubo;
    VkDeviceSize material_stride;
    VkDescriptorSet *material_sets;

    /* shadows */
    prw_shadow_view shadow_views[PRW_MAX_SHADOW_VIEWS];
    int light_first_shadow[PRW_MAX_LIGHTS];
    uint32_t shadow_view_count;
    prw_gpu_image shadow_map;

    prw_view_targets views[PRW_MAX_VIEWS];

    /* downsample binds two storage images (set layout `tonemap_layout`, named for its first user) */
    VkDescriptorSetLayout globals_layout, material_layout, tonemap_layout;
    VkPipelineLayout base_layout, shadow_layout, storage2_layout_pl;
    /* base pipelines by [double-sided][mirrored]: nodes with a negative determinant flip the winding */
    VkPipeline base_pipes[2][2], shadow_pipe, downsample_pipe;
    prw_desc_pool *pool;
    prw_timer *timer;

    prw_pass_graph graph;
    prw_frame_stats last;

    struct prw_tm_gpu *tm; /* display-aware tone mapping state (pass_tonemap.c) */
    struct prw_mv_state *mv; /* multiview backend (pass_multiview.c); NULL with the per-view loop */
    struct prw_lod_scene *lod; /* NURBS models with per-frame LOD (lod_scene.c); NULL without */
    struct prw_reproj_state *rp; /* stereo_reuse=reproject (pass_reproject.c); NULL when off */
};

/* The pass table (pass_shadow.c, pass_base.c, pass_tonemap.c). */
extern const prw_pass prw_pass_shadow;
extern const prw_pass prw_pass_base;
extern const prw_pass prw_pass_tonemap;
extern const prw_pass prw_pass_tm_stats; /* tone-mapping statistics, once for all views */
/* Tone-mapping pipelines, per-view signal images and descriptor sets (pass_tonemap.c); after the
 * view targets exist.  destroy is safe on a partly created state. */
bool prw_tm_gpu_create(prw_renderer *r, prw_error *e);
void prw_tm_gpu_destroy(prw_renderer *r);
extern const prw_pass prw_pass_downsample;
extern const prw_pass prw_pass_extra_work; /* in the graph only when desc.extra_gpu_work > 0 */

/* The base pass's draws for view vi inside an open rendering scope (pass_base.c; the caller binds
 * nothing and sets viewport/scissor).  Counts triangles and draws into ctx. */
void prw_base_record_draws(prw_frame_ctx *ctx, uint32_t vi, VkCommandBuffer cmd);
/* The camera-relative origin of view vi's draws (pass_base.c): the view's own eye (issue 5). */
prw_dvec3 prw_render_view_origin(const prw_frame_ctx *ctx, uint32_t vi);
/* Multiview backend (pass_multiview.c): layered targets, pipelines with view mask 0b11 (after the
 * view targets exist); destroy is safe on a partly created state.  The base pass calls
 * prw_mv_record_base for frames of 2 views when r->mv exists. */
bool prw_mv_create(prw_renderer *r, prw_error *e);
void prw_mv_destroy(prw_renderer *r);
bool prw_mv_record_base(prw_frame_ctx *ctx, VkCommandBuffer cmd, prw_error *e);
/* stereo_reuse=reproject (pass_reproject.c): targets and pipelines (after the view targets exist; nothing
 * when off or max_views < 2; fails for multiview); destroy is safe on a partly created state.  The base
 * pass calls prw_reproj_record_base for frames of 2 views when r->rp exists. */
bool prw_reproj_create(prw_renderer *r, prw_error *e);
void prw_reproj_destroy(prw_renderer *r);
bool prw_reproj_record_base(prw_frame_ctx *ctx, VkCommandBuffer cmd, prw_error *e);
/* NURBS LOD draws (lod_draw.c): inside the base pass's rendering scope (pipes: [double-sided][mirrored],
 * *bound: the pipeline bound last) and inside shadow view `shadow_view`'s scope. */
void prw_lod_record_base(prw_frame_ctx *ctx, uint32_t vi, VkCommandBuffer cmd, VkPipeline (*pipes)[2],
                         VkPipeline *bound);
void prw_lod_record_shadow(prw_renderer *r, uint32_t shadow_view, VkCommandBuffer cmd);
/* The base pass's push constants (112 bytes: model matrix relative to origin, normal matrix, mirror flag). */
void prw_base_push_constants(prw_dmat4 world, prw_dvec3 origin, float out[28]);
/* The base pass's pipeline description (vertex layout, HDR colour, depth, the renderer's samples,
 * back-face culling, depth test and write) for a pipeline layout; callers change what differs. */
prw_graphics_desc prw_base_graphics_desc(const prw_renderer *r, VkPipelineLayout layout);
/* View vi's globals (pass_base.c), relative to prw_render_view_origin(ctx, vi). */
void prw_base_fill_globals(const prw_frame_ctx *ctx, uint32_t vi, prw_gpu_globals *g);

/* Helpers shared by passes (renderer.c). */
prw_mat4 prw_render_rel_model(prw_dmat4 world, prw_dvec3 origin);
void prw_render_node_draws(const prw_renderer *r, uint32_t node, uint32_t *first, uint32_t *count);
/* Shadow views for the scene's lights (absolute, double), computed from the scene's bounds. */
uint32_t prw_render_plan_shadows(const prw_scene *s, prw_shadow_view *out, int *light_first);

#endif
