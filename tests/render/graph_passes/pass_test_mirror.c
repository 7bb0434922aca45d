/* test_mirror — a stand-in for the planar-mirror pass: per view, the scene's drawables re-rendered for
 * the view reflected in the scene's mirror (a node named "mirror*", tp_scene_mirror) into an HDR +
 * depth target of its own ("mirror_hdr", "mirror_depth"), with the winding flipped and a user clip
 * plane at the mirror.  Not in the graph when the scene has no mirror. */
#include <stdlib.h>
#include <string.h>

#include "gpu_types.h"
#include "pipes.h"
#include "tp_util.h"
#include "view_globals.h"

typedef struct mirror_state {
    prw_pipe_recipe recipe; /* the base recipe at one sample (the mirror image is not multisampled) */
    prw_buffer globals[PRW_MAX_VIEWS];
    VkDescriptorSet sets[PRW_MAX_VIEWS];
} mirror_state;

static void setup(prw_setup *s)
{
    prw_dvec3 n;
    double d;
    if (!tp_scene_mirror(prw_setup_env(s)->scene, &n, &d)) return prw_setup_skip(s, "no mirror in the scene");
    prw_image_decl hdr = {.format = prw_pipes_radiance_format(prw_setup_env(s)), .size = PRW_SIZE_VIEW};
    prw_image_decl depth = {.format = PRW_DEPTH_FORMAT, .size = PRW_SIZE_VIEW};
    prw_setup_image(s, "mirror_hdr", &hdr);
    prw_setup_image(s, "mirror_depth", &depth);
    prw_setup_use(s, "mirror_hdr", PRW_USE_COLOR);
    prw_setup_use(s, "mirror_depth", PRW_USE_DEPTH);
    prw_setup_use(s, "shadow_map", PRW_USE_SAMPLED);
}

static bool describe(const prw_pipe_recipe *r, const prw_render_env *env, const prw_pipe_key *k, prw_graphics_desc *d,
                     prw_error *e)
{
    if (!prw_pipes_describe_base(env, k, r->layout, d, e)) return false;
    d->samples = VK_SAMPLE_COUNT_1_BIT;
    return true;
}

static bool create(const prw_pass_init *in, void **state, prw_error *e)
{
    const prw_render_env *env = in->env;
    mirror_state *m = prw_calloc(1, sizeof *m);
    *state = m;
    m->recipe = (prw_pipe_recipe){.name = "test_mirror", .layout = env->pipes->base_layout, .describe = describe};
    prw_gpu_image *shadow = prw_graph_image(in->graph, "shadow_map", 0);
    for (uint32_t v = 0; v < env->desc->max_views; v++) {
        if (!prw_buffer_create(env->gpu, sizeof(prw_gpu_globals), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, PRW_MEM_UPLOAD,
                               &m->globals[v], e) ||
            !prw_desc_alloc(env->gpu, env->pool, env->pipes->globals_layout, &m->sets[v], e))
            return false;
        prw_desc_write_buffer(env->gpu, m->sets[v], 0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, &m->globals[v], 0,
                              sizeof(prw_gpu_globals));
        prw_pipes_write_globals(env->pipes, m->sets[v]);
        prw_desc_write_image(env->gpu, m->sets[v], 1, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, shadow->view,
                             prw_gpu_sampler(env->gpu, PRW_SAMPLER_SHADOW), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
        prw_desc_write_image(env->gpu, m->sets[v], 2, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, shadow->view,
                             prw_gpu_sampler(env->gpu, PRW_SAMPLER_SHADOW_DEPTH),
                             VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    }
    return true;
}

static void destroy(const prw_pass_init *in, void *state)
{
    mirror_state *m = state;
    if (!m) return;
    prw_pipes_forget(in->env->pipes, &m->recipe);
    for (uint32_t v = 0; v < PRW_MAX_VIEWS; v++) prw_buffer_destroy(in->env->gpu, &m->globals[v]);
    free(m);
}

static bool record(prw_pass_ctx *c, prw_error *e)
{
    const prw_render_env *env = c->env;
    mirror_state *m = c->state;
    tp_log_record("test_mirror", c->view);
    prw_dvec3 n;
    double d;
    if (!tp_scene_mirror(env->scene, &n, &d)) return prw_fail(e, "test_mirror: the mirror is gone");
    /* reflection in the plane n.x = d: x' = x - 2 (n.x - d) n */
    prw_dmat4 R = prw_dm4_identity();
    double nn[3] = {n.x, n.y, n.z};
    for (int col = 0; col < 3; col++)
        for (int row = 0; row < 3; row++) R.m[col * 4 + row] -= 2 * nn[row] * nn[col];
    for (int row = 0; row < 3; row++) R.m[12 + row] = 2 * d * nn[row];
    const prw_view *v = &c->frame->views[c->view];
    prw_view mv = *v;
    mv.view = prw_dm4_mul(v->view, R);
    prw_dvec3 e0 = v->eye;
    double s = prw_v3_dot(n, e0) - d;
    mv.eye = prw_v3_sub(e0, prw_v3_scale(n, 2 * s));
    prw_gpu_globals g;
    prw_view_globals_fill(env->scene, env->shadows, env->desc->quality.shadow_size, &mv, mv.eye, &g);
    memcpy(m->globals[c->view].mapped, &g, sizeof g);
    /* keep what lies on the real eye's side of the mirror (camera-relative to the mirrored eye) */
    float sign = s >= 0 ? 1.0f : -1.0f;
    prw_draw_view dv = {.origin = mv.eye, .eye = mv.eye, .globals = m->sets[c->view], .mirrored = true, .clip = true};
    dv.clip_plane[0] = sign * (float)n.x, dv.clip_plane[1] = sign * (float)n.y, dv.clip_plane[2] = sign * (float)n.z;
    dv.clip_plane[3] = sign * (float)(prw_v3_dot(n, mv.eye) - d);
    prw_gpu_image *hdr = prw_pass_image(c, "mirror_hdr"), *depth = prw_pass_image(c, "mirror_depth");
    VkRenderingAttachmentInfo ca = {
        .sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
        .imageView = hdr->view,
        .imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
        .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
        .storeOp = VK_ATTACHMENT_STORE_OP_STORE,
    };
    VkRenderingAttachmentInfo da = {
        .sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
        .imageView = depth->view,
        .imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
        .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
        .storeOp = VK_ATTACHMENT_STORE_OP_STORE,
    };
    VkRenderingInfo ri = {.sType = VK_STRUCTURE_TYPE_RENDERING_INFO, .renderArea = {{0, 0}, {hdr->width, hdr->height}},
                          .layerCount = 1, .colorAttachmentCount = 1, .pColorAttachments = &ca,
                          .pDepthAttachment = &da};
    prw_draw_ctx dc = {.cmd = c->cmd, .kind = PRW_DRAW_COLOR, .view = &dv, .pipes = env->pipes, .recipe = &m->recipe,
                       .sg = env->sg, .layout = env->pipes->base_layout};
    prw_pass_begin_rendering(c, &ri);
    prw_cmd_viewport(c->cmd, hdr->width, hdr->height);
    vkCmdPushConstants(c->cmd, env->pipes->base_layout, VK_SHADER_STAGE_ALL, PRW_CLIP_PUSH_OFFSET, 16, dv.clip_plane);
    prw_drawables_record(env->drawables, env, &dc);
    prw_pass_end_rendering(c);
    tp_mirror_triangles += dc.triangles;
    return !dc.failed || prw_fail(e, "%s", dc.err.msg);
}

const prw_pass test_pass_mirror = {
    .name = "test_mirror",
    .scope = PRW_SCOPE_VIEW,
    .setup = setup,
    .create = create,
    .destroy = destroy,
    .record = record,
};
