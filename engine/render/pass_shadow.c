/* pass_shadow — the shadow atlas, once per frame for the whole view set (eye-independent work,
 * DESIGN.md §6): one depth layer per planned shadow view (shadow_plan.h), every drawable's shadow
 * casters drawn with the light's clip matrix.  Reversed Z: cleared to 0 (far), nearer occluders store
 * larger depth; a constant and slope depth bias pushes casters away from the light.  The atlas is cleared once at allocation, so the base pass samples "lit" when
 * this pass does not run. */
#include "pipes.h"
#include "prw_pass.h"
#include "shadow_plan.h"

static void setup(prw_setup *s)
{
    prw_image_decl d = {.format = PRW_DEPTH_FORMAT, .size = PRW_SIZE_SHADOW, .shared = true, .clear_at_create = true};
    prw_setup_image(s, "shadow_map", &d);
    prw_setup_use(s, "shadow_map", PRW_USE_DEPTH);
}

static bool needed(const prw_pass_ctx *c, const char **why)
{
    if (!c->env->shadows->count) return (*why = "no light casts shadows"), false;
    if (!prw_drawables_have(c->env->drawables, c->env, PRW_DRAW_SHADOW)) return (*why = "no shadow casters"), false;
    return true;
}

static bool record(prw_pass_ctx *c, prw_error *e)
{
    const prw_render_env *env = c->env;
    prw_gpu_image *map = prw_pass_image(c, "shadow_map");
    uint32_t size = env->desc->quality.shadow_size;
    for (uint32_t v = 0; v < env->shadows->count; v++) {
        VkRenderingAttachmentInfo depth = {
            .sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
            .imageView = map->layer_views[v],
            .imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
            .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
            .storeOp = VK_ATTACHMENT_STORE_OP_STORE,
            .clearValue.depthStencil = {0.0f, 0},
        };
        VkRenderingInfo ri = {
            .sType = VK_STRUCTURE_TYPE_RENDERING_INFO,
            .renderArea = {{0, 0}, {size, size}},
            .layerCount = 1,
            .pDepthAttachment = &depth,
        };
        prw_draw_view dv = {.shadow_view_proj = env->shadows->views[v].view_proj};
        /* reversed Z: the bias moves casters towards 0 (away from the light) */
        prw_draw_ctx dc = {.cmd = c->cmd, .kind = PRW_DRAW_SHADOW, .view = &dv, .pipes = env->pipes,
                           .recipe = &env->pipes->shadow, .sg = env->sg, .layout = env->pipes->shadow_layout,
                           .depth_bias = true, .bias_constant = -1.0f, .bias_slope = -1.5f};
        prw_pass_begin_rendering(c, &ri);
        prw_cmd_viewport(c->cmd, size, size);
        prw_drawables_record(env->drawables, env, &dc);
        prw_pass_end_rendering(c);
        if (dc.failed) return prw_fail(e, "%s", dc.err.msg);
    }
    return true;
}

const prw_pass prw_pass_shadow = {
    .name = "shadow",
    .scope = PRW_SCOPE_FRAME,
    .setup = setup,
    .needed = needed,
    .record = record,
};
