/* prw_render — draws a prw_scene for a view set with the pass graph of DESIGN.md §4.
 *
 * Promises:
 *  - Output per view: linear HDR radiance in cd/m^2 (RGBA16F, 4x MSAA resolved in linear HDR by
 *    averaging samples) and the display signal from display-aware tone mapping (prw_tonemap.h) as
 *    float (prw_renderer_read_signal) and 8-bit; by default the "srgb" display with the exposure
 *    operator, identical to the former provisional tone map (exposure from EV100, clamp, sRGB OETF).
 *  - Passes: "shadow" (once per frame for all views: one depth layer per spot/rect/directional light,
 *    six per point light), "base" (per view: emission + shadowed direct light), "downsample" (only
 *    with N x N supersampling: box filter to the output size), "tm_stats" (once for all views: frame
 *    log-average and largest luminance; only when the operator or pixel classification needs it),
 *    "tonemap" (per view).
 *    A pass whose needed() is false records nothing.
 *  - stereo_reuse = reproject (two-view frames, per-view loop): the base pass shades the left eye as a mono
 *    render and reuses its colour in the right eye where the left eye saw the same surface (pass_reproject.c);
 *    the right eye's pixels change (FLIP reported by `prw bench --views 2`), the left eye's do not.
 *  - Rect lights are drawn as one-sided emissive quads (their visible surface); a scene should not
 *    add a separate emissive mesh for them (the reference counts emissive meshes as emitters too).
 *  - Camera-relative rendering: world transforms stay double on the CPU; the GPU gets matrices
 *    relative to each view's own eye, so a scene 1e5 m from the origin renders like one at it, and
 *    each eye of a view set is bit-identical to a mono render from that eye (issue 5; shadow maps
 *    are built from absolute double matrices, so they do not depend on the views at all).
 *  - The renderer uploads the scene at create; after editing the scene call prw_renderer_sync_scene(),
 *    which uploads it again and rebuilds the pass graph (so a pass that depends on the scene's features
 *    joins or leaves the graph).
 *  - The pass graph (graph.h, prw_pass.h) orders the passes, allocates their images, derives every
 *    barrier and culls what no one reads; prw_renderer_describe prints it.
 */
#ifndef PRW_RENDER_H
#define PRW_RENDER_H

#include "prw_gpu.h"
#include "prw_hmd.h"
#include "prw_emissive.h"
#include "prw_image.h"
#include "prw_lightmap.h"
#include "prw_quality.h"
#include "prw_scene.h"
#include "prw_tonemap.h"
#include "prw_view.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PRW_MAX_VIEWS 6
#define PRW_MAX_PASSES 32

struct prw_pass;

/* Test-only switches (never set by the app's commands). */
typedef struct prw_render_debug {
    double reproject_tolerance; /* reproject: relative depth agreement; 0 -> 0.01; < 0 reuses nothing */
    bool reproject_mark;        /* reproject: reused samples get alpha 0 in the right eye's HDR image and the
                                   clear alpha is 0 (resolved alpha = fraction of the pixel's samples shaded
                                   by the right eye) */
    const struct prw_pass *const *passes; /* NULL-terminated pass table; NULL: the standard one (passes.c) */
    const char *const *exports;           /* NULL-terminated names of graph images to keep for
                                             prw_renderer_read_image (e.g. "depth", "gbuf_normal") */
} prw_render_debug;

typedef struct prw_renderer prw_renderer;

/* Backends of the per-view passes (DESIGN.md §6): one pass per view, or Vulkan multiview. */
typedef enum prw_views_backend {
    PRW_VIEWS_LOOP = 0,      /* per-view loop: each eye bit-identical to a mono render from it */
    PRW_VIEWS_MULTIVIEW = 1, /* view mask 0b11, layered targets, gl_ViewIndex selects the view */
} prw_views_backend;


typedef struct prw_render_desc {
    uint32_t width, height;  /* per view */
    uint32_t max_views;      /* 0 -> 1 */
    bool timestamps;         /* per-pass times (each timestamp flushes on lavapipe) */
    prw_views_backend views_backend; /* per-view passes; 0 = loop (issue 5) */
    prw_quality quality;     /* the knobs (prw_quality.h); all zero -> prw_quality_default(), otherwise it must
                                pass prw_quality_validate.  msaa, shadow_size, supersample, tonemap (the
                                initial operator on the srgb display), stereo_reuse (frames of exactly 2 views
                                on a renderer with max_views >= 2), lod_pixel_tolerance and the hidden test
                                knob extra_gpu_work (pass_extra_work.c) are used */
    const prw_compose_params *compose; /* two-view frames are also composed into one panel (HMD pre-distortion or
                                          side by side, prw_hmd.h): the graph images "panel_hdr" and
                                          "panel_signal" (prw_renderer_read_image); NULL: none; copied */
    const struct prw_glare_settings *glare; /* temporal glare (prw_glare.h) on the display outputs: a host stage
                                               after the radiance, whose glared copy "hdr_glare" the tone
                                               mapping reads; the "hdr" images stay unglared; NULL: none;
                                               copied (needs kissfft) */
    const prw_render_debug *debug; /* NULL: none; copied at create (its passes / exports arrays are not: they
                                      must outlive the renderer) */
    const struct prw_lightmaps *lightmaps; /* baked indirect diffuse (prw_lightmap.h): the light-mapped instances
                                              are drawn with the light-map shaders; NULL: none (the shaders of
                                              before).  Read at create only (copied to the GPU) */
    const struct prw_env_data *environment; /* the scene's environment light (materials/env/prw_env_file.h,
                                               prw_env_gpu.h): the base shaders add the environment term;
                                               NULL: none (the shaders of before).  Read at create only */
    const struct prw_probes *probes; /* reflection probes (prw_probe_gpu.h): the base shaders add the probe term on
                                        their objects; NULL: none (the shaders of before).  Read at create only */
    uint32_t terms;      /* PRW_TERM_* bits (prw_constants.h) the base shaders draw; 0 = all (emission, direct light,
                            the light maps' indirect diffuse) */
    bool display_signal; /* keep the float display signal of every view for prw_renderer_read_signal (HDR10
                            PNGs, display-referred EXRs, metrics on the signal); otherwise the tone mapping
                            writes it only when a pass reads it (HMD composition) and the 8-bit image alone */
} prw_render_desc;

typedef struct prw_pass_stat {
    const char *name;
    bool skipped;
    char reason[96];       /* skipped: why (not needed this frame, or culled) */
    double gpu_ms;         /* < 0 when not timed: GPU timestamps (graphics passes) or the host clock around
                              the pass's own submission (compute passes) */
    bool host_clock;       /* gpu_ms is the host clock around the pass's own submission */
    uint32_t flags;        /* the pass's PRW_PASS_* flags (prw_pass.h), e.g. PRW_PASS_RADIANCE */
    uint32_t timer_scope;  /* internal */
} prw_pass_stat;

typedef struct prw_frame_stats {
    uint32_t pass_count;
    prw_pass_stat passes[PRW_MAX_PASSES];
    double cpu_ms;       /* recording + submit + wait, measured on the CPU */
    uint64_t triangles;  /* drawn in the base pass, all views */
    uint32_t draws;
    uint32_t barriers;   /* barrier commands recorded (each flushes on lavapipe) */
    uint32_t begins;     /* render-pass begins recorded */
    double glare_pupil_mm; /* with glare: the pupil diameter used (mm); 0 otherwise */
    int glare_psf_radius;  /* and the PSF radius, pixels */
} prw_frame_stats;

/* The base passes' time and the floor's of one timestamped frame (pass_floor.c): base = the sum over
 * the timed passes flagged PRW_PASS_RADIANCE (every pass writing HDR radiance before tone mapping,
 * shadow maps excluded), floor = the "floor" pass.  false when the frame has no timed floor. */
bool prw_frame_stats_base_floor(const prw_frame_stats *st, double *base_ms, double *floor_ms);

bool prw_renderer_create(prw_gpu *gpu, const prw_scene *scene, const prw_render_desc *desc, prw_renderer **out,
                         prw_error *e);
void prw_renderer_destroy(prw_renderer *r);

/* Records the frame for views[0..count) into cmd (caller submits). */
bool prw_renderer_record(prw_renderer *r, VkCommandBuffer cmd, const prw_view *views, uint32_t count,
                         prw_error *e);
/* Records, submits and waits; fills stats (pass times when desc.timestamps). */
bool prw_renderer_render(prw_renderer *r, const prw_view *views, uint32_t count, prw_frame_stats *stats,
                         prw_error *e);
/* Changes the extra-work test knob (pass_extra_work.c) of a renderer created with extra_gpu_work > 0
 * (the bench calibrates it); fraction in (0, 16]. */
bool prw_renderer_set_extra_work(prw_renderer *r, double fraction, prw_error *e);
/* The scene's NURBS models with LOD (prw_lod_render.h: options, per-frame report); NULL without. */
struct prw_lod_scene *prw_renderer_lod(prw_renderer *r);
/* After a frame: the stats of the passes (needed or skipped) as last recorded. */
void prw_renderer_last_passes(const prw_renderer *r, prw_frame_stats *stats);

/* Reads back view v's linear HDR image (cd/m^2). */
bool prw_renderer_read_hdr(prw_renderer *r, uint32_t v, prw_image *out, prw_error *e);
/* Reads back view v's display-encoded image as 8-bit RGBA (width*height*4 bytes). */
bool prw_renderer_read_ldr(prw_renderer *r, uint32_t v, uint8_t *rgba, prw_error *e);
/* The display-encoded image of view v (RGBA8 UNORM holding sRGB-encoded values), for presenting. */
prw_gpu_image *prw_renderer_ldr_image(prw_renderer *r, uint32_t v);

/* Display-aware tone mapping (prw_tonemap.h; issue 6), used from the next frame on.  Default: the
 * built-in "srgb" display with the exposure operator, i.e. the provisional tone map (exposure from
 * EV100, clamp, sRGB).  d or s may be NULL to keep the current one. */
bool prw_renderer_set_tonemap(prw_renderer *r, const prw_display *d, const prw_tonemap_settings *s, prw_error *e);
void prw_renderer_get_tonemap(const prw_renderer *r, prw_display *d, prw_tonemap_settings *s);
/* Reads back view v's display signal V before quantisation (RGBA float, A = 1). */
bool prw_renderer_read_signal(prw_renderer *r, uint32_t v, prw_image *out, prw_error *e);
/* The last frame's tone-mapping statistics (all views) and pixel classification; returns false
 * (report zeroed) when the frame did not classify (exposure/neutral/reinhard/adaptive without
 * settings.report or overlay).  Call after the frame completed. */
bool prw_renderer_tonemap_report(prw_renderer *r, prw_tm_stats *stats, prw_tm_report *rep);
/* Tone-maps an arbitrary linear HDR image (cd/m^2, Rec.709) on the GPU with the current settings
 * and exposure ev100: signal V (RGBA float), statistics and report (may be NULL).  For tests and
 * files; the image may not have more 16x16 tiles than max_views * the renderer's size. */
bool prw_renderer_tonemap_image(prw_renderer *r, const prw_image *hdr, double ev100, prw_image *signal,
                                prw_tm_stats *stats, prw_tm_report *rep, prw_error *e);
/* Temporal adaptation (prw_tonemap_settings.adapt): the frame time dt (s) of the next frame's
 * adaptation step (dt < 0 or never called: the measured wall time between frames), and the adapted
 * luminance La the last frame used (false, *la = 0, when none: adaptation off or the first frame).
 * prw_renderer_set_tonemap starts a new state when the operator or the adaptation settings change. */
void prw_renderer_tonemap_advance(prw_renderer *r, double dt);
bool prw_renderer_tonemap_adaptation(const prw_renderer *r, double *la);

/* A tone-mapping session on one HDR image (uploaded once): each run tone-maps it with the current
 * settings (prw_renderer_set_tonemap) and returns the wall time of the submitted tone-mapping passes
 * alone in *ms (host clock around submit + wait: on lavapipe the GPU is the CPU), and optionally
 * the signal, statistics and report.  For benchmarks that alternate operators frame by frame. */
typedef struct prw_tm_session prw_tm_session;
bool prw_tm_session_create(prw_renderer *r, const prw_image *hdr, prw_tm_session **out, prw_error *e);
bool prw_tm_session_run(prw_tm_session *s, double ev100, double *ms, prw_image *signal, prw_tm_stats *stats,
                        prw_tm_report *rep, prw_error *e);
void prw_tm_session_destroy(prw_tm_session *s);
/* The same with the image uploaded as RGBA16F (the half radiance targets' format: values rounded to
 * nearest, clipped at 65504). */
bool prw_tm_session_create_half(prw_renderer *r, const prw_image *hdr, prw_tm_session **out, prw_error *e);
/* The yardstick of "memory speed": the wall time of a vkCmdCopyImage of the session's input image to
 * another of the same format and size, timed as prw_tm_session_run times its passes. */
bool prw_tm_session_time_copy(prw_tm_session *s, double *ms, prw_error *e);
/* The floors of a pass over the image on this device, timed the same way (the yardsticks of prw tmbench
 * --vs-copy): compute passes with 16 x 16 workgroups (the dispatch alone; reading every pixel; a
 * texelFetch -> imageStore into the session's RGBA8 or RGBA32F image or packed RGBA8 into a storage
 * buffer; reading + the statistics' per-workgroup reduction) and full-screen fragment passes
 * (texelFetch -> the RGBA8 colour attachment, or RGBA8 + RGBA32F). */
typedef enum prw_tm_floor {
    PRW_TM_FLOOR_CS_EMPTY,
    PRW_TM_FLOOR_CS_READ,
    PRW_TM_FLOOR_CS_RGBA8,
    PRW_TM_FLOOR_CS_RGBA32F,
    PRW_TM_FLOOR_CS_BUFFER8,
    PRW_TM_FLOOR_CS_STATS,
    PRW_TM_FLOOR_CS_STATS_NB,
    PRW_TM_FLOOR_CS_LOG,
    PRW_TM_FLOOR_FS_RGBA8,
    PRW_TM_FLOOR_FS_BOTH,
    PRW_TM_FLOOR_COUNT
} prw_tm_floor;
bool prw_tm_session_time_floor(prw_tm_session *s, prw_tm_floor k, double *ms, prw_error *e);
const char *prw_tm_floor_name(prw_tm_floor k);
/* Profiling (prw tmbench --profile): wall time per pass ("stats", "classify", "blur3h", ...) of the
 * current settings, as differences of runs recording only the first k passes (best of `reps` runs
 * each; GPU timestamps do not time lavapipe's compute dispatches).  base_ms: the run with no pass. */
typedef struct prw_tm_profile {
    int count;
    char names[64][24];
    double ms[64], base_ms;
} prw_tm_profile;
bool prw_tm_session_profile(prw_tm_session *s, double ev100, int reps, prw_tm_profile *out, prw_error *e);

/* "loop" | "multiview" | "auto" (NULL = auto) for gpu.  auto = prw_views_backend_choose (views_backend.c) */
bool prw_views_backend_resolve(prw_gpu *gpu, const char *name, prw_views_backend *out, prw_error *e);

/* The auto choice, measured once per device + driver and cached (views_backend.c): multiview only when
 * a probe stereo pair rendered by it equals the loop's within relative L1 1e-5 and it is >= 3 %
 * faster over interleaved frames; otherwise the loop.  `reason` says which rule decided. */
typedef struct prw_views_choice {
    prw_views_backend backend;
    bool from_cache;         /* read from $PRW_CACHE_DIR/views/, not measured now */
    bool multiview_ok;       /* multiview eyes == loop eyes within 1e-5 relative L1 */
    double multiview_rel_l1; /* worst eye */
    double loop_ms, multiview_ms; /* median probe frame (two views, 256x144 per eye) */
    char reason[160];
} prw_views_choice;
bool prw_views_backend_choose(prw_gpu *gpu, prw_views_choice *out, prw_error *e);
const char *prw_views_backend_name(prw_views_backend b);

/* The graph as built for this renderer's scene and settings: passes in order with their resources and
 * why a pass is not in the graph, then the resources (graph.h prw_graph_describe).  Appends to buf. */
void prw_renderer_describe(const prw_renderer *r, char *buf, size_t cap);
/* The emissive meshes' area lights this renderer lights with (prw_emissive.h): built at create and
 * sync with the budget min(quality.emissive_lights, the light slots the scene's lights leave). */
const prw_emissive_lights *prw_renderer_emissive(const prw_renderer *r);
/* Re-uploads the scene (edited since create or the last sync) and rebuilds the pass graph. */
bool prw_renderer_sync_scene(prw_renderer *r, prw_error *e);
/* Reads back view v's instance of the graph image `name` ("hdr", "depth", "gbuf_normal", "gbuf_id", ...):
 * RGBA16F/32F/8 images as float RGBA (width*height*4), D32F / R32 images as width*height 32-bit values.
 * *w, *h receive the size.  Fails for multisampled or absent images. */
bool prw_renderer_read_image(prw_renderer *r, const char *name, uint32_t v, void **out, uint32_t *w, uint32_t *h,
                             prw_error *e);
struct prw_graph;
/* The renderer's pass graph (graph.h; tests). */
struct prw_graph *prw_renderer_graph(prw_renderer *r);

#ifdef __cplusplus
}
#endif
#endif
