/* prw_compose — the HMD panel composition on the GPU (shaders/hmd_compose.comp): two eye images ->
 * one panel image, plain side-by-side (debug view) or with barrel pre-distortion and per-channel
 * chromatic-aberration pre-correction.  The C reference and the parameters are prw_hmd.h
 * (prw_compose_params_*, prw_compose_cpu); the GPU result equals it up to float rounding (a test).
 * Works on any RGBA float data: linear HDR eye images (composed EXR) or display signals (PNG).
 */
#ifndef PRW_COMPOSE_H
#define PRW_COMPOSE_H

#include "prw_gpu.h"
#include "prw_hmd.h"
#include "prw_image.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct prw_composer prw_composer;

bool prw_composer_create(prw_gpu *gpu, prw_composer **out, prw_error *e);
void prw_composer_destroy(prw_composer *c);
/* Uploads left/right (p->eye_w x p->eye_h each), composes, reads the panel back into out
 * (allocated here, p->out_w x p->out_h, alpha 1).  out_w must be even; out must not be one of the
 * inputs.  On a refused input out is left as it was. */
bool prw_composer_run(prw_composer *c, const prw_compose_params *p, const prw_image *left, const prw_image *right,
                      prw_image *out, prw_error *e);
/* The same on GPU images, recorded into a caller's command buffer (the graph's "compose" pass): a set
 * naming left / right (sampled, SHADER_READ_ONLY) and out (RGBA32F storage, GENERAL) from the
 * composer's pool, then the dispatch.  Sets stay valid until the composer is destroyed. */
bool prw_composer_view_set(prw_composer *c, const prw_gpu_image *left, const prw_gpu_image *right,
                           const prw_gpu_image *out, VkDescriptorSet *set, prw_error *e);
void prw_composer_record(prw_composer *c, VkCommandBuffer cmd, VkDescriptorSet set, const prw_compose_params *p);

#ifdef __cplusplus
}
#endif
#endif
