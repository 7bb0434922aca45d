/* pass_extra_work — a test knob, not a feature: adds a known amount of GPU work per frame so the
 * benchmark's A/B mode can be checked against a known slowdown (`prw bench --vs extra_gpu_work=0.2`).
 *
 * With f = desc.extra_gpu_work > 0 it replays the base pass's draws (every drawable) into a scratch
 * colour target ("extra_color", same format and sample count as the base pass) and the view's depth
 * buffer (the pass runs after every reader of it): floor(f) full-image replays, then the
 * fraction f - floor(f) of the image's rows, taken as the top rows of every 32-row band so the
 * selected pixels sample the whole image evenly (scissor per band).  The base pass is nearly all of
 * a frame's GPU time on lavapipe, so this adds roughly f x the frame (measured: 1.25-1.3 x for f = 0.2
 * at 1280x720, the replays cost more per row than the base pass); `prw bench --vs extra_gpu_work=F`
 * therefore calibrates the fraction with timestamps (app/bench_ab.c) before it times anything.  The
 * pass runs after the tone map and writes nothing any other pass reads (flagged KEEP so the graph does
 * not cull it): the image is unchanged.  Triangle and draw counts of the frame stats are not affected.
 */
#include <math.h>

#include "pipes.h"
#include "prw_pass.h"

#define BAND_ROWS 32u

static void setup(prw_setup *s)
{
    const prw_render_env *env = prw_setup_env(s);
    if (!(env->desc->quality.extra_gpu_work > 0)) return prw_setup_skip(s, "test knob extra_gpu_work is off");
    prw_image_decl d = {.format = prw_pipes_radiance_format(env), .size = PRW_SIZE_INTERNAL, .msaa = true, .transient = true};
    prw_setup_image(s, "extra_color", &d);
    prw_setup_use(s, "extra_color", PRW_USE_COLOR);
    prw_setup_use(s, "depth", PRW_USE_DEPTH);
    prw_setup_use(s, "shadow_map", PRW_USE_SAMPLED);
}

static bool needed(const prw_pass_ctx *c, const char **why)
{
    if (!(c->env->desc->quality.extra_gpu_work > 0)) return (*why = "test knob extra_gpu_work is off"), false;
    return true;
}

/* One replay of the base draws restricted to `fraction` (0, 1] of the rows of a w x h target. */
static void replay(const prw_pass_ctx *c, prw_draw_ctx *dc, uint32_t w, uint32_t h, double fraction)
{
    for (uint32_t y0 = 0; y0 < h; y0 += BAND_ROWS) {
        uint32_t y1 = y0 + BAND_ROWS < h ? y0 + BAND_ROWS : h;
        /* rows chosen so far up to y1 minus those up to y0: the total is round(fraction * h) exactly */
        uint32_t rows = (uint32_t)lround(fraction * y1) - (uint32_t)lround(fraction * y0);
        if (rows == 0) continue;
        VkRect2D sc = {{0, (int32_t)y0}, {w, rows}};
        vkCmdSetScissor(c->cmd, 0, 1, &sc);
        prw_drawables_record(c->env->drawables, c->env, dc);
    }
}

static bool record(prw_pass_ctx *c, prw_error *e)
{
    const prw_render_env *env = c->env;
    double f = env->desc->quality.extra_gpu_work;
    prw_gpu_image *color = prw_pass_image(c, "extra_color"), *depth = prw_pass_image(c, "depth");
    uint32_t w = color->width, h = color->height;
    VkRenderingAttachmentInfo ca = {
        .sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
        .imageView = color->view,
        .imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
        .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
        .storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE,
    };
    VkRenderingAttachmentInfo da = {
        .sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
        .imageView = depth->view,
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
    prw_draw_ctx dc = {.cmd = c->cmd, .kind = PRW_DRAW_COLOR, .view = &c->frame->draw[c->view], .pipes = env->pipes,
                       .recipe = &env->pipes->base, .sg = env->sg, .layout = env->pipes->base_layout};
    prw_pass_begin_rendering(c, &ri);
    prw_cmd_viewport(c->cmd, w, h);
    double whole = floor(f);
    for (double k = 0; k < whole; k++) replay(c, &dc, w, h, 1.0);
    if (f > whole) replay(c, &dc, w, h, f - whole);
    prw_pass_end_rendering(c);
    return !dc.failed || prw_fail(e, "%s", dc.err.msg); /* triangles and draws are not counted */
}

const prw_pass prw_pass_extra_work = {
    .name = "extra_work",
    .scope = PRW_SCOPE_VIEW,
    .flags = PRW_PASS_KEEP,
    .setup = setup,
    .needed = needed,
    .record = record,
};
