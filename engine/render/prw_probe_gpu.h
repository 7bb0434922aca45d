/* prw_probe_gpu — reflection probes on the GPU for the base pass's probe term (issue 16,
 * shaders/gi_probe.glsl): prefiltered equirectangular maps of the radiance leaving the surfaces seen from
 * a point, baked by engine/bake/prw_probe.h (which states what a texel holds and where probes go), filled
 * by app/ and handed to prw_renderer_create through prw_render_desc.probes (the renderer never links the
 * baker).
 *
 * Promises:
 *  - Globals set 0: binding 8 a storage buffer (prw_gpu_probes: count, levels, height; the parallax box;
 *    per probe its centre and material slot + 1 (the G-buffer id of material_gltf.glsl), its influence
 *    box), binding 9 the levels as one RGBA32F 2-D array (width 2H, height H, layer p K + k: probe p at
 *    roughness k / (K - 1)), binding 10 the split-sum table (prw_env_dfg, N x N RG32F, x: mu = (i + 0.5)
 *    / N, y: roughness j / (N - 1)) — the environment's own (prw_env_gpu.h) exists only with an
 *    environment.
 *  - Positions are world coordinates (float); the shader adds the view's origin (globals origin).
 *  - Without probes (NULL, count 0, or the quality knob probe_count 0) `active` is false and the bindings
 *    name a zero block and 1 x 1 black images; the base pipelines are then specialised exactly as before
 *    (PRW_SC_PROBES unset), so nothing a scene without probes draws changes.  With the knob below the
 *    count, the first probe_count probes are used.
 *  - The input is checked (sizes in range, every float finite, materials in range); an error names what.
 *  - Uploaded once at create: different probes need a new renderer (as the light maps).
 */
#ifndef PRW_PROBE_GPU_H
#define PRW_PROBE_GPU_H

#include "prw_constants.h"
#include "prw_gpu.h"
#include "prw_scene.h"

typedef struct prw_probe_desc {
    float centre[3];
    float box_min[3], box_max[3]; /* influence box: the probe shades its material's fragments inside it */
    int32_t material;             /* scene material index */
} prw_probe_desc;

typedef struct prw_probes {
    uint32_t count;         /* 0..PRW_GPU_MAX_PROBES */
    uint32_t levels;        /* K, 2..64 */
    uint32_t height;        /* H of every level, 1..1024 (width 2H) */
    float parallax_min[3], parallax_max[3];
    prw_probe_desc probe[PRW_GPU_MAX_PROBES];
    const float *levels_rgb; /* count x K x H x 2H x 3, probe-major, rows top down */
} prw_probes;

/* std430 mirror of gi_probe.glsl's block */
typedef struct prw_gpu_probes {
    float head[4]; /* count, levels K, height H, 0 */
    float pmin[4], pmax[4];
    float p[PRW_GPU_MAX_PROBES][3][4]; /* (centre, slot + 1), (box min, 0), (box max, 0) */
} prw_gpu_probes;
_Static_assert(sizeof(prw_gpu_probes) == 48 + PRW_GPU_MAX_PROBES * 48, "prw_gpu_probes: std430 layout of gi_probe.glsl");

typedef struct prw_probe_gpu {
    bool active;
    uint32_t count;
    prw_buffer buf;
    prw_gpu_image levels, dfg;
} prw_probe_gpu;

/* max_count: the quality knob probe_count (0: none). */
bool prw_probe_gpu_create(prw_gpu *gpu, const prw_scene *s, const prw_probes *d, uint32_t max_count,
                          prw_probe_gpu **out, prw_error *e);
void prw_probe_gpu_destroy(prw_gpu *gpu, prw_probe_gpu *g);

#endif
