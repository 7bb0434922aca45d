/* prw_probe — the reflection-probe baker (issue 16, DESIGN.md §4): for the curved glossy objects of a
 * scene (the gold sphere, a car shell), equirectangular maps of the radiance arriving at a point from
 * every direction, gathered by the reference path tracer (prw_ref_trace_rays), prefiltered per roughness
 * by materials/env (prw_env_prefilter), with their file and cache entry (kind "probe").
 *
 * Where probes go (prw_probe_select): one per drawn (node, mesh) whose material is the glTF kind, opaque,
 * without a clear coat, with a specular lobe (metallic > 0 or specular > 0), of roughness at most
 * `max_roughness`, and which is NOT planar (its vertices off the plane of its largest triangle by more
 * than 1e-3 of its bounding-box diagonal: planar reflectors are pass_mirror's).  At most `count` of
 * them, those of the largest bounding boxes first (ties in scene order).  A probe sits at the centre of
 * the mesh's world bounding box; its influence box is that box grown by 1 % of its diagonal + 1 mm.
 *
 * What a probe texel holds (RGB float, cd/m^2): L(c, d) = the mean, over `samples` directions d jittered
 * in the texel (stratified), of the radiance arriving at the centre c from d along the light paths
 * that scatter at least once after the ray (the reference filter mindepth:1 along the ray): the
 * radiance LEAVING the surfaces seen from c minus their emission.  Emission seen directly (lights,
 * emissive meshes) and the environment seen directly are not in it: a reflection of those is the
 * direct term's (rect lights' and emissive polygons' specular) and the environment term's.  Hence the
 * renderer's probe term, the split sum of the surface's specular lobes over P (the prefiltered map), is
 * the reference's `indirect-glossy-last` (k >= 2 paths whose eye vertex took the specular lobes):
 * vertex 1 is the surface, vertex 2 the surface the probe sees, and everything after it is in L.
 * The object's own surface is not seen: single-sided materials are passed through from inside (the
 * ray's first hit passes back faces, prw_ref_ray_desc.camera), double-sided ones skipped by tnear =
 * the largest distance of a vertex from c.  Approximations (measured by tests/render/test_probe.c): L is
 * gathered at c, not at the shaded point (the renderer corrects the direction by box parallax, the box
 * being the scene's bounds); the object's shadowing of the surroundings it reflects is in L.
 *
 * Map: rows top down from +Y, u = 0.5 + atan2(d.x, -d.z) / (2 pi), v = acos(d.y) / pi (materials/env's
 * mapping with rotation 0: world directions), `size` rows of 2 size texels.  Ray of sample j of texel
 * t of probe p: index (p W H + t) samples + j, the option's seed, one sample each: a pure function of
 * (scene, options), bit-identical for any thread count.
 * Prefiltered levels: prw_env_prefilter of the map, PRW_PROBE_LEVELS levels (roughness k / (K - 1)),
 * height max(4, size / 2), PRW_PROBE_PREFILTER_SAMPLES samples.
 *
 * File (PRWPRB01, little-endian, probe_bake.c has the layout): read back with every count checked
 * against limits and the remaining bytes before allocation, non-finite or negative values refused, a
 * prw_hash64 checksum; levels must be PRW_PROBE_LEVELS.  A cache entry is used only when its probes' nodes,
 * meshes and materials are the ones prw_probe_select gives for the scene and options.  Cache: <cache>/probe/<key>.probe, key = prw_cache_key over "prw-probe-key",
 * PRW_PROBE_ALGO_VERSION, the file version, the resolved options (count, size, samples, seed,
 * max_roughness; not threads), the material model's hash and prw_gi_content_hash (static content and
 * lights, not cameras).  Nothing here prints: progress goes to the callback.
 */
#ifndef PRW_PROBE_H
#define PRW_PROBE_H

#include <stddef.h>
#include <stdint.h>

#include "prw_core.h"
#include "prw_scene.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PRW_PROBE_ALGO_VERSION "probe-2026-12-06b" /* b: prefilter 256 samples */
#define PRW_PROBE_CACHE_KIND "probe"
#define PRW_PROBE_MAX 8
#define PRW_PROBE_LEVELS 21u /* roughness steps of 0.05 */
#define PRW_PROBE_PREFILTER_SAMPLES 256u
#define PRW_PROBE_DEFAULT_SAMPLES 16u
#define PRW_PROBE_DEFAULT_MAX_ROUGHNESS 0.5

typedef struct prw_probe_options {
    uint32_t count;        /* at most this many probes, 0..PRW_PROBE_MAX (the quality knob probe_count) */
    uint32_t size;         /* map rows (width 2 size), 8..512 (the quality knob probe_size) */
    uint32_t samples;      /* rays per texel, 1..4096; 0: PRW_PROBE_DEFAULT_SAMPLES */
    uint64_t seed;
    double max_roughness;  /* 0: PRW_PROBE_DEFAULT_MAX_ROUGHNESS */
    int threads;           /* 0: prw_threads_get() */
} prw_probe_options;

typedef struct prw_probe_info {
    uint32_t node, mesh; /* scene indices */
    int32_t material;
    double centre[3];
    double box_min[3], box_max[3]; /* influence box (world) */
    double tnear;
} prw_probe_info;

typedef struct prw_probe_bake {
    uint32_t count, size, samples, levels, level_height;
    double parallax_min[3], parallax_max[3]; /* the scene's bounds */
    prw_probe_info probes[PRW_PROBE_MAX];
    float *levels_rgb; /* count x levels x level_height x (2 level_height) x 3, probe-major, rows top down */
    double seconds_gather;
} prw_probe_bake;

void prw_probe_bake_destroy(prw_probe_bake *b);

typedef void (*prw_probe_progress_fn)(void *user, double fraction, const char *line);

/* The probes of s for o (no gathering): fills b->probes / count and the parallax box. */
void prw_probe_select(const prw_scene *s, const prw_probe_options *o, prw_probe_bake *b);

/* Selects and gathers (count may come out 0: then nothing is traced). */
bool prw_probe_build(const prw_scene *s, const prw_probe_options *o, prw_probe_progress_fn progress, void *user,
                     prw_probe_bake **out, prw_error *e);

void prw_probe_key(const prw_scene *s, const prw_probe_options *o, char key[33]);
bool prw_probe_encode(const prw_probe_bake *b, const char *key, uint8_t **data, size_t *size, prw_error *e);
bool prw_probe_decode(const void *data, size_t size, const char *name, prw_probe_bake **out, char key[33],
                      prw_error *e);

typedef struct prw_probe_result {
    char key[33];
    char cache_path[4096];
    bool cache_hit, built, cache_written;
    char warning[1024];
    double seconds_total;
} prw_probe_result;

/* From the cache (kind "probe") or built and stored; no_cache: neither read nor write. */
bool prw_probe_run(const prw_scene *s, const prw_probe_options *o, bool no_cache, prw_probe_progress_fn progress,
                   void *user, prw_probe_bake **out, prw_probe_result *r, prw_error *e);

#ifdef __cplusplus
}
#endif
#endif
