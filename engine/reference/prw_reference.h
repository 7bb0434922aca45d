/* prw_reference — the reference path tracer (CPU, Embree 3): the image the rasterizer is judged by.
 *
 * Promises:
 *  - Unbiased estimate of the radiance (cd/m^2, linear Rec.709) through each pixel of a prw_view,
 *    box-filtered over the pixel square [i, i+1) x [j, j+1) (y down; the positions of a pixel's
 *    samples are an Owen-scrambled Sobol (0,2)-sequence, scrambled per pixel), same scene as
 *    the rasterizer: world transforms in double (geometry camera-relative in float), meshes at their
 *    finest, smooth shading normals + normal maps, the shared material model through prw_bsdf.h,
 *    base-colour / emissive textures sRGB-decoded then bilinear (repeat wrap), metal-rough and
 *    normal textures linear bilinear.
 *  - BTF materials (PRW_MATERIAL_BTF, prw_scene.h): the file read once at prw_ref_create (refused, naming
 *    material and file, when its bytes no longer hash to what the scene loaded); evaluated through
 *    prw_btf_eval.h (3 x 3 measured directions with barycentric weights, bilinear texels, the shared
 *    decode) in the frame and texel mapping prw_scene.h states; its value is f cos theta_l, used as such in
 *    next-event estimation and path weights; BSDF samples are cosine-weighted (prw_sample_cosine), so the
 *    estimate stays unbiased; light-path filters count it as diffuse.  With btf_scale_rule, a camera
 *    ray's first hit where the pixel footprint exceeds a texel uses the file's fitted average (glTF model)
 *    instead; prw_ref_trace_rays passes no footprint, so its bit-equality with prw_ref_render below does
 *    not hold for such materials.
 *  - Lights as the rasterizer models them (shaders/base.frag): point/spot in cd with the range
 *    window clamp(1 - (d^2/range^2)^2, 0, 1) (range > 0) and the spot factor
 *    clamp((cos - cos_outer) / max(cos_inner - cos_outer, 1e-4), 0, 1)^2; directional in lux; these
 *    delta lights by next-event estimation only.  Rect lights (cd/m^2): one-sided quads emitting
 *    towards the node's -Z, axes = normalised node x/y columns; they are hit (front face: emits and
 *    absorbs; back face: invisible) and sampled (uniform area), combined by MIS.  Emissive meshes:
 *    hit + area sampling (triangles chosen by area x emission luminance), MIS.  Environment
 *    (prw_scene.environment): hit + importance sampling (equirectangular map: piecewise-constant
 *    2-D distribution weighted by sin(theta); uniform sky: uniform sphere), MIS.  MIS uses the
 *    power heuristic; every light is sampled once per vertex.
 *  - Faces: a single-sided material's back face is culled for camera rays (as the rasterizer does)
 *    and is an opaque black surface for every other ray (so NEE and BSDF rays see the same scene).
 *    Double-sided materials shade both sides (normal flipped), emit on both sides.  Shading normals
 *    facing away from wo are bent as base.frag does; wi on the other side of the geometric surface
 *    than wo contributes nothing.
 *  - Russian roulette after 3 scattering events with survival min(0.95, max throughput channel):
 *    no depth cap (a safety stop at 65536 events is unreachable in practice: 0.95^65533).
 *  - Determinism: every random number is a pure function (SplitMix64 hash; the pixel positions a
 *    hash-scrambled Sobol point) of (seed, pixel index y*width+x of the full image, sample index,
 *    dimension), and samples accumulate in fixed point
 *    (round(v * 2^32) for the sum, round(v^2 * 2^24) for the sum of squares, __int128 per channel):
 *    any split into threads, tiles or sample ranges merges bit-exactly by integer addition.
 *    Non-finite samples are dropped (counted in nonfinite) — they contribute 0.
 *  - Light-path filters (DESIGN.md §4), by the number k of scattering vertices between the eye and
 *    the emitter (k = 0: emission seen directly; k = 1: one bounce):
 *      all; emission (k = 0); direct (k <= 1); indirect (k >= 2); depth:N (k == N); maxdepth:N
 *      (k <= N); mindepth:N (k >= N); diffuse-last / glossy-last: k >= 1 paths weighted by the fraction of the eye
 *      vertex's BSDF value that belongs to its diffuse lobe (prw_brdf_diffuse_channel), resp. the
 *      rest (the specular lobes), for the direction actually taken (NEE or BSDF sample);
 *      indirect-diffuse-last / indirect-glossy-last: k >= 2 paths with the same weights (the eye
 *      vertex's diffuse share for the BSDF sample that continued the path; every later vertex
 *      counts whole); environment-direct: k == 1 paths whose emitter is the environment
 *      (prw_scene.environment: the EXR map or uniform sky outside the scene, reached by the eye
 *      vertex's environment sample or by its BSDF ray escaping the scene; not rect lights or
 *      emissive meshes, even behind a window), with the MIS weights of `all`.  A scene without an
 *      environment has none: its environment-direct image is 0 everywhere.
 *    Sums that hold per sample (same seed), to the rounding of the class weights x + (1 - x):
 *      emission + (direct - emission) + indirect = all; emission + diffuse-last + glossy-last = all;
 *      direct + indirect-diffuse-last + indirect-glossy-last = all;
 *      indirect-diffuse-last + indirect-glossy-last = indirect;
 *      environment-direct = depth:1 - depth:1 of the same scene without its environment.
 *    The filter never changes which random numbers a path uses, so the same seed gives the same paths.
 */
#ifndef PRW_REFERENCE_H
#define PRW_REFERENCE_H

#include "prw_core.h"
#include "prw_scene.h"
#include "prw_view.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum prw_ref_filter_kind {
    PRW_REF_ALL = 0,
    PRW_REF_EMISSION,
    PRW_REF_DIRECT,
    PRW_REF_INDIRECT,
    PRW_REF_DIFFUSE_LAST,
    PRW_REF_GLOSSY_LAST,
    PRW_REF_DEPTH,     /* exactly `depth` scattering vertices */
    PRW_REF_MAX_DEPTH, /* at most `depth` */
    PRW_REF_INDIRECT_DIFFUSE_LAST,
    PRW_REF_INDIRECT_GLOSSY_LAST,
    PRW_REF_ENVIRONMENT_DIRECT,
    PRW_REF_MIN_DEPTH, /* at least `depth` */
    PRW_REF_FILTER_COUNT /* new kinds go before this: .acc files store the number */
} prw_ref_filter_kind;

typedef struct prw_ref_filter {
    prw_ref_filter_kind kind;
    int depth; /* PRW_REF_DEPTH / PRW_REF_MAX_DEPTH / PRW_REF_MIN_DEPTH: 0..1000000 */
} prw_ref_filter;

/* "all|emission|direct|indirect|diffuse-last|glossy-last|indirect-diffuse-last|indirect-glossy-last|
 *  environment-direct|depth:N|maxdepth:N|mindepth:N". */
bool prw_ref_filter_parse(const char *s, prw_ref_filter *out, prw_error *e);
/* The same spelling back (cap >= 32). */
void prw_ref_filter_name(prw_ref_filter f, char *buf, size_t cap);

/* Fixed-point accumulation of one tile over one sample range. */
#define PRW_REF_SUM_SCALE 4294967296.0 /* 2^32 per cd/m^2 */
#define PRW_REF_SQ_SCALE 16777216.0    /* 2^24 per (cd/m^2)^2 */
#define PRW_REF_MAX_SPP 10000000ull

__extension__ typedef __int128 prw_ref_fixed;

typedef struct prw_ref_acc {
    uint32_t width, height;         /* the full image */
    uint32_t x0, y0, x1, y1;        /* this tile: [x0, x1) x [y0, y1) */
    uint64_t s0, s1;                /* samples [s0, s1) of every pixel of the tile */
    uint64_t seed, scene_hash, material_hash;
    prw_ref_filter filter;
    uint64_t nonfinite;             /* dropped samples (NaN/Inf), counted as 0 */
    double ev100;                   /* the view's exposure (carried into the EXR header) */
    prw_ref_fixed *sum, *sq;        /* 3 per tile pixel, row-major within the tile */
} prw_ref_acc;

void prw_ref_acc_free(prw_ref_acc *a);

typedef struct prw_ref_progress {
    uint64_t done, total;   /* pixel samples */
    uint64_t spp_done;      /* whole sample batches finished */
    double elapsed_s, eta_s; /* eta < 0: unknown */
} prw_ref_progress;

typedef struct prw_ref_desc {
    uint32_t x0, y0, x1, y1;        /* tile; all 0 = the whole view */
    uint64_t s0, s1;                /* sample range [s0, s1); s1 - s0 = spp in 1..PRW_REF_MAX_SPP */
    uint64_t seed;
    prw_ref_filter filter;
    double time_limit_s;            /* > 0: stop after the sample batch during which it expires */
    int threads;                    /* 0: prw_threads_get() */
    void (*progress)(void *user, const prw_ref_progress *p); /* main thread, <= 4 times/s; may be NULL */
    void *user;
} prw_ref_desc;

typedef struct prw_ref_stats {
    uint64_t spp;        /* samples per pixel actually done (s1 - s0 of the result) */
    uint64_t rays;       /* camera, bounce and shadow rays */
    double seconds;      /* wall time of the sampling (not the scene build) */
    bool time_limited;   /* stopped early by time_limit_s */
    double tess_px;      /* NURBS models: worst projected error of their tessellation (level 0 of the
                            hierarchy, exact normals) for this view, pixels; 0 without NURBS models */
} prw_ref_stats;

typedef struct prw_ref_renderer prw_ref_renderer;

/* The view of scene camera `camera` (NULL or "": the first) for a width x height image; errors name
 * the scene and the camera ("<scene>: no camera named 'x' (cameras: a, b)"). */
bool prw_ref_view_for_camera(const prw_scene *s, const char *camera, uint32_t width, uint32_t height, prw_view *out,
                             prw_error *e);

/* Builds the Embree scene (camera-relative to `origin`, normally the view's eye), emitter tables
 * and the environment distribution (reads the environment EXR).  threads: 0 = prw_threads_get().
 * NURBS entries use the model and hierarchy attached to the scene (engine/bake's prw_bake_scene
 * must have run; otherwise "reference: NURBS entry '<name>' has no baked hierarchy: ..."). */
bool prw_ref_create(const prw_scene *s, prw_dvec3 origin, int threads, prw_ref_renderer **out, prw_error *e);
void prw_ref_destroy(prw_ref_renderer *r);

/* Bytes a reference run holds at its peak besides the scene: the accumulation (96 bytes per tile
 * pixel) and, when it writes the EXR pair (exr), the mean and variance images and the encoded file
 * (48 bytes per image pixel).  Commands check it against the memory budget before any work;
 * prw_ref_render, the merge, the reader and prw_ref_acc_images check their own allocations. */
uint64_t prw_ref_memory_bytes(uint32_t width, uint32_t height, uint64_t tile_pixels, bool exr);

/* Renders a tile over a sample range into *acc (allocated; free with prw_ref_acc_free).
 * The view's eye should be the origin given to prw_ref_create (any eye works, precision aside). */
bool prw_ref_render(prw_ref_renderer *r, const prw_view *view, const prw_ref_desc *d, prw_ref_acc *acc,
                    prw_ref_stats *stats, prw_error *e);

/* The camera ray through image point (x, y) (pixels; pixel (i, j) spans [i, i+1) x [j, j+1), y down)
 * and what it hits first, with the same rules as a path's first vertex (back faces of single-sided
 * materials are passed through, as the rasterizer culls them): the world position (absolute), the
 * shading normal the BSDF sees (interpolated, double-sided flip, normal map, bent towards the viewer
 * below 1e-4) and the material index (-1: a rect light's surface).  false: nothing hit. */
typedef struct prw_ref_hit {
    prw_dvec3 position;
    prw_dvec3 normal;
    int material;
    double t; /* ray distance, metres */
} prw_ref_hit;
bool prw_ref_primary_hit(const prw_ref_renderer *r, const prw_view *view, double x, double y, prw_ref_hit *out);

/* ---- rays: the integrator of prw_ref_render along any rays (bakers: light maps, BTFs) ----
 * prw_ref_trace_rays estimates, for each ray i of `rays`, the radiance arriving at its origin from
 * along its direction (cd/m^2, i.e. the radiance leaving the first surface hit towards the origin),
 * restricted to the light paths of the filter, counting k from the ray: its first hit is
 * scattering vertex 1 (so mindepth:1 = everything but emission seen directly along the ray;
 * the eye-vertex filters (diffuse-last, ...) weight at that first hit).  Same integrator, MIS,
 * Russian roulette, and random numbers as prw_ref_render: sample s of ray i uses the key of
 * (seed, first_index + i, s), dimensions from 2 on — the numbers prw_ref_render gives pixel
 * y * width + x.  Hence the relation (a test checks it bit-exactly): for sample s of pixel (x, y),
 * the ray prw_ref_camera_ray returns, traced with first_index = y * width + x, camera = true,
 * over [s, s + 1), gives exactly that sample's value (mean = the pixel's fixed-point sum / 2^32).
 * Samples accumulate per ray in the same fixed point, so the result is bit-identical for any thread
 * count.  A ray's direction is fixed over its samples: a baker wanting a distribution of directions
 * passes one ray per direction. */
typedef struct prw_ref_ray {
    prw_dvec3 origin; /* absolute world position */
    prw_dvec3 dir;    /* unit (normalised by the call when not) */
    double tnear;     /* hits closer than this are ignored, metres (>= 0) */
} prw_ref_ray;

typedef struct prw_ref_ray_desc {
    uint64_t first_index;     /* random-number index of rays[0] */
    uint64_t s0, s1;          /* samples [s0, s1) of every ray; 1..PRW_REF_MAX_SPP of them */
    uint64_t seed;
    prw_ref_filter filter;
    bool camera;              /* true: the first hit passes through back faces of single-sided materials
                                 (as camera rays do); false: they are opaque black, as for bounce rays */
    int threads;              /* 0: the renderer's */
} prw_ref_ray_desc;

typedef struct prw_ref_ray_result {
    double mean[3];     /* the fixed-point sum / 2^32 / samples */
    double var_mean[3]; /* sample variance / samples (the variance of the mean); 0 with one sample */
    uint64_t back_faces;/* samples whose first surface was the back face of a single-sided material (the
                           ray starts inside or under closed geometry; camera = false only) */
} prw_ref_ray_result;

/* out holds n results.  Errors: n > 2^32, empty or too long sample range, unknown filter, a
 * non-finite ray or negative tnear (naming the ray).  rays_traced (may be NULL) gets the count of
 * traced rays (camera, bounce, shadow) and nonfinite (may be NULL) the dropped samples. */
bool prw_ref_trace_rays(const prw_ref_renderer *r, const prw_ref_ray *rays, size_t n, const prw_ref_ray_desc *d,
                        prw_ref_ray_result *out, uint64_t *rays_traced, uint64_t *nonfinite, prw_error *e);

/* The camera ray prw_ref_render traces for sample s of pixel (x, y) of view (jittered position in
 * the pixel, eye origin, near-plane tnear); with seed the render's seed. */
prw_ref_ray prw_ref_camera_ray(const prw_ref_renderer *r, const prw_view *view, uint64_t seed, uint32_t x, uint32_t y,
                               uint64_t s);

/* ---- accumulation files ("PRWACC01", little-endian, version 1; see ref_acc.c) ---- */
bool prw_ref_acc_write(const char *path, const prw_ref_acc *a, prw_error *e);
bool prw_ref_acc_read(const char *path, prw_ref_acc *out, prw_error *e);
bool prw_ref_acc_read_memory(const void *data, size_t size, const char *name, prw_ref_acc *out, prw_error *e);

/* Merges accumulations (any tiles, any sample ranges) into one full-image accumulation.  Errors:
 * different image size, seed, scene hash, material hash or filter; overlapping sample ranges on a
 * shared pixel; pixels left uncovered; pixels with different sample counts.  `names` (may be NULL)
 * label the inputs in messages.  out->s0 = 0 and out->s1 = the common sample count when the inputs'
 * ranges differ (the ranges themselves are then not one interval). */
bool prw_ref_acc_merge(const prw_ref_acc *const *in, const char *const *names, int count, prw_ref_acc *out,
                       prw_error *e);

/* Mean (RGB, A = 1) and variance of the mean per channel (RGB, A = sample count) of a full-image
 * accumulation (tile = whole image).  The variance is the pixel's sample variance / count: unbiased
 * for the error of the mean where the value does not depend on the position inside the pixel (the
 * path after the camera ray is random per sample); an over-estimate (conservative) where it does
 * (edges, a light's rim), whose stratified positions converge faster than independent ones. */
bool prw_ref_acc_images(const prw_ref_acc *a, float **mean_rgba, float **var_rgba, prw_error *e);

/* Writes `path` (mean radiance) and the variance EXR (prw_ref_var_path) with the header attributes
 * prw:spp, prw:seed, prw:scene_hash, prw:material_hash, prw:git, prw:filter, prw:ev100, prw:samples,
 * prw:nonfinite, prw:units plus extra_count key/value pairs (extra_kv holds 2 * extra_count strings). */
bool prw_ref_write_exr(const char *path, const prw_ref_acc *a, const char *const *extra_kv,
                       int extra_count, prw_error *e);
/* "<path without .exr>.var.exr" into buf. */
void prw_ref_var_path(const char *path, char *buf, size_t cap);

/* SHA-256 (hex) of materials/prw_brdf.h at configure time, and its first 16 hex digits as a number. */
const char *prw_ref_material_hash_hex(void);
uint64_t prw_ref_material_hash(void);
const char *prw_ref_git_hash(void);

#ifdef __cplusplus
}
#endif
#endif
