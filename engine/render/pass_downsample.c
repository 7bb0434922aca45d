/* pass_downsample — N x N supersampling for stills: box-filters the internal HDR image
 * (N*W x N*H) into the view's W x H HDR image.  Needed only when supersampling is on. */
#include "render_internal.h"

typedef struct downsample_pc {
    uint32_t factor, width, height;
} downsample_pc;

static bool downsample_needed(const prw_frame_ctx *ctx) { return ctx->r->desc.supersample > 1; }

static bool downsample_record(prw_frame_ctx *ctx, VkCommandBuffer cmd, prw_error *e)
{
    (void)e;
    prw_renderer *r = ctx->r;
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, r->downsample_pipe);
    for (uint32_t vi = 0; vi < ctx->view_count; vi++) {
        prw_view_targets *t = &r->views[vi];
        prw_cmd_transition(cmd, &t->hdr_ss, VK_IMAGE_LAYOUT_GENERAL);
        prw_cmd_transition(cmd, &t->hdr, VK_IMAGE_LAYOUT_GENERAL);
        downsample_pc pc = {r->desc.supersample, r->desc.width, r->desc.height};
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, r->storage2_layout_pl, 0, 1,
                                &t->downsample_set, 0, NULL);
        vkCmdPushConstants(cmd, r->storage2_layout_pl, VK_SHADER_STAGE_ALL, 0, sizeof pc, &pc);
        vkCmdDispatch(cmd, (pc.width + 7) / 8, (pc.height + 7) / 8, 1);
    }
    return true;
}

const prw_pass prw_pass_downsample = {
    .name = "downsample",
    .reads = PRW_RES_HDR_SS,
    .writes = PRW_RES_HDR,
    .needed = downsample_needed,
    .record = downsample_record,
};
