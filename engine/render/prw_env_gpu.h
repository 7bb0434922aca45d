/* prw_env_gpu — the environment light on the GPU for the base pass's environment term (issue 16,
 * shaders/gi_env.glsl): the precomputation of materials/env (prw_env_file.h: SH9 irradiance,
 * prefiltered specular levels, split-sum table), filled by app/ from the env bake
 * (engine/bake/prw_env_bake.h; the renderer never links the baker) and handed to prw_renderer_create
 * through prw_render_desc.environment.
 *
 * Promises:
 *  - Globals set 0: binding 5 a storage buffer (prw_gpu_env: the 27 SH coefficients, the rotation's
 *    cos / sin, the level count and height), binding 6 the levels as one RGBA32F 2-D array (width 2H,
 *    height H, one layer per roughness level k / (K - 1); float32: no range check needed), binding 7
 *    the split-sum table as an N x N RG32F image (x: mu = (i + 0.5) / N, y: roughness j / (N - 1)).
 *  - Without an environment (NULL) `active` is false and the bindings name a zero block and 1 x 1
 *    black images; the base pipelines are then specialised exactly as before (PRW_SC_ENV unset), so
 *    nothing a scene without an environment draws changes.
 *  - The input is checked (sizes in range, every float finite); an error names what is wrong.
 *  - Uploaded once at create: a different environment needs a new renderer (as the light maps).
 */
#ifndef PRW_ENV_GPU_H
#define PRW_ENV_GPU_H

#include "prw_env_file.h"
#include "prw_gpu.h"

/* std140 mirror of gi_env.glsl's block */
typedef struct prw_gpu_env {
    float sh[9][4]; /* rgb, 0 */
    float rot[4];   /* cos rotation, sin rotation, levels K, height H */
} prw_gpu_env;
_Static_assert(sizeof(prw_gpu_env) == 160, "prw_gpu_env: std140 layout of gi_env.glsl");

typedef struct prw_env_gpu {
    bool active;
    prw_buffer ubo;
    prw_gpu_image levels, dfg;
} prw_env_gpu;

bool prw_env_gpu_create(prw_gpu *gpu, const prw_env_data *d, prw_env_gpu **out, prw_error *e);
void prw_env_gpu_destroy(prw_gpu *gpu, prw_env_gpu *g);

/* An equirect map set as one sampled 2D-array image (w x h, `layers` layers, RGBA32F): layer k from
 * rgb + k w h 3 (alpha 1), or zeros when rgb is NULL.  Shared by the environment and the probes. */
bool prw_env_gpu_rgb_layers(prw_gpu *gpu, uint32_t w, uint32_t h, uint32_t layers, const float *rgb,
                            prw_gpu_image *out, prw_error *e);
/* A sampled w x h RG32F image for the split-sum table (uploaded by the caller). */
bool prw_env_gpu_rg_image(prw_gpu *gpu, uint32_t w, uint32_t h, prw_gpu_image *out, prw_error *e);

#endif
