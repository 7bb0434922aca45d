/* pass_reproject — the `stereo_reuse=reproject` quality knob (issue 5): a two-view frame shades the
 * left eye fully and reuses its colour for the right eye where the left eye saw the same surface.
 *
 * What it does (per-view loop backend only; prw_reproj_create refuses multiview):
 *  1. Left eye (view 0): exactly the base pass of a mono render (same pipelines and draws), but into a
 *     depth image that is kept and sampled afterwards.  So the left eye stays bit-identical to mono.
 *  2. Right eye (view 1), one single-sample rendering scope on a depth + stencil target:
 *     a. depth pre-pass: base.vert, no fragment shader, no colour writes;
 *     b. reprojection (shaders/reproject.glsl): base.vert again, depth test GREATER_OR_EQUAL against
 *        the pre-pass (reversed Z) without depth writes, so only the visible surface is written; a
 *        fragment that the left eye saw (the nearest left texel's depth, extended with a minmod slope,
 *        agrees with the fragment's own left depth to the relative tolerance; inside the left image;
 *        the left texel is not an MSAA edge: its samples spread no more than the neighbours' slope
 *        allows) writes the left colour and stencil 1; the others are discarded (holes, stencil 0);
 *     c. holes: the normal base shading (base.vert + base.frag) with depth GREATER_OR_EQUAL, no depth
 *        write and stencil EQUAL 0.  base.frag neither discards nor writes depth and the pass writes
 *        neither depth nor stencil, so lavapipe tests early and skips groups of fragments that all fail
 *        (measured: `stereo_reuse` test case `timing`, README).
 *  MSAA ("resolve first", then supersample the holes): lavapipe skips fragments that fail the
 *  depth/stencil test only in single-sample rendering; with 4x MSAA it runs the shader for them anyway
 *  (measured: a stencil-masked hole pass at 4x MSAA cost as much as shading every pixel).  So with
 *  msaa 4 the right eye is rendered single-sampled at 2x2 its size (4 shaded samples per pixel on an
 *  ordered grid) and box-filtered down (the downsample shader): reused samples take the left eye's
 *  *resolved* colour, left edge texels are not reused but shaded again, and hole pixels are
 *  anti-aliased by 2x2 supersampling instead of 4x MSAA (a small, reported difference: FLIP).  With
 *  msaa 1 the right eye renders at its size straight into its HDR image.
 *  Nothing else changes (shadow maps and tone mapping run as before).  The pass counts the right eye's
 *  triangles three times (pre-pass, reprojection, holes). */
#include <stdlib.h>
#include <string.h>

#include "prw_shaders.h"
#include "render_internal.h"

#define HDR_FORMAT VK_FORMAT_R16G16B16A16_SFLOAT
#define DEPTH_FORMAT VK_FORMAT_D32_SFLOAT
#define DS_FORMAT VK_FORMAT_D32_SFLOAT_S8_UINT
#define DEFAULT_TOLERANCE 0.01

typedef struct rp_ubo {
    prw_mat4 left_view_proj;
    float params[4];
} rp_ubo;

struct prw_reproj_state {
    uint32_t k;                /* right eye rendered at k x k its (internal) size: 2 with MSAA, else 1 */
    prw_gpu_image left_depth;  /* view 0's depth, kept for sampling */
    prw_gpu_image right_ds;    /* view 1's depth + stencil, single-sample, k x size */
    VkImageView right_ds_view; /* depth + stencil aspects, the attachment view */
    prw_gpu_image right_color; /* k = 2 only: the supersampled right eye */
    VkDescriptorSet down_set;  /* k = 2 only: right_color -> the view's HDR image */
    prw_buffer ubo;
    VkDescriptorSetLayout set_layout;
    VkDescriptorSet set;
    VkPipelineLayout layout; /* base sets 0, 1 + set 2; push constants as the base pass */
    VkPipeline pre[2][2], reproj[2][2], holes[2][2];
};

typedef enum rp_kind { RP_PRE = 0, RP_REPROJ, RP_HOLES } rp_kind;

/* The three pipelines of the right eye's scope (the base pass's vertex layout and cull variants). */
static bool make_pipe(prw_renderer *r, rp_kind kind, int two, int mirror, VkPipeline *out, prw_error *e)
{
    struct prw_reproj_state *s = r->rp;
    prw_spirv fcode = kind == RP_HOLES ? prw_shader_base_frag()
                      : r->samples != VK_SAMPLE_COUNT_1_BIT ? prw_shader_reproject_ms_frag()
                                                             : prw_shader_reproject_ss_frag();
    VkStencilOpState st = {.failOp = VK_STENCIL_OP_KEEP, .passOp = VK_STENCIL_OP_KEEP,
                           .depthFailOp = VK_STENCIL_OP_KEEP, .compareOp = VK_COMPARE_OP_ALWAYS,
                           .compareMask = 1, .writeMask = 0, .reference = 0};
    if (kind == RP_REPROJ) { /* accepted: stencil 1 */
        st.passOp = VK_STENCIL_OP_REPLACE;
        st.writeMask = 1;
        st.reference = 1;
    } else if (kind == RP_HOLES) { /* only stencil 0 */
        st.compareOp = VK_COMPARE_OP_EQUAL;
    }
    prw_graphics_desc d = prw_base_graphics_desc(r, s->layout); /* reversed Z, as the base pass */
    d.fs = kind == RP_PRE ? (prw_spirv){0} : fcode;
    d.depth_format = DS_FORMAT;
    d.samples = VK_SAMPLE_COUNT_1_BIT; /* the right eye is supersampled instead (see the header) */
    d.cull = two ? VK_CULL_MODE_NONE : VK_CULL_MODE_BACK_BIT;
    d.front_face = mirror ? VK_FRONT_FACE_CLOCKWISE : VK_FRONT_FACE_COUNTER_CLOCKWISE;
    d.depth_write = kind == RP_PRE;
    d.no_color_write = kind == RP_PRE;
    d.stencil_test = kind != RP_PRE;
    d.stencil = st;
    return prw_pipeline_graphics(r->gpu, &d, out, e) || prw_fail_wrap(e, "reproject");
}

static prw_gpu_image *view_out(prw_renderer *r, uint32_t vi)
{
    return r->desc.supersample > 1 ? &r->views[vi].hdr_ss : &r->views[vi].hdr;
}

bool prw_reproj_create(prw_renderer *r, prw_error *e)
{
    if (r->desc.stereo_reuse == PRW_STEREO_REUSE_OFF || r->desc.max_views < 2) return true;
    if (r->desc.stereo_reuse != PRW_STEREO_REUSE_REPROJECT)
        return prw_fail(e, "render: stereo_reuse %d unknown (off = 0, reproject = 1)", (int)r->desc.stereo_reuse);
    if (r->desc.views_backend != PRW_VIEWS_LOOP)
        return prw_fail(e, "render: stereo_reuse=reproject is implemented for the per-view loop backend only "
                           "(use --views-backend loop)");
    struct prw_reproj_state *s = prw_calloc(1, sizeof *s);
    r->rp = s;
    prw_gpu *gpu = r->gpu;
    s->k = r->samples != VK_SAMPLE_COUNT_1_BIT ? 2 : 1;
    uint32_t w = r->desc.width * r->desc.supersample, h = r->desc.height * r->desc.supersample;
    prw_image_desc ld = {.width = w, .height = h, .format = DEPTH_FORMAT, .samples = r->samples,
                         .usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT};
    prw_image_desc rd = {.width = s->k * w, .height = s->k * h, .format = DS_FORMAT,
                         .usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT};
    prw_image_desc rc = {.width = s->k * w, .height = s->k * h, .format = HDR_FORMAT,
                         .usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_STORAGE_BIT};
    if (!prw_image_create(gpu, &ld, &s->left_depth, e) || !prw_image_create(gpu, &rd, &s->right_ds, e) ||
        (s->k > 1 && !prw_image_create(gpu, &rc, &s->right_color, e)))
        return prw_fail_wrap(e, "render: stereo_reuse=reproject targets");
    VkImageViewCreateInfo vci = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO,
        .image = s->right_ds.image,
        .viewType = VK_IMAGE_VIEW_TYPE_2D,
        .format = DS_FORMAT,
        .subresourceRange = {VK_IMAGE_ASPECT_DEPTH_BIT | VK_IMAGE_ASPECT_STENCIL_BIT, 0, 1, 0, 1},
    };
    if (!prw_vk_check(vkCreateImageView(prw_gpu_device(gpu), &vci, NULL, &s->right_ds_view),
                      "reproject: vkCreateImageView", e))
        return false;
    VkDescriptorSetLayoutBinding b[3] = {
        {0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, NULL},
        {1, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, NULL},
        {2, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, NULL},
    };
    VkDescriptorSetLayout sets[3] = {r->globals_layout, r->material_layout, VK_NULL_HANDLE};
    if (!prw_desc_layout_create(gpu, b, 3, &s->set_layout, e)) return false;
    sets[2] = s->set_layout;
    if (!prw_pipeline_layout_create(gpu, sets, 3, 112, &s->layout, e) ||
        !prw_buffer_create(gpu, sizeof(rp_ubo), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, PRW_MEM_UPLOAD, &s->ubo, e) ||
        !prw_desc_alloc(gpu, r->pool, s->set_layout, &s->set, e) ||
        (s->k > 1 && !prw_desc_alloc(gpu, r->pool, r->tonemap_layout, &s->down_set, e)))
        return false;
    VkSampler nearest = prw_gpu_sampler(gpu, PRW_SAMPLER_NEAREST_CLAMP);
    prw_desc_write_buffer(gpu, s->set, 0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, &s->ubo, 0, sizeof(rp_ubo));
    prw_desc_write_image(gpu, s->set, 1, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, view_out(r, 0)->view, nearest,
                         VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    prw_desc_write_image(gpu, s->set, 2, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, s->left_depth.view, nearest,
                         VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    if (s->k > 1) {
        prw_desc_write_image(gpu, s->down_set, 0, 0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, s->right_color.view,
                             VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
        prw_desc_write_image(gpu, s->down_set, 1, 0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, view_out(r, 1)->view,
                             VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
    }
    for (int two = 0; two < 2; two++)
        for (int m = 0; m < 2; m++)
            if (!make_pipe(r, RP_PRE, two, m, &s->pre[two][m], e) ||
                !make_pipe(r, RP_REPROJ, two, m, &s->reproj[two][m], e) ||
                !make_pipe(r, RP_HOLES, two, m, &s->holes[two][m], e))
                return false;
    return true;
}

void prw_reproj_destroy(prw_renderer *r)
{
    struct prw_reproj_state *s = r->rp;
    if (!s) return;
    VkDevice dev = prw_gpu_device(r->gpu);
    for (int two = 0; two < 2; two++)
        for (int m = 0; m < 2; m++) {
            VkPipeline p[3] = {s->pre[two][m], s->reproj[two][m], s->holes[two][m]};
            for (int k = 0; k < 3; k++)
                if (p[k]) vkDestroyPipeline(dev, p[k], NULL);
        }
    if (s->layout) vkDestroyPipelineLayout(dev, s->layout, NULL);
    if (s->set_layout) vkDestroyDescriptorSetLayout(dev, s->set_layout, NULL);
    prw_buffer_destroy(r->gpu, &s->ubo);
    if (s->right_ds_view) vkDestroyImageView(dev, s->right_ds_view, NULL);
    prw_image_destroy(r->gpu, &s->right_ds);
    prw_image_destroy(r->gpu, &s->right_color);
    prw_image_destroy(r->gpu, &s->left_depth);
    free(s);
    r->rp = NULL;
}

/* Rendering scope: colour (resolved into resolve_to when color is multisampled) and depth [+ stencil]. */
static void begin_scope(VkCommandBuffer cmd, prw_gpu_image *color, prw_gpu_image *resolve_to, prw_gpu_image *depth,
                        VkImageView depth_view, bool stencil, bool store_depth, float clear_alpha)
{
    bool msaa = color->samples != VK_SAMPLE_COUNT_1_BIT;
    prw_cmd_transition(cmd, color, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    if (msaa) prw_cmd_transition(cmd, resolve_to, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    VkImageLayout dl = stencil ? VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL : VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
    prw_cmd_transition(cmd, depth, dl);
    VkRenderingAttachmentInfo ca = {
        .sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
        .imageView = color->view,
        .imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
        .resolveMode = msaa ? VK_RESOLVE_MODE_AVERAGE_BIT : VK_RESOLVE_MODE_NONE,
        .resolveImageView = msaa ? resolve_to->view : VK_NULL_HANDLE,
        .resolveImageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
        .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
        .storeOp = msaa ? VK_ATTACHMENT_STORE_OP_DONT_CARE : VK_ATTACHMENT_STORE_OP_STORE,
        .clearValue.color = {{0, 0, 0, clear_alpha}},
    };
    VkRenderingAttachmentInfo da = {
        .sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
        .imageView = depth_view,
        .imageLayout = dl,
        .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
        .storeOp = store_depth ? VK_ATTACHMENT_STORE_OP_STORE : VK_ATTACHMENT_STORE_OP_DONT_CARE,
        .clearValue.depthStencil = {0.0f, 0},
    };
    VkRenderingInfo ri = {
        .sType = VK_STRUCTURE_TYPE_RENDERING_INFO,
        .renderArea = {{0, 0}, {color->width, color->height}},
        .layerCount = 1,
        .colorAttachmentCount = 1,
        .pColorAttachments = &ca,
        .pDepthAttachment = &da,
        .pStencilAttachment = stencil ? &da : NULL,
    };
    vkCmdBeginRendering(cmd, &ri);
    prw_cmd_viewport(cmd, color->width, color->height);
}

typedef struct down_pc {
    uint32_t factor, width, height;
} down_pc;

bool prw_reproj_record_base(prw_frame_ctx *ctx, VkCommandBuffer cmd, prw_error *e)
{
    (void)e;
    prw_renderer *r = ctx->r;
    struct prw_reproj_state *s = r->rp;
    bool msaa = r->samples != VK_SAMPLE_COUNT_1_BIT;
    for (uint32_t vi = 0; vi < 2; vi++) {
        prw_gpu_globals g;
        prw_base_fill_globals(ctx, vi, &g);
        memcpy(r->views[vi].globals.mapped, &g, sizeof g);
    }
    /* left eye: the mono base pass, depth kept */
    prw_gpu_image *left_out = view_out(r, 0);
    begin_scope(cmd, msaa ? &r->views[0].msaa_color : left_out, left_out, &s->left_depth, s->left_depth.view, false,
                true, 1.0f);
    prw_base_record_draws(ctx, 0, cmd);
    vkCmdEndRendering(cmd);
    prw_cmd_transition(cmd, &s->left_depth, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    prw_cmd_transition(cmd, left_out, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);

    /* right eye: left eye's clip from the right eye's camera-relative frame */
    const prw_view *lv = &ctx->views[0];
    prw_dvec3 o = prw_render_view_origin(ctx, 1);
    prw_dmat4 to_origin = prw_dm4_identity();
    to_origin.m[12] = o.x;
    to_origin.m[13] = o.y;
    to_origin.m[14] = o.z;
    rp_ubo u;
    u.left_view_proj = prw_m4_from_d(prw_dm4_mul(prw_view_proj(lv), prw_dm4_mul(lv->view, to_origin)));
    double tol = r->desc.reproject_tolerance != 0 ? r->desc.reproject_tolerance : DEFAULT_TOLERANCE;
    u.params[0] = (float)tol;
    u.params[1] = (float)s->left_depth.width;
    u.params[2] = (float)s->left_depth.height;
    u.params[3] = r->desc.reproject_mark ? 0.0f : 1.0f;
    memcpy(s->ubo.mapped, &u, sizeof u);

    prw_gpu_image *right_out = view_out(r, 1), *target = s->k > 1 ? &s->right_color : right_out;
    /* marked: nothing drawn = nothing shaded, alpha 0 too */
    begin_scope(cmd, target, NULL, &s->right_ds, s->right_ds_view, true, false, r->desc.reproject_mark ? 0.0f : 1.0f);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, s->layout, 2, 1, &s->set, 0, NULL);
    ctx->pipes = s->pre;
    prw_base_record_draws(ctx, 1, cmd);
    ctx->pipes = s->reproj;
    prw_base_record_draws(ctx, 1, cmd);
    ctx->pipes = s->holes;
    prw_base_record_draws(ctx, 1, cmd);
    ctx->pipes = NULL;
    vkCmdEndRendering(cmd);
    if (s->k > 1) { /* 2x2 box filter into the view's image */
        prw_cmd_transition(cmd, &s->right_color, VK_IMAGE_LAYOUT_GENERAL);
        prw_cmd_transition(cmd, right_out, VK_IMAGE_LAYOUT_GENERAL);
        down_pc pc = {s->k, right_out->width, right_out->height};
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, r->downsample_pipe);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, r->storage2_layout_pl, 0, 1, &s->down_set, 0,
                                NULL);
        vkCmdPushConstants(cmd, r->storage2_layout_pl, VK_SHADER_STAGE_ALL, 0, sizeof pc, &pc);
        vkCmdDispatch(cmd, (pc.width + 7) / 8, (pc.height + 7) / 8, 1);
    }
    return true;
}
