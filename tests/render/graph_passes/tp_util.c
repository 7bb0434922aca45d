/* tp_util — shared pieces of the graph test's passes (tp_util.h). */
#include "tp_util.h"

#include <string.h>

#include "pipes.h"
#include "prw_test_shaders.h"

tp_log_entry tp_log[TP_LOG_MAX];
uint32_t tp_log_count;
uint64_t tp_mirror_triangles;

void tp_log_record(const char *pass, uint32_t view)
{
    if (tp_log_count < TP_LOG_MAX) tp_log[tp_log_count++] = (tp_log_entry){pass, view};
}

typedef struct tp_push {
    float w[4];
    int32_t mode[4];
} tp_push;

bool tp_fullscreen_create(const prw_render_env *env, bool ms_input1, tp_fullscreen *f, prw_error *e)
{
    memset(f, 0, sizeof *f);
    VkDescriptorSetLayoutBinding b[3] = {
        {0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, NULL},
        {1, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, NULL},
        {2, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, NULL},
    };
    if (!prw_desc_layout_create(env->gpu, b, 3, &f->set_layout, e) ||
        !prw_pipeline_layout_create(env->gpu, &f->set_layout, 1, sizeof(tp_push), &f->layout, e))
        return false;
    prw_graphics_desc d = {
        .vs = prw_shader_tp_fullscreen_vert(),
        .fs = ms_input1 ? prw_shader_tp_add_ms_frag() : prw_shader_tp_add_frag(),
        .layout = f->layout,
        .color_formats = {prw_pipes_radiance_format(env)},
        .color_count = 1,
        .blend_additive = true,
    };
    if (!prw_pipeline_graphics(env->gpu, &d, &f->pipe, e)) return false;
    for (uint32_t v = 0; v < env->desc->max_views; v++)
        if (!prw_desc_alloc(env->gpu, env->pool, f->set_layout, &f->sets[v], e)) return false;
    return true;
}

void tp_fullscreen_destroy(const prw_render_env *env, tp_fullscreen *f)
{
    VkDevice dev = prw_gpu_device(env->gpu);
    if (f->pipe) prw_pipeline_release(env->gpu, f->pipe);
    if (f->layout) vkDestroyPipelineLayout(dev, f->layout, NULL);
    if (f->set_layout) vkDestroyDescriptorSetLayout(dev, f->set_layout, NULL);
}

void tp_fullscreen_bind(const prw_render_env *env, tp_fullscreen *f, uint32_t view, const prw_gpu_image *in0,
                        const prw_gpu_image *in1, const prw_gpu_image *in2)
{
    const prw_gpu_image *in[3] = {in0, in1, in2};
    VkSampler s = prw_gpu_sampler(env->gpu, PRW_SAMPLER_NEAREST_CLAMP);
    for (uint32_t k = 0; k < 3; k++)
        prw_desc_write_image(env->gpu, f->sets[view], k, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, in[k]->view, s,
                             VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
}

void tp_fullscreen_add(const prw_pass_ctx *c, tp_fullscreen *f, prw_gpu_image *target, int mode, float weight)
{
    VkRenderingAttachmentInfo ca = {
        .sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
        .imageView = target->view,
        .imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
        .loadOp = VK_ATTACHMENT_LOAD_OP_LOAD,
        .storeOp = VK_ATTACHMENT_STORE_OP_STORE,
    };
    VkRenderingInfo ri = {
        .sType = VK_STRUCTURE_TYPE_RENDERING_INFO,
        .renderArea = {{0, 0}, {target->width, target->height}},
        .layerCount = 1,
        .colorAttachmentCount = 1,
        .pColorAttachments = &ca,
    };
    tp_push pc = {{weight, 0, (float)target->width, (float)target->height}, {mode, 0, 0, 0}};
    prw_pass_begin_rendering(c, &ri);
    prw_cmd_viewport(c->cmd, target->width, target->height);
    vkCmdBindPipeline(c->cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, f->pipe);
    vkCmdBindDescriptorSets(c->cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, f->layout, 0, 1, &f->sets[c->view], 0, NULL);
    vkCmdPushConstants(c->cmd, f->layout, VK_SHADER_STAGE_ALL, 0, sizeof pc, &pc);
    vkCmdDraw(c->cmd, 3, 1, 0, 0);
    prw_pass_end_rendering(c);
}

bool tp_texture(const prw_render_env *env, uint32_t w, uint32_t h, float value, prw_gpu_image *out, prw_error *e)
{
    prw_image_desc d = {.width = w, .height = h, .format = VK_FORMAT_R32G32B32A32_SFLOAT,
                        .usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT};
    float px[16 * 16 * 4];
    if (w * h > 16 * 16) return prw_fail(e, "tp_texture: at most 16 x 16");
    for (uint32_t i = 0; i < w * h * 4; i++) px[i] = value;
    return prw_image_create(env->gpu, &d, out, e) && prw_image_upload(env->gpu, out, 0, px, (size_t)w * h * 16, e);
}

bool tp_scene_mirror(const prw_scene *s, prw_dvec3 *n, double *d)
{
    for (uint32_t i = 0; i < s->node_count; i++) {
        const prw_node *nd = &s->nodes[i];
        if (strncmp(nd->name, "mirror", 6) != 0 || nd->mesh_group < 0) continue;
        const prw_mesh *m = &s->meshes[s->groups[nd->mesh_group].first];
        if (!m->vertex_count) continue;
        const double *w = nd->world.m;
        const float *p = m->positions, *q = m->normals;
        prw_dvec3 pw = prw_v3(w[0] * p[0] + w[4] * p[1] + w[8] * p[2] + w[12], w[1] * p[0] + w[5] * p[1] + w[9] * p[2] + w[13],
                              w[2] * p[0] + w[6] * p[1] + w[10] * p[2] + w[14]);
        /* the node is a rigid placement here: the normal turns with the 3x3 */
        *n = prw_v3_norm(prw_v3(w[0] * q[0] + w[4] * q[1] + w[8] * q[2], w[1] * q[0] + w[5] * q[1] + w[9] * q[2],
                                w[2] * q[0] + w[6] * q[1] + w[10] * q[2]));
        *d = prw_v3_dot(*n, pw);
        return true;
    }
    return false;
}
