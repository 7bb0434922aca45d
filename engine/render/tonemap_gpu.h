/* tonemap_gpu — the GPU side of display-aware tone mapping (issue 6): pipelines, the parameter block,
 * the frame statistics and selective-tile buffers, per-view descriptor sets, adaptation state.  Used by
 * the graph passes "tm_stats" and "tonemap" (pass_tonemap.c), by tone-mapping sessions and by the
 * public tone-mapping calls of prw_render.h; the C reference of the operators is tonemap_ops.c.
 *
 * Promises:
 *  - prw_tm_gpu_record_stats / _apply record only dispatches and the barriers BETWEEN their own
 *    dispatches (counted through the pass); the graph orders the stats and tile buffers (imported by
 *    the passes) and the images against the other passes and the host.
 *  - The view sets name the images bound with prw_tm_gpu_bind_view (the graph's hdr, ldr and signal
 *    images of that view); bind every view before recording.  The float signal is written when it was
 *    bound (the 8-bit image always).
 */
#ifndef PRW_TONEMAP_GPU_H
#define PRW_TONEMAP_GPU_H

#include "prw_pass.h"
#include "prw_tonemap.h"

typedef struct prw_tm_gpu prw_tm_gpu;

bool prw_tm_gpu_create(prw_gpu *gpu, prw_desc_pool *pool, uint32_t width, uint32_t height, uint32_t max_views,
                       prw_tm_op op, prw_tm_gpu **out, prw_error *e);
void prw_tm_gpu_destroy(prw_tm_gpu *tm);
/* signal NULL: the graph dropped it (nobody reads it); the apply then writes the 8-bit image alone. */
bool prw_tm_gpu_bind_view(prw_tm_gpu *tm, uint32_t v, prw_gpu_image *hdr, prw_gpu_image *ldr, prw_gpu_image *signal,
                          prw_error *e);
VkBuffer prw_tm_gpu_stats_buffer(const prw_tm_gpu *tm);
VkBuffer prw_tm_gpu_tiles_buffer(const prw_tm_gpu *tm);
/* The adapted luminance of the last frame (false, *la = 0, when adaptation is off or has no value yet). */
bool prw_tm_gpu_adaptation(const prw_tm_gpu *tm, double *la);
/* Whether the "tm_stats" pass runs before the apply: the operator keys on the frame's statistics.
 * Otherwise, when the statistics or pixel counts are wanted (report, overlay, absolute, adaptation),
 * the "tonemap" pass computes them itself in the same pass over the image (tonemap_fused.comp). */
bool prw_tm_gpu_stats_needed(const prw_tm_gpu *tm);
/* The frame's statistics over every view of c->frame (inputs sampled, outputs: the stats buffer). */
void prw_tm_gpu_record_stats(prw_tm_gpu *tm, const prw_pass_ctx *c);
/* Operator -> gamut mapping -> inverse display model for every view; stats_ran: the statistics of this
 * frame were computed (adaptation and pixel counts use them). */
bool prw_tm_gpu_record_apply(prw_tm_gpu *tm, const prw_pass_ctx *c, bool stats_ran, prw_error *e);

#endif
