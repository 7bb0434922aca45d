/* pass_base_multiview — the base pass of a two-view frame drawn once with Vulkan multiview (views
 * backend "multiview", DESIGN.md §6): view mask 0b11 into two-layer targets of its own (colour, depth,
 * resolved HDR), then the resolved layers are copied into the views' "hdr" images, so later passes are
 * unchanged.  The shaders are base.vert / base.frag compiled with PRW_MULTIVIEW (gl_ViewIndex selects
 * the view's matrix and eye from a set-2 block); all views share one camera-relative origin (the first
 * view's eye), so an eye matches a mono render up to float rounding, not bit for bit.  Frames of one
 * view use the per-view base pass.  The views' "depth" images are not written.
 * On lavapipe (Mesa 22.3) this backend is wrong, not only slow: with view mask 0b11 the clipped
 * triangles of one view get mis-interpolated attributes (test_stereo_gpu multiview_eyes), so the
 * "auto" choice (views_backend.c), which checks a probe pair against the loop, never picks it there. */
#include <stdlib.h>
#include <string.h>

#include "pipes.h"
#include "prw_pass.h"
#include "view_globals.h"

typedef struct mv_block {
    prw_mat4 view_proj[2];
    float eye_rel[2][4];
} mv_block;

typedef struct mv_state {
    VkDescriptorSetLayout set_layout;
    VkPipelineLayout layout;
    prw_pipe_recipe recipe;
    prw_gpu_image color, depth, hdr; /* 2 layers */
    prw_buffer ubo;
    VkDescriptorSet set;
} mv_state;

static void setup(prw_setup *s)
{
    const prw_render_env *env = prw_setup_env(s);
    if (env->desc->views_backend != PRW_VIEWS_MULTIVIEW) return prw_setup_skip(s, "views backend is the per-view loop");
    if (env->desc->max_views != 2) return prw_setup_skip(s, "multiview needs a renderer for exactly 2 views");
    prw_setup_use(s, "hdr", PRW_USE_TRANSFER_DST);
    prw_setup_use(s, "shadow_map", PRW_USE_SAMPLED);
}

static bool describe(const prw_pipe_recipe *r, const prw_render_env *env, const prw_pipe_key *k, prw_graphics_desc *d,
                     prw_error *e)
{
    return prw_pipes_describe_base(env, k, r->layout, d, e);
}

static void destroy(const prw_pass_init *in, void *state)
{
    mv_state *m = state;
    if (!m) return;
    prw_gpu *gpu = in->env->gpu;
    VkDevice dev = prw_gpu_device(gpu);
    prw_pipes_forget(in->env->pipes, &m->recipe);
    if (m->layout) vkDestroyPipelineLayout(dev, m->layout, NULL);
    if (m->set_layout) vkDestroyDescriptorSetLayout(dev, m->set_layout, NULL);
    prw_image_destroy(gpu, &m->color);
    prw_image_destroy(gpu, &m->depth);
    prw_image_destroy(gpu, &m->hdr);
    prw_buffer_destroy(gpu, &m->ubo);
    free(m);
}

static bool create(const prw_pass_init *in, void **state, prw_error *e)
{
    const prw_render_env *env = in->env;
    prw_gpu *gpu = env->gpu;
    if (!prw_gpu_features_enabled(gpu)->multiview)
        return prw_fail(e, "render: views backend multiview: the device lacks the multiview feature");
    mv_state *m = prw_calloc(1, sizeof *m);
    *state = m;
    VkDescriptorSetLayoutBinding b = {0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1,
                                      VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, NULL};
    if (!prw_desc_layout_create(gpu, &b, 1, &m->set_layout, e)) return false;
    VkDescriptorSetLayout sets[3] = {env->pipes->globals_layout, env->pipes->material_layout, m->set_layout};
    if (!prw_pipeline_layout_create(gpu, sets, 3, PRW_DRAW_PUSH_BYTES, &m->layout, e)) return false;
    m->recipe = (prw_pipe_recipe){.name = "base_multiview", .layout = m->layout, .describe = describe};
    bool msaa = env->samples != VK_SAMPLE_COUNT_1_BIT;
    uint32_t w = env->desc->width, h = env->desc->height;
    prw_image_desc color = {.width = w, .height = h, .layers = 2, .format = prw_pipes_radiance_format(env), .samples = env->samples,
                            .usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSIENT_ATTACHMENT_BIT,
                            .view_type = VK_IMAGE_VIEW_TYPE_2D_ARRAY};
    prw_image_desc depth = {.width = w, .height = h, .layers = 2, .format = PRW_DEPTH_FORMAT, .samples = env->samples,
                            .usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
                            .view_type = VK_IMAGE_VIEW_TYPE_2D_ARRAY};
    prw_image_desc hdr = {.width = w, .height = h, .layers = 2, .format = prw_pipes_radiance_format(env),
                          .usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                          .view_type = VK_IMAGE_VIEW_TYPE_2D_ARRAY};
    if ((msaa && !prw_image_create(gpu, &color, &m->color, e)) || !prw_image_create(gpu, &depth, &m->depth, e) ||
        !prw_image_create(gpu, &hdr, &m->hdr, e))
        return false;
    if (!prw_buffer_create(gpu, sizeof(mv_block), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, PRW_MEM_UPLOAD, &m->ubo, e) ||
        !prw_desc_alloc(gpu, env->pool, m->set_layout, &m->set, e))
        return false;
    prw_desc_write_buffer(gpu, m->set, 0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, &m->ubo, 0, sizeof(mv_block));
    return true;
}

static bool needed(const prw_pass_ctx *c, const char **why)
{
    if (c->frame->mode != PRW_FRAME_MULTIVIEW) return (*why = "not a two-view frame"), false;
    return true;
}

static bool record(prw_pass_ctx *c, prw_error *e)
{
    const prw_render_env *env = c->env;
    mv_state *m = c->state;
    const prw_frame *f = c->frame;
    prw_dvec3 o = f->views[0].eye;
    mv_block blk;
    memset(&blk, 0, sizeof blk);
    for (uint32_t vi = 0; vi < 2; vi++) {
        const prw_view *v = &f->views[vi];
        blk.view_proj[vi] = prw_view_globals_view_proj(v, o);
        blk.eye_rel[vi][0] = (float)(v->eye.x - o.x);
        blk.eye_rel[vi][1] = (float)(v->eye.y - o.y);
        blk.eye_rel[vi][2] = (float)(v->eye.z - o.z);
    }
    memcpy(m->ubo.mapped, &blk, sizeof blk);
    bool msaa = env->samples != VK_SAMPLE_COUNT_1_BIT;
    prw_gpu_image *color = msaa ? &m->color : &m->hdr;
    uint32_t w = env->desc->width, h = env->desc->height;
    prw_pass_transition(c, color, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    if (msaa) prw_pass_transition(c, &m->hdr, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    prw_pass_transition(c, &m->depth, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL);
    VkRenderingAttachmentInfo ca = {
        .sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
        .imageView = color->view,
        .imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
        .resolveMode = msaa ? VK_RESOLVE_MODE_AVERAGE_BIT : VK_RESOLVE_MODE_NONE,
        .resolveImageView = msaa ? m->hdr.view : VK_NULL_HANDLE,
        .resolveImageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
        .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
        .storeOp = msaa ? VK_ATTACHMENT_STORE_OP_DONT_CARE : VK_ATTACHMENT_STORE_OP_STORE,
        .clearValue.color = {{0, 0, 0, 1}},
    };
    VkRenderingAttachmentInfo da = {
        .sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
        .imageView = m->depth.view,
        .imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
        .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
        .storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE,
        .clearValue.depthStencil = {0.0f, 0},
    };
    VkRenderingInfo ri = {
        .sType = VK_STRUCTURE_TYPE_RENDERING_INFO,
        .renderArea = {{0, 0}, {w, h}},
        .layerCount = 1,
        .viewMask = 0x3,
        .colorAttachmentCount = 1,
        .pColorAttachments = &ca,
        .pDepthAttachment = &da,
    };
    prw_pass_begin_rendering(c, &ri);
    prw_cmd_viewport(c->cmd, w, h);
    /* set 2 first (compatible with sets 0-1 bound later through the same layout) */
    vkCmdBindDescriptorSets(c->cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, m->layout, 2, 1, &m->set, 0, NULL);
    prw_draw_ctx dc = {.cmd = c->cmd, .kind = PRW_DRAW_COLOR, .view = &f->draw[0], .pipes = env->pipes,
                       .recipe = &m->recipe, .view_mask = 0x3, .sg = env->sg, .layout = m->layout};
    prw_drawables_record(env->drawables, env, &dc);
    if (prw_drawables_have(env->drawables, env, PRW_DRAW_BLEND)) { /* blended surfaces over the opaque image */
        dc.kind = PRW_DRAW_BLEND;
        prw_drawables_record(env->drawables, env, &dc);
    }
    prw_pass_end_rendering(c);
    c->frame->triangles += dc.triangles;
    c->frame->draws += dc.draws;
    if (dc.failed) return prw_fail(e, "%s", dc.err.msg);
    /* resolved layers -> the views' HDR images (in TRANSFER_DST by the graph) */
    prw_pass_transition(c, &m->hdr, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    for (uint32_t vi = 0; vi < 2; vi++) {
        prw_gpu_image *dst = prw_graph_image(c->graph, "hdr", vi);
        VkImageCopy region = {
            .srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, vi, 1},
            .dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
            .extent = {w, h, 1},
        };
        vkCmdCopyImage(c->cmd, m->hdr.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, dst->image,
                       VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
    }
    return true;
}

const prw_pass prw_pass_base_multiview = {
    .name = "base_multiview",
    .flags = PRW_PASS_RADIANCE,
    .scope = PRW_SCOPE_FRAME,
    .setup = setup,
    .create = create,
    .destroy = destroy,
    .needed = needed,
    .record = record,
};
