/* pass_tonemap — provisional display encoding (issue 6 replaces it): HDR * exposure, clamp, sRGB. */
#include <math.h>

#include "render_internal.h"

typedef struct tonemap_pc {
    float exposure;
    uint32_t width, height;
} tonemap_pc;

static bool tonemap_needed(const prw_frame_ctx *ctx) { return ctx->view_count > 0; }

static bool tonemap_record(prw_frame_ctx *ctx, VkCommandBuffer cmd, prw_error *e)
{
    (void)e;
    prw_renderer *r = ctx->r;
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, r->tonemap_pipe);
    for (uint32_t vi = 0; vi < ctx->view_count; vi++) {
        prw_view_targets *t = &r->views[vi];
        const prw_view *v = &ctx->views[vi];
        prw_cmd_transition(cmd, &t->hdr, VK_IMAGE_LAYOUT_GENERAL);
        prw_cmd_transition(cmd, &t->ldr, VK_IMAGE_LAYOUT_GENERAL);
        /* photometric exposure: luminance 1.2 * 2^EV100 cd/m^2 maps to display white */
        tonemap_pc pc = {(float)prw_exposure_scale(v->ev100), v->width, v->height};
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, r->tonemap_layout_pl, 0, 1, &t->tonemap_set, 0,
                                NULL);
        vkCmdPushConstants(cmd, r->tonemap_layout_pl, VK_SHADER_STAGE_ALL, 0, sizeof pc, &pc);
        vkCmdDispatch(cmd, (v->width + 7) / 8, (v->height + 7) / 8, 1);
    }
    return true;
}

const prw_pass prw_pass_tonemap = {
    .name = "tonemap",
    .reads = PRW_RES_HDR,
    .writes = PRW_RES_LDR,
    .needed = tonemap_needed,
    .record = tonemap_record,
};
