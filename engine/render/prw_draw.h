/* prw_draw — drawables: what is drawn, separate from which pass draws it (DESIGN.md §4).
 *
 * A drawable is one geometry kind (scene meshes, rect-light quads, NURBS LOD, later mesh LOD and
 * billboard clouds), one file exporting a `const prw_drawable`, plus one line in the drawable table
 * (drawables.c).  Passes (base, shadow, depth pre-pass, mirror, reprojection) open a rendering scope
 * and call prw_drawables_record() with a draw context; they never know the geometry kinds.
 *
 * The draw context carries:
 *  - the kind of draw: COLOR (shaded: push constants model + normal matrix, material set 1),
 *    BLEND (the same for surfaces blended over the image: glTF alpha BLEND; a pass that draws COLOR
 *    records BLEND after it in the same rendering scope, when prw_drawables_have(BLEND); drawables
 *    draw them back to front and leave them out of COLOR), DEPTH (the same vertex stage, no material),
 *    SHADOW (light clip matrix as push constant; cut-out casters bind their material set 1);
 *  - the view: camera-relative origin, globals set 0, whether it is mirrored (winding flips) and a
 *    user clip plane (camera-relative; drawn with the clip-plane shader variant);
 *  - the pipeline recipe of the pass; pipelines come from the keyed cache (pipes.h) by
 *    (recipe, material kind, sidedness, mirroring, view mask, clip, variant).
 * Drawables count triangles and draw calls into the context.
 * Promises: a drawable binds its own vertex/index buffers; it binds a pipeline only through
 * prw_draw_bind (so set 0 is bound with it); it draws nothing for a kind it has no geometry for.
 */
#ifndef PRW_DRAW_H
#define PRW_DRAW_H

#include "prw_gpu.h"
#include "prw_math.h"
#include "prw_view.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum prw_draw_kind {
    PRW_DRAW_COLOR = 0,
    PRW_DRAW_DEPTH,
    PRW_DRAW_SHADOW,
    PRW_DRAW_BLEND,
} prw_draw_kind;

typedef struct prw_draw_view {
    prw_dvec3 origin;      /* draws are relative to this point (camera-relative rendering) */
    prw_dvec3 eye;         /* sorting (nearest first) */
    VkDescriptorSet globals; /* set 0 of COLOR / DEPTH draws */
    bool mirrored;         /* a reflected view: front faces flip */
    bool clip;             /* user clip plane on (gl_ClipDistance[0] = dot(plane, (p, 1))) */
    float clip_plane[4];   /* camera-relative */
    prw_dmat4 shadow_view_proj; /* SHADOW: absolute world -> light clip */
} prw_draw_view;

struct prw_pipes;
struct prw_pipe_recipe;
struct prw_scene_gpu;

typedef struct prw_draw_ctx {
    VkCommandBuffer cmd;
    prw_draw_kind kind;
    const prw_draw_view *view;
    struct prw_pipes *pipes;
    const struct prw_pipe_recipe *recipe;
    uint32_t view_mask; /* multiview; 0 = off */
    uint32_t variant;   /* recipe-specific (e.g. reprojection stage) */
    const struct prw_scene_gpu *sg;
    VkPipelineLayout layout; /* the recipe's: push constants and material sets bind through it */
    VkPipeline bound;
    bool depth_bias;    /* SHADOW: set (bias_constant, bias_slope) whenever a pipeline with depth bias is bound */
    float bias_constant, bias_slope;
    bool failed;        /* a pipeline could not be built (error in err) */
    prw_error err;
    uint64_t triangles;
    uint32_t draws;
} prw_draw_ctx;

/* Binds the pipeline for (material kind, sidedness, node mirrored) in this context — and set 0 (the
 * view's globals) with it when it changes.  Returns false (ctx->failed, ctx->err) when the pipeline
 * cannot be built; the caller then skips the draw. */
bool prw_draw_bind(prw_draw_ctx *c, uint32_t material_kind, bool two_sided, bool node_mirrored);
/* The same with pipeline features (pipes.h PRW_PIPE_*: the glTF-extension shaders, blending, cut-out
 * shadow casters); prw_draw_bind is features 0. */
bool prw_draw_bind_features(prw_draw_ctx *c, uint32_t material_kind, uint32_t features, bool two_sided,
                            bool node_mirrored);
/* The features a draw of material slot `slot` needs in this context (from scene_gpu.h's slot flags and
 * the draw kind); uv1: the drawable binds the scene's uv set 1 stream (else PRW_PIPE_NO_UV1). */
uint32_t prw_draw_features(const prw_draw_ctx *c, uint32_t slot, bool uv1);
/* The base pass's push constants for a node (112 bytes: model relative to origin, normal matrix,
 * mirrored flag in normal_m[0].w): float out[28]. */
void prw_draw_push_model(prw_dmat4 world, prw_dvec3 origin, float out[28]);
/* Whether world has a negative determinant (a mirroring node). */
bool prw_draw_mirrors(prw_dmat4 world);

typedef struct prw_render_env prw_render_env;

typedef struct prw_drawable {
    const char *name;
    bool (*create)(const prw_render_env *env, void **state, prw_error *e); /* NULL: no state */
    void (*destroy)(const prw_render_env *env, void *state);
    /* Per frame, before any pass records: LOD selection, buffer updates for the view set. */
    bool (*update)(void *state, const prw_render_env *env, const prw_view *views, uint32_t count, prw_error *e);
    void (*record)(void *state, const prw_render_env *env, prw_draw_ctx *c);
    /* Whether it has anything to draw for `kind` (e.g. shadow casters). */
    bool (*has)(const void *state, const prw_render_env *env, prw_draw_kind kind);
} prw_drawable;

/* The renderer's drawables: the table (drawables.c) with their states. */
#define PRW_MAX_DRAWABLES 16
typedef struct prw_drawables {
    const prw_drawable *kind[PRW_MAX_DRAWABLES];
    void *state[PRW_MAX_DRAWABLES];
    uint32_t count;
} prw_drawables;

extern const prw_drawable *const prw_drawables_default[]; /* NULL-terminated */

bool prw_drawables_create(prw_drawables *d, const prw_drawable *const *table, const prw_render_env *env,
                          prw_error *e);
void prw_drawables_destroy(prw_drawables *d, const prw_render_env *env);
bool prw_drawables_update(prw_drawables *d, const prw_render_env *env, const prw_view *views, uint32_t count,
                          prw_error *e);
/* Every drawable, in table order, into the open rendering scope. */
void prw_drawables_record(const prw_drawables *d, const prw_render_env *env, prw_draw_ctx *c);
bool prw_drawables_have(const prw_drawables *d, const prw_render_env *env, prw_draw_kind kind);
/* The state of the drawable named `name` (NULL when absent). */
void *prw_drawables_state(const prw_drawables *d, const char *name);

#ifdef __cplusplus
}
#endif
#endif
