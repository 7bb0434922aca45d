/* prw_pass — how a pass of the render graph is written (DESIGN.md §4, engine/render/README.md).
 *
 * A pass is one file exporting one `const prw_pass` (a tone-mapping pair may share a file).  The graph
 * (graph.h) calls, in this order:
 *   setup(s)        at graph build: declares the images the pass creates (format, size class,
 *                   samples, per view or shared) and every use it makes of a resource (colour or
 *                   depth attachment, additive into radiance, resolve target, sampled, storage,
 *                   transfer, host read).  It may call prw_setup_skip(s, why) to stay out of the graph
 *                   for this scene and configuration (e.g. no mirror in the scene).
 *   create(...)     after the graph allocated its resources: the pass's own state (pipelines,
 *                   descriptor sets naming graph images, buffers).  destroy(...) undoes it and is safe
 *                   on a partly created state.
 *   needed(c, why)  per frame: false (with a one-line reason) skips the pass.  A skipped or culled
 *                   pass records nothing: no render-pass begin, barrier or timestamp.
 *   record(c, e)    per frame (scope FRAME) or once per view (scope VIEW, c->view set).  The graph has
 *                   already recorded the barriers and layout transitions for every declared use;
 *                   the pass only orders dispatches inside itself (prw_pass_barrier).
 * Promises of the graph to a pass: every image it declared or used exists with the union of the
 * usages all passes declared; the pass never reaches into the renderer — what it may touch is in
 * prw_render_env (the scene's GPU data, drawables, pipelines, shadow plan, tone-mapping service) and
 * in the frame (views, per-view globals).  Culling: a pass none of whose outputs is read by a live
 * pass, exported, or flagged PRW_PASS_KEEP does not run.
 */
#ifndef PRW_PASS_H
#define PRW_PASS_H

#include "prw_draw.h"
#include "prw_gpu.h"
#include "prw_render.h"
#include "prw_scene.h"
#include "prw_view.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct prw_graph prw_graph;
typedef struct prw_setup prw_setup;

typedef enum prw_pass_scope {
    PRW_SCOPE_FRAME = 0, /* once per frame for the whole view set */
    PRW_SCOPE_VIEW = 1,  /* once per view */
} prw_pass_scope;

/* What kind of work a pass submits: decides how `--pass-times` times it (GPU timestamps for graphics
 * passes; the host clock around a separately submitted command buffer for compute passes, whose
 * dispatches lavapipe's timestamps do not time). */
typedef enum prw_pass_queue {
    PRW_QUEUE_GRAPHICS = 0,
    PRW_QUEUE_COMPUTE = 1,
    /* A host stage: the graph submits and waits for everything recorded before it, then calls record()
     * with cmd = VK_NULL_HANDLE; the pass works on the CPU (reading back and uploading graph images
     * through engine/gpu) and the frame continues in a new command buffer.  Timed by the host clock.
     * Only prw_renderer_render can run one (prw_renderer_record skips it, with the reason). */
    PRW_QUEUE_HOST = 2,
} prw_pass_queue;

enum {
    PRW_PASS_KEEP = 1u << 0, /* never culled: the pass has an effect nobody reads (test knobs) */
    PRW_PASS_RADIANCE = 1u << 1, /* writes HDR radiance before tone mapping (not a shadow map): the
                                    passes summed as "base ms" against the floor (pass_floor.c) */
};

/* Size classes of graph images. */
typedef enum prw_size_class {
    PRW_SIZE_VIEW = 0,  /* the output size of a view: width x height */
    PRW_SIZE_INTERNAL,  /* the base pass's size: view x supersample */
    PRW_SIZE_SCALED,    /* internal x decl.scale */
    PRW_SIZE_SHADOW,    /* shadow_size^2 with one layer per planned shadow view (at least 1) */
    PRW_SIZE_FIXED,     /* decl.width x decl.height */
} prw_size_class;

typedef struct prw_image_decl {
    VkFormat format;
    prw_size_class size;
    uint32_t width, height; /* PRW_SIZE_FIXED */
    uint32_t scale;         /* PRW_SIZE_SCALED (>= 1) */
    uint32_t layers;        /* 0 -> 1 (PRW_SIZE_SHADOW: the plan's count) */
    bool msaa;              /* the renderer's sample count; else single-sample */
    bool shared;            /* one image for the whole frame; else one per view */
    bool transient;         /* content never needed after the pass (MSAA colour) */
    bool clear_at_create;   /* cleared once at allocation (colour 0 / depth 0) and left SHADER_READ_ONLY,
                               so readers see defined content even when the writer never runs */
    VkImageUsageFlags usage; /* added to the declared uses' usages: a pass that writes the image in one of
                                two ways (tone mapping: storage or colour attachment) declares the common
                                one as its use and changes the layout itself for the other */
} prw_image_decl;

/* Uses of a resource by a pass; each maps to a layout, pipeline stages and accesses. */
typedef enum prw_use {
    PRW_USE_COLOR = 0,    /* colour attachment written (cleared or overwritten) */
    PRW_USE_COLOR_ADD,    /* colour attachment loaded and added to: additive into radiance */
    PRW_USE_RESOLVE,      /* resolve target of a multisampled colour attachment */
    PRW_USE_DEPTH,        /* depth (and stencil) attachment, tested and written */
    PRW_USE_DEPTH_TEST,   /* depth attachment, tested only */
    PRW_USE_SAMPLED,      /* sampled by fragment or compute shaders */
    PRW_USE_STORAGE_READ, /* storage image / buffer, read by shaders */
    PRW_USE_STORAGE_WRITE,/* storage image / buffer, written (and read) by shaders */
    PRW_USE_TRANSFER_SRC,
    PRW_USE_TRANSFER_DST,
    PRW_USE_INDIRECT,     /* buffer: indirect dispatch / draw arguments */
    PRW_USE_HOST_READ,    /* buffer: read by the host after the frame */
    PRW_USE_COUNT
} prw_use;
const char *prw_use_name(prw_use u);
bool prw_use_writes(prw_use u);

typedef enum prw_frame_mode {
    PRW_FRAME_LOOP = 0,   /* every view rendered by the per-view passes */
    PRW_FRAME_MULTIVIEW,  /* two views drawn at once with view mask 0b11 (views backend multiview) */
    PRW_FRAME_REPROJECT,  /* two views; the right eye reuses the left's colour (stereo_reuse) */
} prw_frame_mode;

/* What every pass may use (owned by the renderer; read-only to passes). */
typedef struct prw_render_env {
    prw_gpu *gpu;
    const prw_scene *scene;
    const prw_render_desc *desc;  /* validated, defaults filled in */
    VkSampleCountFlagBits samples;
    struct prw_scene_gpu *sg;     /* geometry, textures, material sets (scene_gpu.h) */
    struct prw_pipes *pipes;      /* layouts and the keyed pipeline cache (pipes.h) */
    const struct prw_shadow_plan *shadows; /* shadow views of the scene's lights (shadow_plan.h) */
    struct prw_tm_gpu *tm;        /* display-aware tone mapping (tonemap_gpu.h) */
    prw_desc_pool *pool;
    const prw_drawables *drawables;
    struct prw_lightmap_gpu *lm;  /* the light maps (lightmap_gpu.h); never NULL after create, lm->active
                                     false without */
} prw_render_env;

/* One frame as the passes see it. */
typedef struct prw_frame {
    const prw_view *views;
    uint32_t view_count;
    prw_frame_mode mode;
    prw_draw_view draw[PRW_MAX_VIEWS]; /* per view: camera-relative origin, globals set, ... */
    uint64_t triangles;                /* drawn by the passes that count (base, reproject) */
    uint32_t draws;
    double glare_pupil_mm;             /* the glare stage's pupil (0: no glare this frame) */
    int glare_psf_radius;              /* and its PSF radius, pixels */
} prw_frame;

typedef struct prw_pass_ctx {
    const prw_render_env *env;
    prw_frame *frame;
    prw_graph *graph;
    VkCommandBuffer cmd;
    void *state;   /* the pass's own (create) */
    uint32_t view; /* scope VIEW: the view being recorded; FRAME: 0 */
} prw_pass_ctx;

/* Arguments of create / destroy. */
typedef struct prw_pass_init {
    const prw_render_env *env;
    prw_graph *graph;
} prw_pass_init;

typedef struct prw_pass {
    const char *name;
    prw_pass_scope scope;
    prw_pass_queue queue;
    unsigned flags;
    void (*setup)(prw_setup *s);
    bool (*create)(const prw_pass_init *in, void **state, prw_error *e); /* NULL: no state */
    void (*destroy)(const prw_pass_init *in, void *state);
    /* NULL: always needed.  For scope VIEW, called with c->view set (per view). */
    bool (*needed)(const prw_pass_ctx *c, const char **why_not);
    bool (*record)(prw_pass_ctx *c, prw_error *e);
} prw_pass;

/* ---- setup ---- */
const prw_render_env *prw_setup_env(const prw_setup *s);
/* The pass stays out of the graph (reason shown by `prw info`). */
void prw_setup_skip(prw_setup *s, const char *reason);
/* Declares an image this pass creates; it must be used by the pass too (prw_setup_use). */
void prw_setup_image(prw_setup *s, const char *name, const prw_image_decl *d);
/* A created image that exists only when a live pass reads it (G-buffer attachments). */
void prw_setup_optional(prw_setup *s, const char *name);
/* A created image that exists exactly when the optional image `leader` does (its multisampled source). */
void prw_setup_optional_with(prw_setup *s, const char *name, const char *leader);
/* Declares a use of a resource; on a per-view resource from a FRAME pass: every view of the frame. */
void prw_setup_use(prw_setup *s, const char *name, prw_use use);
/* The same for one view's instance of a per-view resource. */
void prw_setup_use_view(prw_setup *s, const char *name, uint32_t view, prw_use use);
/* A buffer owned outside the graph (e.g. by the tone-mapping service) that passes share. */
void prw_setup_import_buffer(prw_setup *s, const char *name, VkBuffer buffer);
/* The renderer reads the resource after the frame (readback, presenting): its producers are live. */
void prw_setup_export(prw_setup *s, const char *name);

/* ---- create / record ---- */
/* The graph image `name` of view v (shared images: any v); NULL when absent (optional, skipped). */
prw_gpu_image *prw_graph_image(prw_graph *g, const char *name, uint32_t view);
/* Whether a pass that ran earlier in this frame wrote the resource. */
bool prw_graph_written(const prw_graph *g, const char *name);
static inline prw_gpu_image *prw_pass_image(const prw_pass_ctx *c, const char *name)
{
    return prw_graph_image(c->graph, name, c->view);
}
/* Counted render-pass begin / end and pass-internal barriers (each flushes on lavapipe; `prw info`
 * and the frame stats report the counts). */
void prw_pass_begin_rendering(const prw_pass_ctx *c, const VkRenderingInfo *ri);
void prw_pass_end_rendering(const prw_pass_ctx *c);
void prw_pass_barrier(const prw_pass_ctx *c, const VkDependencyInfo *d);
/* A layout change of an image the pass owns itself (not a graph image; counted). */
void prw_pass_transition(const prw_pass_ctx *c, prw_gpu_image *img, VkImageLayout layout);
/* A memory barrier between shader stages inside a pass (counted). */
void prw_pass_memory_barrier(const prw_pass_ctx *c, VkPipelineStageFlags2 src, VkAccessFlags2 src_access,
                             VkPipelineStageFlags2 dst, VkAccessFlags2 dst_access);

/* The standard pass table (passes.c), in order; NULL-terminated. */
extern const prw_pass *const prw_passes_default[];

#ifdef __cplusplus
}
#endif
#endif
