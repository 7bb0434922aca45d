/* pass_floor — the base pass's floor, for speed figures (issue "Speed", DESIGN.md §5): what the base
 * pass would cost if shading were free.  Per view, in the same frame as the base pass and only when
 * the renderer times its passes (desc.timestamps), it records the base pass's draws once more — the same dynamic
 * rendering set-up (attachment formats, sample count, load/store and resolve ops, render area), the
 * same pipeline state and vertex shader (the base recipe, variant PRW_BASE_VARIANT_FLOOR: only the
 * fragment shader is floor.frag, a constant with no inputs and no descriptors) and the same draws
 * (every drawable's COLOR, then BLEND draws, once: not the base pass's depth pre-pass, whose time counts
 * in base) — into scratch targets of its own, so the image is
 * unchanged.  The base pass's G-buffer outputs are not mirrored (they exist only for a later pass
 * that reads them; none does in the benchmarks).  Its triangles and draws are not counted.
 * base/floor is the base passes' time (prw_pass_stat.flags & PRW_PASS_RADIANCE) over this pass's. */
#include "pipes.h"
#include "prw_pass.h"

static void setup(prw_setup *s)
{
    const prw_render_env *env = prw_setup_env(s);
    if (!env->desc->timestamps) return prw_setup_skip(s, "only with pass timestamps");
    bool msaa = env->samples != VK_SAMPLE_COUNT_1_BIT;
    prw_image_decl out = {.format = prw_pipes_radiance_format(env), .size = PRW_SIZE_INTERNAL, .transient = true};
    prw_setup_image(s, "floor_out", &out);
    prw_setup_use(s, "floor_out", msaa ? PRW_USE_RESOLVE : PRW_USE_COLOR);
    prw_image_decl depth = {.format = PRW_DEPTH_FORMAT, .size = PRW_SIZE_INTERNAL, .msaa = true, .transient = true};
    prw_setup_image(s, "floor_depth", &depth);
    prw_setup_use(s, "floor_depth", PRW_USE_DEPTH);
    if (msaa) {
        prw_image_decl c = {.format = prw_pipes_radiance_format(env), .size = PRW_SIZE_INTERNAL, .msaa = true, .transient = true};
        prw_setup_image(s, "floor_msaa", &c);
        prw_setup_use(s, "floor_msaa", PRW_USE_COLOR);
    }
    prw_setup_use(s, "shadow_map", PRW_USE_SAMPLED); /* bound by the draws' set 0, as in the base pass */
}

static bool needed(const prw_pass_ctx *c, const char **why)
{
    if (!c->env->desc->timestamps) return (*why = "only with pass timestamps"), false;
    if (c->frame->mode == PRW_FRAME_MULTIVIEW) return (*why = "the base pass is multiview (no floor variant)"), false;
    if (c->frame->mode == PRW_FRAME_REPROJECT && c->view == 1) return (*why = "right eye reprojected"), false;
    return true;
}

static bool record(prw_pass_ctx *c, prw_error *e)
{
    const prw_render_env *env = c->env;
    bool msaa = env->samples != VK_SAMPLE_COUNT_1_BIT;
    prw_gpu_image *out = prw_pass_image(c, "floor_out"), *depth = prw_pass_image(c, "floor_depth");
    prw_gpu_image *col = msaa ? prw_pass_image(c, "floor_msaa") : out;
    /* the base pass's attachment set-up (pass_base.c), colour 0 and depth */
    VkRenderingAttachmentInfo ca =
        prw_pipes_color_attachment(col, msaa ? out : NULL, VK_RESOLVE_MODE_AVERAGE_BIT, 1);
    VkRenderingAttachmentInfo da = prw_pipes_depth_attachment(depth);
    uint32_t w = out->width, h = out->height;
    VkRenderingInfo ri = {
        .sType = VK_STRUCTURE_TYPE_RENDERING_INFO,
        .renderArea = {{0, 0}, {w, h}},
        .layerCount = 1,
        .colorAttachmentCount = 1,
        .pColorAttachments = &ca,
        .pDepthAttachment = &da,
    };
    prw_draw_ctx dc = {.cmd = c->cmd, .kind = PRW_DRAW_COLOR, .view = &c->frame->draw[c->view], .pipes = env->pipes,
                       .recipe = &env->pipes->base, .variant = PRW_BASE_VARIANT_FLOOR, .sg = env->sg,
                       .layout = env->pipes->base_layout};
    prw_pass_begin_rendering(c, &ri);
    prw_cmd_viewport(c->cmd, w, h);
    prw_drawables_record(env->drawables, env, &dc);
    if (prw_drawables_have(env->drawables, env, PRW_DRAW_BLEND)) {
        dc.kind = PRW_DRAW_BLEND;
        prw_drawables_record(env->drawables, env, &dc);
    }
    prw_pass_end_rendering(c);
    return !dc.failed || prw_fail(e, "%s", dc.err.msg);
}

const prw_pass prw_pass_floor = {
    .name = "floor",
    .scope = PRW_SCOPE_VIEW,
    .flags = PRW_PASS_KEEP,
    .setup = setup,
    .needed = needed,
    .record = record,
};
