/* pass_multiview — the backends of the per-view passes (issue 5, DESIGN.md §6): choosing one, and
 * the Vulkan multiview base pass.  With multiview, a frame of two views draws the scene once with
 * view mask 0b11 into two-layer targets (4x MSAA colour, depth, resolved HDR); the vertex and
 * fragment shaders are base.vert / base.frag with gl_ViewIndex selecting the view's matrix and eye
 * (derived at configure time: shaders/CMakeLists.txt); all views share one camera-relative origin
 * (the first view's eye), so an eye matches a mono render up to float rounding, not bit for bit.
 * The resolved layers are then copied into the views' HDR images, so later passes are unchanged.
 * Frames of one view use the per-view loop.
 * On lavapipe (Mesa 22.3) this backend is wrong, not only slow: with view mask 0b11 the clipped
 * triangles of one view get mis-interpolated attributes (see test_stereo_gpu multiview_eyes), so the
 * "auto" choice (views_choice.c), which checks a probe pair against the loop, never picks it there. */
#include <stdlib.h>
#include <string.h>

#include "prw_shaders.h"
#include "render_internal.h"

#define HDR_FORMAT VK_FORMAT_R16G16B16A16_SFLOAT
#define DEPTH_FORMAT VK_FORMAT_D32_SFLOAT

typedef struct prw_mv_block {
    prw_mat4 view_proj[2];
    float eye_rel[2][4];
} prw_mv_block;

typedef struct prw_mv_state {
    VkDescriptorSetLayout set_layout;
    VkPipelineLayout layout;
    VkPipeline pipes[2][2]; /* [double-sided][mirrored] */
    prw_gpu_image color, depth, hdr; /* 2 layers */
    prw_buffer ubo;
    VkDescriptorSet set;
} prw_mv_state;

const char *prw_views_backend_name(prw_views_backend b) { return b == PRW_VIEWS_MULTIVIEW ? "multiview" : "loop"; }

bool prw_views_backend_resolve(prw_gpu *gpu, const char *name, prw_views_backend *out, prw_error *e)
{
    bool has_mv = prw_gpu_features_enabled(gpu)->multiview;
    const char *dev = prw_gpu_device_name(gpu);
    if (!name || strcmp(name, "auto") == 0) {
        prw_views_choice c;
        if (!prw_views_backend_choose(gpu, &c, e)) return false;
        *out = c.backend;
        return true;
    }
    if (strcmp(name, "loop") == 0) {
        *out = PRW_VIEWS_LOOP;
        return true;
    }
    if (strcmp(name, "multiview") == 0) {
        if (!has_mv) return prw_fail(e, "views backend multiview: device '%s' lacks the multiview feature", dev);
        *out = PRW_VIEWS_MULTIVIEW;
        return true;
    }
    return prw_fail(e, "views backend '%s': expected loop, multiview or auto", name);
}

bool prw_mv_create(prw_renderer *r, prw_error *e)
{
    if (!prw_gpu_features_enabled(r->gpu)->multiview)
        return prw_fail(e, "render: views backend multiview: the device lacks the multiview feature");
    if (r->desc.max_views < 2) return true; /* one view: the per-view loop is the same thing */
    if (r->desc.max_views != 2)
        return prw_fail(e, "render: views backend multiview supports 2 views (max_views %u)", r->desc.max_views);
    if (r->desc.supersample > 1) return prw_fail(e, "render: views backend multiview does not support supersampling");
    prw_mv_state *m = prw_calloc(1, sizeof *m);
    r->mv = m;
    VkDescriptorSetLayoutBinding b = {0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1,
                                      VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, NULL};
    if (!prw_desc_layout_create(r->gpu, &b, 1, &m->set_layout, e)) return false;
    VkDescriptorSetLayout sets[3] = {r->globals_layout, r->material_layout, m->set_layout};
    if (!prw_pipeline_layout_create(r->gpu, sets, 3, 112, &m->layout, e)) return false;
    prw_graphics_desc d = prw_base_graphics_desc(r, m->layout);
    d.vs = prw_shader_mv_base_vert();
    d.fs = prw_shader_mv_base_frag();
    d.view_mask = 0x3;
    for (int two = 0; two < 2; two++)
        for (int mirror = 0; mirror < 2; mirror++) {
            d.cull = two ? VK_CULL_MODE_NONE : VK_CULL_MODE_BACK_BIT;
            d.front_face = mirror ? VK_FRONT_FACE_CLOCKWISE : VK_FRONT_FACE_COUNTER_CLOCKWISE;
            if (!prw_pipeline_graphics(r->gpu, &d, &m->pipes[two][mirror], e)) return false;
        }
    bool msaa = r->samples != VK_SAMPLE_COUNT_1_BIT;
    uint32_t w = r->desc.width, h = r->desc.height;
    prw_image_desc color = {.width = w, .height = h, .layers = 2, .format = HDR_FORMAT, .samples = r->samples,
                            .usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSIENT_ATTACHMENT_BIT,
                            .view_type = VK_IMAGE_VIEW_TYPE_2D_ARRAY};
    prw_image_desc depth = {.width = w, .height = h, .layers = 2, .format = DEPTH_FORMAT, .samples = r->samples,
                            .usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
                            .view_type = VK_IMAGE_VIEW_TYPE_2D_ARRAY};
    prw_image_desc hdr = {.width = w, .height = h, .layers = 2, .format = HDR_FORMAT,
                          .usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                          .view_type = VK_IMAGE_VIEW_TYPE_2D_ARRAY};
    if ((msaa && !prw_image_create(r->gpu, &color, &m->color, e)) || !prw_image_create(r->gpu, &depth, &m->depth, e) ||
        !prw_image_create(r->gpu, &hdr, &m->hdr, e))
        return false;
    if (!prw_buffer_create(r->gpu, sizeof(prw_mv_block), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, PRW_MEM_UPLOAD, &m->ubo,
                           e) ||
        !prw_desc_alloc(r->gpu, r->pool, m->set_layout, &m->set, e))
        return false;
    prw_desc_write_buffer(r->gpu, m->set, 0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, &m->ubo, 0, sizeof(prw_mv_block));
    return true;
}

void prw_mv_destroy(prw_renderer *r)
{
    prw_mv_state *m = r->mv;
    if (!m) return;
    VkDevice dev = prw_gpu_device(r->gpu);
    for (int i = 0; i < 4; i++)
        if (m->pipes[i / 2][i % 2]) vkDestroyPipeline(dev, m->pipes[i / 2][i % 2], NULL);
    if (m->layout) vkDestroyPipelineLayout(dev, m->layout, NULL);
    if (m->set_layout) vkDestroyDescriptorSetLayout(dev, m->set_layout, NULL);
    prw_image_destroy(r->gpu, &m->color);
    prw_image_destroy(r->gpu, &m->depth);
    prw_image_destroy(r->gpu, &m->hdr);
    prw_buffer_destroy(r->gpu, &m->ubo);
    free(m);
    r->mv = NULL;
}

bool prw_mv_record_base(prw_frame_ctx *ctx, VkCommandBuffer cmd, prw_error *e)
{
    prw_renderer *r = ctx->r;
    prw_mv_state *m = r->mv;
    if (ctx->view_count != 2) return prw_fail(e, "multiview base pass: %u views (made for 2)", ctx->view_count);
    prw_dvec3 o = ctx->views[0].eye;
    prw_dmat4 to_origin = prw_dm4_identity();
    to_origin.m[12] = o.x;
    to_origin.m[13] = o.y;
    to_origin.m[14] = o.z;
    prw_mv_block blk;
    memset(&blk, 0, sizeof blk);
    for (uint32_t vi = 0; vi < 2; vi++) {
        const prw_view *v = &ctx->views[vi];
        prw_gpu_globals g;
        prw_base_fill_globals(ctx, vi, &g); /* relative to the first eye: lights, shadow matrices */
        memcpy(r->views[vi].globals.mapped, &g, sizeof g);
        blk.view_proj[vi] = prw_m4_from_d(prw_dm4_mul(prw_view_proj(v), prw_dm4_mul(v->view, to_origin)));
        blk.eye_rel[vi][0] = (float)(v->eye.x - o.x);
        blk.eye_rel[vi][1] = (float)(v->eye.y - o.y);
        blk.eye_rel[vi][2] = (float)(v->eye.z - o.z);
    }
    memcpy(m->ubo.mapped, &blk, sizeof blk);
    bool msaa = r->samples != VK_SAMPLE_COUNT_1_BIT;
    prw_gpu_image *color = msaa ? &m->color : &m->hdr;
    uint32_t w = r->desc.width, h = r->desc.height;
    prw_cmd_transition(cmd, color, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    if (msaa) prw_cmd_transition(cmd, &m->hdr, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    prw_cmd_transition(cmd, &m->depth, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL);
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
    vkCmdBeginRendering(cmd, &ri);
    prw_cmd_viewport(cmd, w, h);
    /* set 2 first (compatible with sets 0-1 bound later through the same layout) */
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, m->layout, 2, 1, &m->set, 0, NULL);
    /* the draws are the per-view loop's, with the multiview pipelines and layout swapped in */
    VkPipeline saved[2][2];
    memcpy(saved, r->base_pipes, sizeof saved);
    VkPipelineLayout saved_layout = r->base_layout;
    memcpy(r->base_pipes, m->pipes, sizeof saved);
    r->base_layout = m->layout;
    prw_base_record_draws(ctx, 0, cmd);
    memcpy(r->base_pipes, saved, sizeof saved);
    r->base_layout = saved_layout;
    vkCmdEndRendering(cmd);
    /* resolved layers -> the views' HDR images */
    prw_cmd_transition(cmd, &m->hdr, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    for (uint32_t vi = 0; vi < 2; vi++) {
        prw_gpu_image *dst = &r->views[vi].hdr;
        prw_cmd_transition(cmd, dst, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
        VkImageCopy region = {
            .srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, vi, 1},
            .dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
            .extent = {w, h, 1},
        };
        vkCmdCopyImage(cmd, m->hdr.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, dst->image,
                       VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
    }
    return true;
}
