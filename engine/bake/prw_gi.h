/* prw_gi — the indirect-diffuse baker: light maps of the irradiance of INDIRECT light (issue 16,
 * DESIGN.md §4) at the static meshes of a scene, gathered by the reference path tracer
 * (prw_ref_trace_rays), and their file / cache entry (kind "gi").
 *
 * What a texel holds (RGB float, linear, lux-like units: cd/m^2 x sr):
 *   E_ind(x) = integral over the hemisphere of n(x) of  w(mu_i) L_ind(x, wi) mu_i dwi
 *   L_ind(x, wi): radiance arriving at x from wi along light paths that scattered at least once after
 *                 leaving the emitter (the reference filter mindepth:1 along the ray from x: emission
 *                 seen directly and direct light are NEVER in it);
 *   mu_i = n.wi, n the surface's geometric normal (front side; normal maps are not applied);
 *   w(mu) = 1 - e(mu),  e(mu) = s Ed(mu, r) + F_ms(s F_avg, Ec_avg(r)) Ec(mu, r)  (materials/prw_brdf.h:
 *           the dielectric specular layer's albedo E_ds; s = material.specular, r = material.roughness
 *           factor; prw_gi_weight).  With specular 0 (pure Lambert), w = 1 and E_ind is the plain
 *           irradiance of indirect light.
 * What the renderer makes of it (prw_gi_radiance; exactly the reference's indirect-diffuse-last term,
 * up to the light map's resolution and noise): for a surface point seen from wo (mu_o = n.wo),
 *   L_idl(x, wo) = (1 - metallic) base / pi x (1 - e(mu_o)) / (1 - e_avg) x E_ind(x)
 * with e_avg = s Ed_avg(r) + F_ms Ec_avg(r) — the model's diffuse lobe f_diffuse
 * = base/pi (1 - e(mu_o)) (1 - e(mu_i)) / (1 - e_avg) integrated against L_ind.  base is the base
 * colour (factor x texture, linear) at the point, so textures need no rebake.  It is what
 * `prw reference --filter indirect-diffuse-last` shows on that surface when its metallic, roughness
 * and specular are the material's factors (no metal-rough texture, no clear coat, no normal map:
 * those deviate from this formula and are not baked per texel).
 *
 * Storage:
 *  - Instances: one per (node, mesh) drawn, in scene order (nodes, then the meshes of their group).
 *    mode NONE: not baked (no diffuse lobe: metallic >= 1 or a black base colour; emissive-only),
 *    except that with an environment every mesh with triangles is baked (its visibility V);
 *    mode ATLAS: flat charts in an atlas, uv = 6 floats per triangle (the corners' light-map uv,
 *    normalised to the atlas: texel (i, j) is centred at ((i + 0.5) / width, (j + 0.5) / height));
 *    mode VERTEX: meshes without TEXCOORD_1 dense enough (sqrt(world area / vertices) <= the texel size
 *    computed over every baked mesh: the spheres), one RGB per mesh vertex, interpolated with the
 *    triangle's barycentrics (gathered at the vertex with its shading normal).
 *  - Charts (gi_build.c): a mesh with TEXCOORD_1 (prw_mesh.uvs1, non-degenerate) is one chart: its
 *    uv1 layout scaled by sqrt(world area / uv1 area) / t texels per uv unit (overlapping uv1
 *    triangles are not detected: the first one rasterised owns a texel; islands of the layout are
 *    dilated into each other's gaps, so the author's padding is what separates them).  Other meshes
 *    are unwrapped: triangles welded by position, grouped by connectivity and normal (within
 *    ~2.6 degrees of the chart's first triangle), projected on the plane of that normal.  Texel size
 *    t, 2 texels of padding each side; shelf-packed (tallest first) into atlases PRW_GI_ATLAS_W wide
 *    and at most as high, at most PRW_GI_MAX_ATLASES.  Curved meshes coarser than the texel size
 *    and without TEXCOORD_1 get one chart per facet (correct, wasteful); NURBS models are not baked
 *    (the instance list holds meshes only).
 *  - Texel size t = sqrt(A / radiosity_size^2), A = the world area of the ATLAS-mode triangles:
 *    the quality knob radiosity_size ("radiosity texture size, texels a side") keeps its meaning as
 *    the side of the total light-map budget (about radiosity_size^2 sampled texels).
 *  - A texel whose centre lies in a chart triangle is sampled there (state 1); a chart with no such
 *    texel gets one at its largest triangle's centroid.  A sampled texel more than a quarter of whose
 *    gather rays first meet the back face of a single-sided surface (prw_ref_ray_result.back_faces:
 *    the point lies under or inside closed geometry, like the floor under a box) is hidden: it is
 *    treated as outside the chart, so lookups next to a contact read the visible neighbours instead
 *    of black.  Every texel of the chart's rectangle (padding included) that is not sampled takes
 *    the value of the nearest sampled texel of the SAME chart (state 2: dilation), so bilinear and
 *    bicubic lookups near a chart border never read another chart.  A chart with no visible texel
 *    stays 0 (state 0).
 *  - Gathering: `samples` cosine-weighted rays per point (a stratified (0,2) pattern rotated per
 *    point), origin offset 2e-4 m along n, each ray one sample of prw_ref_trace_rays with the filter
 *    mindepth:1, ray index point x samples + j, the option's seed: a pure function of (scene, options).
 *    E = pi x mean(w(mu) L); var = its variance of the mean (stored per texel and vertex).
 *  - Box filter (filter_radius r > 0; PRW_GI_DEFAULT_FILTER_RADIUS for the renderer's bakes, 0 = off
 *    in the struct): a sampled texel's E becomes the mean of the sampled texels of the same chart
 *    within r texels (after the hidden-texel rule, before dilation; vertices unfiltered): less noise,
 *    a bias where E bends (corners, contact); `prw bake --gi --sweep` measures the trade.
 *
 * Environment visibility (issue 16, the renderer's environment term, engine/render/prw_env_gpu.h):
 *   V(x) = Y(sum_j L_env(wj) [wj escapes]) / Y(sum_j L_env(wj))   over the SAME cosine-weighted gather
 *   rays wj of the point, Y the luminance, L_env the scene's environment radiance in direction wj
 *   (prw_environment's mapping, nearest texel as the path tracer), "escapes": the ray's emission seen
 *   directly (prw_ref_trace_rays, filter emission, the path tracer's own ray casting) equals L_env(wj)
 *   — it met no surface.  It is the fraction of the unoccluded environment irradiance (cosine-weighted,
 *   luminance) that reaches the point: in [0, 1], exactly 1 where nothing occludes (a ratio estimator
 *   on the same rays, so unoccluded texels carry no noise).  V = 1 without an environment, or where
 *   Y(sum L_env) = 0 (a black environment).  With an environment present, metallic meshes are baked
 *   too (their E_ind is weighted by 1 - metallic = 0 in the renderer; they need V).
 *   The open cone (texels and vertices, for the renderer's specular occlusion): over the same rays,
 *   f = the fraction that escapes and b = the sum of their directions (world space, not normalised; 0
 *   when none escapes), stored as (b, f).  For cosine-weighted rays, a cone of half-angle t about n
 *   holds the fraction sin^2 t of them, so the renderer reads the open directions as the cone about
 *   b / |b| of half-angle asin(sqrt(f)), and |b| / f (their mean resultant length) as how far they
 *   spread: how much of the cap they span is open (shaders/gi_env.glsl).  Directions where the environment is black count as open
 *   (the test above cannot tell them apart); without an environment b = n, f = 1.
 * File (PRWGI001, little-endian; gi_file.c has the layout): read back with every count checked
 * against limits and the remaining bytes before any allocation, non-finite or negative values
 * refused, a prw_hash64 (FNV-1a) checksum.  Cache: <cache>/gi/<key>.gi, key = prw_cache_key over the
 * tag "prw-gi-key", PRW_GI_ALGO_VERSION, the file version, the options (radiosity_size, samples,
 * seed, filter_radius; not threads: the result does not depend on them), the material model's hash
 * (prw_ref_material_hash) and the static content hash (prw_gi_content_hash: meshes, their nodes'
 * world transforms, materials, textures, lights with their transforms, the environment, NURBS
 * entries; NOT cameras).
 * Nothing here prints: progress goes to the callback.
 */
#ifndef PRW_GI_H
#define PRW_GI_H

#include <stddef.h>
#include <stdint.h>

#include "prw_core.h"
#include "prw_scene.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PRW_GI_ALGO_VERSION "gi-2026-12-06c" /* b: hidden texels dilated; c: environment visibility */
#define PRW_GI_CACHE_KIND "gi"
#define PRW_GI_MAX_ATLASES 128
#define PRW_GI_ATLAS_W 1024
#define PRW_GI_PAD 2
#define PRW_GI_DEFAULT_RADIOSITY_SIZE 256 /* the "high" preset's radiosity_size */
#define PRW_GI_DEFAULT_SAMPLES 128
#define PRW_GI_DEFAULT_FILTER_RADIUS 1 /* what prw bake (and callers baking for the renderer) pass */

typedef struct prw_gi_options {
    uint32_t radiosity_size; /* the quality knob (texels a side of the light-map budget); 0: default */
    uint32_t samples;        /* gather rays per point, 1..65536; 0: default */
    uint64_t seed;
    int threads;             /* 0: prw_threads_get() */
    uint32_t filter_radius;  /* 0: off; r: each sampled texel becomes the mean of the sampled texels of its
                                chart within r texels (a (2r+1)^2 box; variance propagated); 0..8.
                                Callers baking for the renderer pass PRW_GI_DEFAULT_FILTER_RADIUS. */
} prw_gi_options;

typedef enum prw_gi_mode { PRW_GI_NONE = 0, PRW_GI_ATLAS = 1, PRW_GI_VERTEX = 2 } prw_gi_mode;

typedef struct prw_gi_instance {
    uint32_t node, mesh;    /* scene indices */
    uint32_t mode;          /* prw_gi_mode */
    uint32_t atlas;         /* ATLAS */
    uint32_t triangle_count;/* ATLAS: of the mesh */
    float *uv;              /* ATLAS: 6 per triangle */
    uint32_t vertex_count;  /* VERTEX: of the mesh */
    float *vertex_rgb;      /* VERTEX: 3 per vertex, E_ind */
    float *vertex_var;      /* VERTEX: 3 per vertex, variance of the mean */
    float *vertex_vis;      /* VERTEX: 1 per vertex, environment visibility V (see the top) */
    float *vertex_cone;     /* VERTEX: 4 per vertex, the open cone (b, f) (see the top) */
} prw_gi_instance;

typedef struct prw_gi_atlas {
    uint32_t width, height;
    float *rgb;     /* 3 per texel, row-major, E_ind */
    float *var;     /* 3 per texel, variance of the mean (sampled texels; dilated ones copy it) */
    float *vis;     /* 1 per texel, environment visibility V (see the top; filtered and dilated as rgb) */
    float *cone;    /* 4 per texel, the open cone (b, f) (see the top; filtered and dilated as rgb) */
    uint8_t *state; /* per texel: 0 unused, 1 sampled, 2 dilated */
} prw_gi_atlas;

typedef struct prw_gi_bake {
    double texel_size;      /* metres */
    uint32_t samples;
    uint32_t atlas_count;
    prw_gi_atlas *atlases;
    uint32_t instance_count;
    prw_gi_instance *inst;
    uint64_t charts, sampled_texels, sampled_vertices; /* statistics */
    uint64_t hidden_texels; /* sampled texels found under / inside closed geometry, then dilated */
    double seconds_gather;
} prw_gi_bake;

void prw_gi_bake_destroy(prw_gi_bake *b);

typedef void (*prw_gi_progress_fn)(void *user, double fraction, const char *line);

/* w(mu) of the header for material m (mu clamped to (0, 1]). */
double prw_gi_weight(const prw_material *m, double mu);
/* L_idl of the header per channel from E_ind, the base colour (linear) and mu_o. */
void prw_gi_radiance(const prw_material *m, const double base[3], double mu_o, const float E[3], double out[3]);

/* Bakes scene s (static: every mesh node; NURBS entries are skipped).  Errors: no mesh to bake,
 * the atlas budget exceeded (naming the texel size), a reference failure. */
bool prw_gi_build(const prw_scene *s, const prw_gi_options *o, prw_gi_progress_fn progress, void *user,
                  prw_gi_bake **out, prw_error *e);

/* The light-map value at barycentrics (b1, b2) of triangle tri of instance i (s: the baked scene,
 * for the vertex indices): bilinear in the atlas (clamped at its edges), barycentric over vertex
 * values; false (and 0) for mode NONE or indices out of range. */
bool prw_gi_lookup(const prw_gi_bake *b, const prw_scene *s, uint32_t i, uint32_t tri, double b1, double b2,
                   double out[3]);

/* The vertex buffer a renderer draws instance i with: the mesh's vertices split where its triangles
 * give one vertex different light-map uvs (chart borders of a welded mesh), so per-vertex uvs
 * reproduce the per-corner ones exactly.  source[k]: the mesh vertex new vertex k copies; uv: 2 per
 * new vertex; indices: the mesh's index count, into the new vertices.  ATLAS instances only (an
 * error otherwise, or when the scene's mesh does not match the bake). */
typedef struct prw_gi_split {
    uint32_t vertex_count, index_count;
    uint32_t *source;
    float *uv;
    uint32_t *indices;
} prw_gi_split;
bool prw_gi_split_vertices(const prw_gi_bake *b, const prw_scene *s, uint32_t i, prw_gi_split *out, prw_error *e);
void prw_gi_split_free(prw_gi_split *sp);

/* Hash of what the bake depends on besides the options (not the cameras). */
uint64_t prw_gi_content_hash(const prw_scene *s);
void prw_gi_key(const prw_scene *s, const prw_gi_options *o, char key[33]);

/* File: bytes of the encoding (caller frees), and the strict reader (name labels messages). */
bool prw_gi_encode(const prw_gi_bake *b, const char *key, uint8_t **data, size_t *size, prw_error *e);
bool prw_gi_decode(const void *data, size_t size, const char *name, prw_gi_bake **out, char key[33], prw_error *e);

typedef struct prw_gi_result {
    char key[33];
    char cache_path[4096];
    bool cache_hit, built, cache_written;
    char warning[1024];
    double seconds_total;
} prw_gi_result;

/* From the cache (kind "gi") or built and stored; no_cache: neither read nor write. */
bool prw_gi_run(const prw_scene *s, const prw_gi_options *o, bool no_cache, prw_gi_progress_fn progress,
                void *user, prw_gi_bake **out, prw_gi_result *r, prw_error *e);

#ifdef __cplusplus
}
#endif
#endif
