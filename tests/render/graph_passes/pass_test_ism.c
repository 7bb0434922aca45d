/* test_ism — a stand-in for imperfect shadow maps: once per frame for the whole view set, every
 * drawable's shadow casters into a small depth atlas "ism_atlas" from one fixed virtual point light above
 * the scene (the SSDO stand-in samples it). */
#include "pipes.h"
#include "shadow_plan.h"
#include "tp_util.h"

static void setup(prw_setup *s)
{
    prw_image_decl d = {.format = VK_FORMAT_D32_SFLOAT, .size = PRW_SIZE_FIXED, .width = 128, .height = 128,
                        .shared = true};
    prw_setup_image(s, "ism_atlas", &d);
    prw_setup_use(s, "ism_atlas", PRW_USE_DEPTH);
}

static bool record(prw_pass_ctx *c, prw_error *e)
{
    const prw_render_env *env = c->env;
    const prw_scene *s = env->scene;
    tp_log_record("test_ism", c->view);
    prw_gpu_image *atlas = prw_pass_image(c, "ism_atlas");
    prw_dvec3 lo = s->bounds_min, hi = s->bounds_max, ctr = prw_v3_scale(prw_v3_add(lo, hi), 0.5);
    prw_dvec3 eye = prw_v3(ctr.x, hi.y + 0.1, ctr.z);
    prw_dmat4 view = prw_dm4_look_at(eye, ctr, prw_v3(0, 0, -1));
    prw_draw_view dv = {.shadow_view_proj = prw_dm4_mul(prw_dm4_frustum_rev_inf(-1, 1, -1, 1, 0.02), view)};
    VkRenderingAttachmentInfo da = {
        .sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
        .imageView = atlas->view,
        .imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
        .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
        .storeOp = VK_ATTACHMENT_STORE_OP_STORE,
    };
    VkRenderingInfo ri = {.sType = VK_STRUCTURE_TYPE_RENDERING_INFO, .renderArea = {{0, 0}, {128, 128}},
                          .layerCount = 1, .pDepthAttachment = &da};
    prw_draw_ctx dc = {.cmd = c->cmd, .kind = PRW_DRAW_SHADOW, .view = &dv, .pipes = env->pipes,
                       .recipe = &env->pipes->shadow, .sg = env->sg, .layout = env->pipes->shadow_layout};
    prw_pass_begin_rendering(c, &ri);
    if (prw_draw_bind(&dc, 0, false, false)) {
        prw_cmd_viewport(c->cmd, 128, 128);
        vkCmdSetDepthBias(c->cmd, 0.0f, 0.0f, 0.0f);
        prw_drawables_record(env->drawables, env, &dc);
    }
    prw_pass_end_rendering(c);
    return !dc.failed || prw_fail(e, "%s", dc.err.msg);
}

const prw_pass test_pass_ism = {
    .name = "test_ism",
    .scope = PRW_SCOPE_FRAME,
    .setup = setup,
    .record = record,
};
