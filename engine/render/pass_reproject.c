/* pass_reproject — the `stereo_reuse=reproject` quality knob (issue 5): a two-view frame shades the
 * left eye fully (the base pass, view 0, depth kept) and reuses its colour for the right eye where the
 * left eye saw the same surface.
 *
 * What it does (per-view loop backend only; prw_reproj_create refuses multiview):
 *  1. Left eye (view 0): the base pass of a mono render (pass_base.c, its depth is kept), whose colour
 *     and depth this pass samples.  So the left eye stays bit-identical to mono.
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

#include "pipes.h"
#include "prw_pass.h"
#include "prw_shaders.h"
#include "scene_gpu.h"
#include "view_globals.h"

#define DS_FORMAT VK_FORMAT_D32_SFLOAT_S8_UINT
#define DEFAULT_TOLERANCE 0.01

typedef struct rp_ubo {
    prw_mat4 left_view_proj;
    float params[4];
} rp_ubo;

typedef enum rp_kind { RP_PRE = 0, RP_REPROJ, RP_HOLES } rp_kind;

typedef struct rp_state {
    uint32_t k;                /* right eye rendered at k x k its (internal) size: 2 with MSAA, else 1 */
    prw_gpu_image right_ds;    /* view 1's depth + stencil, single-sample, k x size */
    VkImageView right_ds_view; /* depth + stencil aspects, the attachment view */
    prw_gpu_image right_color; /* k = 2 only: the supersampled right eye */
    VkDescriptorSet down_set;  /* k = 2 only: right_color -> the view's HDR image */
    prw_buffer ubo;
    VkDescriptorSetLayout set_layout;
    VkDescriptorSet set;
    VkPipelineLayout layout;   /* base sets 0, 1 + set 2; push constants as the base pass */
    prw_pipe_recipe recipe;    /* variant: rp_kind */
} rp_state;

static const char *out_name(const prw_render_env *env) { return env->desc->quality.supersample > 1 ? "hdr_ss" : "hdr"; }

static void setup(prw_setup *s)
{
    const prw_render_env *env = prw_setup_env(s);
    if (env->desc->quality.stereo_reuse != PRW_STEREO_REUSE_REPROJECT) return prw_setup_skip(s, "stereo_reuse is off");
    if (env->desc->max_views < 2) return prw_setup_skip(s, "a renderer for one view");
    bool k2 = env->samples != VK_SAMPLE_COUNT_1_BIT;
    prw_setup_use_view(s, out_name(env), 0, PRW_USE_SAMPLED);
    prw_setup_use_view(s, "depth", 0, PRW_USE_SAMPLED);
    prw_setup_use_view(s, out_name(env), 1, k2 ? PRW_USE_STORAGE_WRITE : PRW_USE_COLOR);
    prw_setup_use(s, "shadow_map", PRW_USE_SAMPLED);
}

/* The three pipelines of the right eye's scope (the base pass's vertex layout and cull variants). */
static bool describe(const prw_pipe_recipe *r, const prw_render_env *env, const prw_pipe_key *key,
                     prw_graphics_desc *d, prw_error *e)
{
    rp_kind kind = (rp_kind)key->variant;
    prw_pipe_key base = *key;
    base.variant = PRW_BASE_VARIANT_PLAIN;
    if (!prw_pipes_describe_base(env, &base, r->layout, d, e)) return false; /* reversed Z, as the base pass */
    bool ext = (key->features & PRW_PIPE_EXT) != 0; /* opaque extension materials (no alpha: see needed()) */
    prw_spirv holes = !ext ? prw_shader_base_frag()
                      : key->features & PRW_PIPE_COAT ? prw_shader_coat_base_frag() : prw_shader_ext_base_frag();
    prw_spirv fcode = kind == RP_HOLES ? holes
                      : env->samples != VK_SAMPLE_COUNT_1_BIT ? prw_shader_reproject_ms_frag()
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
    d->fs = kind == RP_PRE ? (prw_spirv){0} : fcode;
    d->depth_format = DS_FORMAT;
    d->samples = VK_SAMPLE_COUNT_1_BIT; /* the right eye is supersampled instead (see the header) */
    d->depth_write = kind == RP_PRE;
    d->no_color_write = kind == RP_PRE;
    d->stencil_test = kind != RP_PRE;
    d->stencil = st;
    return true;
}

static void destroy(const prw_pass_init *in, void *state)
{
    rp_state *s = state;
    if (!s) return;
    prw_gpu *gpu = in->env->gpu;
    VkDevice dev = prw_gpu_device(gpu);
    prw_pipes_forget(in->env->pipes, &s->recipe);
    if (s->layout) vkDestroyPipelineLayout(dev, s->layout, NULL);
    if (s->set_layout) vkDestroyDescriptorSetLayout(dev, s->set_layout, NULL);
    prw_buffer_destroy(gpu, &s->ubo);
    if (s->right_ds_view) vkDestroyImageView(dev, s->right_ds_view, NULL);
    prw_image_destroy(gpu, &s->right_ds);
    prw_image_destroy(gpu, &s->right_color);
    free(s);
}

static bool create(const prw_pass_init *in, void **state, prw_error *e)
{
    const prw_render_env *env = in->env;
    if (env->desc->views_backend != PRW_VIEWS_LOOP)
        return prw_fail(e, "render: stereo_reuse=reproject is implemented for the per-view loop backend only "
                           "(use --views-backend loop)");
    rp_state *s = prw_calloc(1, sizeof *s);
    *state = s;
    prw_gpu *gpu = env->gpu;
    s->k = env->samples != VK_SAMPLE_COUNT_1_BIT ? 2 : 1;
    uint32_t w = env->desc->width * env->desc->quality.supersample, h = env->desc->height * env->desc->quality.supersample;
    prw_image_desc rd = {.width = s->k * w, .height = s->k * h, .format = DS_FORMAT,
                         .usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT};
    prw_image_desc rc = {.width = s->k * w, .height = s->k * h, .format = prw_pipes_radiance_format(env),
                         .usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_STORAGE_BIT};
    if (!prw_image_create(gpu, &rd, &s->right_ds, e) || (s->k > 1 && !prw_image_create(gpu, &rc, &s->right_color, e)))
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
    if (!prw_desc_layout_create(gpu, b, 3, &s->set_layout, e)) return false;
    VkDescriptorSetLayout sets[3] = {env->pipes->globals_layout, env->pipes->material_layout, s->set_layout};
    if (!prw_pipeline_layout_create(gpu, sets, 3, PRW_DRAW_PUSH_BYTES, &s->layout, e) ||
        !prw_buffer_create(gpu, sizeof(rp_ubo), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, PRW_MEM_UPLOAD, &s->ubo, e) ||
        !prw_desc_alloc(gpu, env->pool, s->set_layout, &s->set, e) ||
        (s->k > 1 && !prw_desc_alloc(gpu, env->pool, env->pipes->storage2_layout, &s->down_set, e)))
        return false;
    s->recipe = (prw_pipe_recipe){.name = "reproject", .layout = s->layout, .describe = describe};
    VkSampler nearest = prw_gpu_sampler(gpu, PRW_SAMPLER_NEAREST_CLAMP);
    prw_desc_write_buffer(gpu, s->set, 0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, &s->ubo, 0, sizeof(rp_ubo));
    prw_desc_write_image(gpu, s->set, 1, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                         prw_graph_image(in->graph, out_name(env), 0)->view, nearest,
                         VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    prw_desc_write_image(gpu, s->set, 2, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                         prw_graph_image(in->graph, "depth", 0)->view, nearest,
                         VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    if (s->k > 1) {
        prw_desc_write_image(gpu, s->down_set, 0, 0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, s->right_color.view,
                             VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
        prw_desc_write_image(gpu, s->down_set, 1, 0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                             prw_graph_image(in->graph, out_name(env), 1)->view, VK_NULL_HANDLE,
                             VK_IMAGE_LAYOUT_GENERAL);
    }
    return true;
}

static bool needed(const prw_pass_ctx *c, const char **why)
{
    if (c->frame->mode == PRW_FRAME_REPROJECT) return true;
    if (c->frame->view_count == 2 && c->env->sg->alpha_meshes)
        return (*why = "cut-out or blended materials: both eyes shaded"), false;
    return (*why = "not a two-view frame"), false;
}

typedef struct down_pc {
    uint32_t factor, width, height;
} down_pc;

static bool record(prw_pass_ctx *c, prw_error *e)
{
    const prw_render_env *env = c->env;
    rp_state *s = c->state;
    const prw_frame *f = c->frame;
    /* right eye: left eye's clip from the right eye's camera-relative frame */
    const prw_view *lv = &f->views[0];
    rp_ubo u;
    u.left_view_proj = prw_view_globals_view_proj(lv, f->draw[1].origin);
    const prw_render_debug *dbg = env->desc->debug;
    bool mark = dbg && dbg->reproject_mark;
    double tol = dbg && dbg->reproject_tolerance != 0 ? dbg->reproject_tolerance : DEFAULT_TOLERANCE;
    prw_gpu_image *left_depth = prw_graph_image(c->graph, "depth", 0);
    u.params[0] = (float)tol;
    u.params[1] = (float)left_depth->width;
    u.params[2] = (float)left_depth->height;
    u.params[3] = mark ? 0.0f : 1.0f;
    memcpy(s->ubo.mapped, &u, sizeof u);

    prw_gpu_image *right_out = prw_graph_image(c->graph, out_name(env), 1);
    prw_gpu_image *target = s->k > 1 ? &s->right_color : right_out;
    if (s->k > 1) prw_pass_transition(c, &s->right_color, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    prw_pass_transition(c, &s->right_ds, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL);
    VkRenderingAttachmentInfo ca = {
        .sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
        .imageView = target->view,
        .imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
        .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
        .storeOp = VK_ATTACHMENT_STORE_OP_STORE,
        /* marked: nothing drawn = nothing shaded, alpha 0 too */
        .clearValue.color = {{0, 0, 0, mark ? 0.0f : 1.0f}},
    };
    VkRenderingAttachmentInfo da = {
        .sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
        .imageView = s->right_ds_view,
        .imageLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
        .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
        .storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE,
        .clearValue.depthStencil = {0.0f, 0},
    };
    VkRenderingInfo ri = {
        .sType = VK_STRUCTURE_TYPE_RENDERING_INFO,
        .renderArea = {{0, 0}, {target->width, target->height}},
        .layerCount = 1,
        .colorAttachmentCount = 1,
        .pColorAttachments = &ca,
        .pDepthAttachment = &da,
        .pStencilAttachment = &da,
    };
    prw_pass_begin_rendering(c, &ri);
    prw_cmd_viewport(c->cmd, target->width, target->height);
    vkCmdBindDescriptorSets(c->cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, s->layout, 2, 1, &s->set, 0, NULL);
    bool failed = false;
    prw_error err = {{0}};
    for (int kind = RP_PRE; kind <= RP_HOLES && !failed; kind++) {
        prw_draw_ctx dc = {.cmd = c->cmd, .kind = kind == RP_PRE ? PRW_DRAW_DEPTH : PRW_DRAW_COLOR,
                           .view = &f->draw[1], .pipes = env->pipes, .recipe = &s->recipe, .variant = (uint32_t)kind,
                           .sg = env->sg, .layout = s->layout};
        prw_drawables_record(env->drawables, env, &dc);
        c->frame->triangles += dc.triangles;
        c->frame->draws += dc.draws;
        if (dc.failed) failed = true, err = dc.err;
    }
    prw_pass_end_rendering(c);
    if (failed) return prw_fail(e, "%s", err.msg);
    if (s->k > 1) { /* 2x2 box filter into the view's image (GENERAL by the graph) */
        prw_pass_transition(c, &s->right_color, VK_IMAGE_LAYOUT_GENERAL);
        down_pc pc = {s->k, right_out->width, right_out->height};
        vkCmdBindPipeline(c->cmd, VK_PIPELINE_BIND_POINT_COMPUTE, env->pipes->downsample);
        vkCmdBindDescriptorSets(c->cmd, VK_PIPELINE_BIND_POINT_COMPUTE, env->pipes->storage2_pl, 0, 1, &s->down_set, 0,
                                NULL);
        vkCmdPushConstants(c->cmd, env->pipes->storage2_pl, VK_SHADER_STAGE_ALL, 0, sizeof pc, &pc);
        vkCmdDispatch(c->cmd, (pc.width + 7) / 8, (pc.height + 7) / 8, 1);
    }
    return true;
}

const prw_pass prw_pass_reproject = {
    .name = "reproject",
    .flags = PRW_PASS_RADIANCE,
    .scope = PRW_SCOPE_FRAME,
    .setup = setup,
    .create = create,
    .destroy = destroy,
    .needed = needed,
    .record = record,
};
