/* pass_base — per view: emission + direct light (shadowed) into the HDR radiance target (4x MSAA
 * resolved by averaging in linear HDR, DESIGN.md §5), with the depth kept for later passes.  The
 * drawables' COLOR draws, then (when a drawable has any) their BLEND draws in the same scope: blended
 * surfaces over the opaque image, back to front, depth tested against it but not written (so the kept
 * depth and the G-buffer are the opaque surfaces').
 *
 * Targets: "hdr" (the view's output size) or, with N x N supersampling, "hdr_ss" (N times larger,
 * box-filtered by pass_downsample); "depth" (D32F, the renderer's samples, stored); with MSAA the
 * transient "msaa_color".  G-buffer, only when a later pass reads it: "gbuf_normal" (RGBA16F:
 * camera-relative shading normal, roughness) and "gbuf_id" (R32U: material slot + 1, 0 where nothing
 * was drawn), resolved from multisampled attachments (normal averaged, id sample 0).
 * The opaque draws run twice in the pass's scope: a depth pre-pass (no fragment shader), then shading
 * with depth EQUAL (on lavapipe a fragment costs all of its shader, so hidden ones are worth skipping).
 * With an environment (prw_env_gpu.h) and the direct term drawn, the environment seen directly fills what
 * no opaque surface covers (pipes.h's sky recipe), before the blended draws.
 * Not needed for a view that another pass renders: both views of a multiview frame
 * (pass_base_multiview), the right eye of a reprojected frame (pass_reproject). */
#include "pipes.h"
#include "prw_env_gpu.h"
#include "prw_pass.h"

static const char *out_name(const prw_render_env *env) { return env->desc->quality.supersample > 1 ? "hdr_ss" : "hdr"; }

static void setup(prw_setup *s)
{
    const prw_render_env *env = prw_setup_env(s);
    bool msaa = env->samples != VK_SAMPLE_COUNT_1_BIT;
    prw_image_decl hdr = {.format = prw_pipes_radiance_format(env), .size = PRW_SIZE_VIEW};
    prw_setup_image(s, "hdr", &hdr);
    prw_setup_export(s, "hdr");
    if (env->desc->quality.supersample > 1) {
        prw_image_decl ss = {.format = prw_pipes_radiance_format(env), .size = PRW_SIZE_INTERNAL};
        prw_setup_image(s, "hdr_ss", &ss);
    }
    prw_image_decl depth = {.format = PRW_DEPTH_FORMAT, .size = PRW_SIZE_INTERNAL, .msaa = true};
    prw_setup_image(s, "depth", &depth);
    prw_image_decl normal = {.format = PRW_NORMAL_FORMAT, .size = PRW_SIZE_INTERNAL};
    prw_image_decl id = {.format = PRW_MATID_FORMAT, .size = PRW_SIZE_INTERNAL};
    prw_setup_image(s, "gbuf_normal", &normal);
    prw_setup_image(s, "gbuf_id", &id);
    prw_setup_optional(s, "gbuf_normal");
    prw_setup_optional(s, "gbuf_id");
    if (msaa) {
        prw_image_decl c = {.format = prw_pipes_radiance_format(env), .size = PRW_SIZE_INTERNAL, .msaa = true, .transient = true};
        prw_setup_image(s, "msaa_color", &c);
        prw_setup_use(s, "msaa_color", PRW_USE_COLOR);
        prw_image_decl nm = normal, im = id;
        nm.msaa = im.msaa = nm.transient = im.transient = true;
        prw_setup_image(s, "gbuf_normal_ms", &nm);
        prw_setup_image(s, "gbuf_id_ms", &im);
        prw_setup_optional_with(s, "gbuf_normal_ms", "gbuf_normal");
        prw_setup_optional_with(s, "gbuf_id_ms", "gbuf_id");
        prw_setup_use(s, "gbuf_normal_ms", PRW_USE_COLOR);
        prw_setup_use(s, "gbuf_id_ms", PRW_USE_COLOR);
    }
    prw_setup_use(s, out_name(env), msaa ? PRW_USE_RESOLVE : PRW_USE_COLOR);
    prw_setup_use(s, "gbuf_normal", msaa ? PRW_USE_RESOLVE : PRW_USE_COLOR);
    prw_setup_use(s, "gbuf_id", msaa ? PRW_USE_RESOLVE : PRW_USE_COLOR);
    prw_setup_use(s, "depth", PRW_USE_DEPTH);
    prw_setup_use(s, "shadow_map", PRW_USE_SAMPLED);
}

static bool needed(const prw_pass_ctx *c, const char **why)
{
    if (c->frame->mode == PRW_FRAME_MULTIVIEW) return (*why = "both views drawn by base_multiview"), false;
    if (c->frame->mode == PRW_FRAME_REPROJECT && c->view == 1) return (*why = "right eye reprojected"), false;
    return true;
}

static bool record(prw_pass_ctx *c, prw_error *e)
{
    const prw_render_env *env = c->env;
    bool msaa = env->samples != VK_SAMPLE_COUNT_1_BIT;
    prw_gpu_image *out = prw_pass_image(c, out_name(env));
    prw_gpu_image *depth = prw_pass_image(c, "depth");
    prw_gpu_image *normal = prw_pass_image(c, "gbuf_normal"), *id = prw_pass_image(c, "gbuf_id");
    bool gbuf = normal && id;
    VkRenderingAttachmentInfo ca[3];
    ca[0] = prw_pipes_color_attachment(msaa ? prw_pass_image(c, "msaa_color") : out, msaa ? out : NULL,
                                       VK_RESOLVE_MODE_AVERAGE_BIT, 1);
    if (gbuf) {
        ca[1] = prw_pipes_color_attachment(msaa ? prw_pass_image(c, "gbuf_normal_ms") : normal, msaa ? normal : NULL,
                           VK_RESOLVE_MODE_AVERAGE_BIT, 0);
        ca[2] = prw_pipes_color_attachment(msaa ? prw_pass_image(c, "gbuf_id_ms") : id, msaa ? id : NULL,
                           VK_RESOLVE_MODE_SAMPLE_ZERO_BIT, 0);
    }
    VkRenderingAttachmentInfo da = prw_pipes_depth_attachment(depth); /* kept: later passes may read it */
    uint32_t w = out->width, h = out->height;
    VkRenderingInfo ri = {
        .sType = VK_STRUCTURE_TYPE_RENDERING_INFO,
        .renderArea = {{0, 0}, {w, h}},
        .layerCount = 1,
        .colorAttachmentCount = gbuf ? 3 : 1,
        .pColorAttachments = ca,
        .pDepthAttachment = &da,
    };
    /* a depth pre-pass, then shading with depth EQUAL: each visible sample shaded once (pipes.h
     * PRW_BASE_VARIANT_PREPASS / _EQUAL); alpha-tested draws keep the single-pass state */
    bool prepass = true;
    prw_draw_ctx dc = {.cmd = c->cmd, .kind = PRW_DRAW_COLOR, .view = &c->frame->draw[c->view], .pipes = env->pipes,
                       .recipe = &env->pipes->base, .variant = gbuf ? PRW_BASE_VARIANT_GBUFFER : PRW_BASE_VARIANT_PLAIN,
                       .sg = env->sg, .layout = env->pipes->base_layout};
    prw_pass_begin_rendering(c, &ri);
    prw_cmd_viewport(c->cmd, w, h);
    if (prepass) {
        /* depth of the opaque surfaces first, then shade only the fragments that stay visible */
        dc.variant = gbuf ? PRW_BASE_VARIANT_PREPASS_GBUFFER : PRW_BASE_VARIANT_PREPASS;
        prw_drawables_record(env->drawables, env, &dc);
        dc.variant = gbuf ? PRW_BASE_VARIANT_EQUAL_GBUFFER : PRW_BASE_VARIANT_EQUAL;
        dc.triangles = 0, dc.draws = 0;
    }
    prw_drawables_record(env->drawables, env, &dc);
    if (env->pipes->envlight && env->pipes->envlight->active && (env->desc->terms & PRW_TERM_DIRECT) && !dc.failed) {
        /* the environment seen directly (emission) where no surface is: one triangle at the far plane */
        prw_pipe_key k = {.recipe = &env->pipes->sky, .variant = gbuf ? PRW_BASE_VARIANT_GBUFFER : PRW_BASE_VARIANT_PLAIN};
        VkPipeline pl;
        if (prw_pipes_get(env->pipes, &k, &pl, &dc.err)) {
            vkCmdBindPipeline(c->cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pl);
            vkCmdBindDescriptorSets(c->cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, env->pipes->base_layout, 0, 1,
                                    &c->frame->draw[c->view].globals, 0, NULL);
            vkCmdDraw(c->cmd, 3, 1, 0, 0);
            dc.bound = pl; /* the blended draws rebind theirs */
        } else {
            dc.failed = true;
        }
    }
    if (prw_drawables_have(env->drawables, env, PRW_DRAW_BLEND)) { /* blended surfaces over the opaque image */
        dc.kind = PRW_DRAW_BLEND;
        dc.variant = gbuf ? PRW_BASE_VARIANT_GBUFFER : PRW_BASE_VARIANT_PLAIN; /* tested against the opaque depth */
        prw_drawables_record(env->drawables, env, &dc);
    }
    prw_pass_end_rendering(c);
    c->frame->triangles += dc.triangles;
    c->frame->draws += dc.draws;
    return !dc.failed || prw_fail(e, "%s", dc.err.msg);
}

const prw_pass prw_pass_base = {
    .name = "base",
    .flags = PRW_PASS_RADIANCE,
    .scope = PRW_SCOPE_VIEW,
    .setup = setup,
    .needed = needed,
    .record = record,
};
