/* pass_extra_work — a test knob, not a feature: adds a known amount of GPU work per frame so the
 * benchmark's A/B mode can be checked against a known slowdown (`prw bench --vs extra_gpu_work=0.2`).
 *
 * With f = desc.extra_gpu_work > 0 it replays the base pass's draws into a scratch colour target
 * (view_targets.extra_color, same format and sample count as the base pass) and the view's depth
 * buffer (whose content is not used after the base pass): floor(f) full-image replays, then the
 * fraction f - floor(f) of the image's rows, taken as the top rows of every 32-row band so the
 * selected pixels sample the whole image evenly (scissor per band).  The base pass is nearly all of
 * a frame's GPU time on lavapipe, so this adds roughly f x the frame (measured: 1.25-1.3 x for f = 0.2
 * at 1280x720, the replays cost more per row than the base pass); `prw bench --vs extra_gpu_work=F`
 * therefore calibrates the fraction with timestamps (app/bench_ab.c) before it times anything.  The pass runs after the tone
 * map and writes nothing any other pass reads: the image is unchanged.  Triangle and draw counts
 * of the frame stats are not affected.
 */
#include <math.h>

#include "render_internal.h"

#define BAND_ROWS 32u

static bool extra_needed(const prw_frame_ctx *ctx) { return ctx->r->desc.extra_gpu_work > 0 && ctx->view_count > 0; }

/* One replay of the base draws restricted to `fraction` (0, 1] of the rows of a w x h target. */
static void replay(prw_frame_ctx *ctx, uint32_t vi, VkCommandBuffer cmd, uint32_t w, uint32_t h, double fraction)
{
    for (uint32_t y0 = 0; y0 < h; y0 += BAND_ROWS) {
        uint32_t y1 = y0 + BAND_ROWS < h ? y0 + BAND_ROWS : h;
        /* rows chosen so far up to y1 minus those up to y0: the total is round(fraction * h) exactly */
        uint32_t rows = (uint32_t)lround(fraction * y1) - (uint32_t)lround(fraction * y0);
        if (rows == 0) continue;
        VkRect2D sc = {{0, (int32_t)y0}, {w, rows}};
        vkCmdSetScissor(cmd, 0, 1, &sc);
        prw_base_record_draws(ctx, vi, cmd);
    }
}

static bool extra_record(prw_frame_ctx *ctx, VkCommandBuffer cmd, prw_error *e)
{
    (void)e;
    prw_renderer *r = ctx->r;
    uint64_t triangles = ctx->triangles;
    uint32_t draws = ctx->draws;
    double f = r->desc.extra_gpu_work;
    for (uint32_t vi = 0; vi < ctx->view_count; vi++) {
        prw_view_targets *t = &r->views[vi];
        uint32_t w = t->extra_color.width, h = t->extra_color.height;
        prw_cmd_transition(cmd, &t->extra_color, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
        prw_cmd_transition(cmd, &t->depth, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL);
        VkRenderingAttachmentInfo ca = {
            .sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
            .imageView = t->extra_color.view,
            .imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
            .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
            .storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE,
        };
        VkRenderingAttachmentInfo da = {
            .sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
            .imageView = t->depth.view,
            .imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
            .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
            .storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE,
        };
        VkRenderingInfo ri = {
            .sType = VK_STRUCTURE_TYPE_RENDERING_INFO,
            .renderArea = {{0, 0}, {w, h}},
            .layerCount = 1,
            .colorAttachmentCount = 1,
            .pColorAttachments = &ca,
            .pDepthAttachment = &da,
        };
        vkCmdBeginRendering(cmd, &ri);
        prw_cmd_viewport(cmd, w, h);
        double whole = floor(f);
        for (double k = 0; k < whole; k++) replay(ctx, vi, cmd, w, h, 1.0);
        if (f > whole) replay(ctx, vi, cmd, w, h, f - whole);
        vkCmdEndRendering(cmd);
    }
    ctx->triangles = triangles;
    ctx->draws = draws;
    return true;
}

const prw_pass prw_pass_extra_work = {
    .name = "extra_work",
    .reads = PRW_RES_SCENE | PRW_RES_SHADOW,
    .writes = 0,
    .needed = extra_needed,
    .record = extra_record,
};
