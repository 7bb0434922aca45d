/* compose — the HMD panel composition on the GPU; see prw_compose.h.  One compute dispatch over
 * the panel; eye images are sampled with texelFetch and filtered in the shader exactly as the C
 * reference does (no sampler filtering, so C and GPU agree up to float rounding). */
#include <stdlib.h>
#include <string.h>

#include "prw_compose.h"
#include "prw_shaders.h"

#define EYE_FORMAT VK_FORMAT_R32G32B32A32_SFLOAT

typedef struct compose_pc {
    int32_t size[4], size2[4];
    float screen[4], k[4], ca[4], tan0[4], tan1[4], lens_x[4];
} compose_pc;

struct prw_composer {
    prw_gpu *gpu;
    VkDescriptorSetLayout set_layout;
    VkPipelineLayout layout;
    VkPipeline pipe;
    prw_desc_pool *pool;
    prw_gpu_image eye[2], out;
};

bool prw_composer_create(prw_gpu *gpu, prw_composer **out, prw_error *e)
{
    *out = NULL;
    prw_composer *c = prw_calloc(1, sizeof *c);
    c->gpu = gpu;
    VkDescriptorSetLayoutBinding b[2] = {
        {0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 2, VK_SHADER_STAGE_COMPUTE_BIT, NULL},
        {1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, NULL},
    };
    if (!prw_desc_layout_create(gpu, b, 2, &c->set_layout, e) ||
        !prw_pipeline_layout_create(gpu, &c->set_layout, 1, sizeof(compose_pc), &c->layout, e) ||
        !prw_pipeline_compute(gpu, prw_shader_hmd_compose_comp(), c->layout, &c->pipe, e) ||
        !prw_desc_pool_create(gpu, &c->pool, e)) {
        prw_composer_destroy(c);
        return false;
    }
    *out = c;
    return true;
}

void prw_composer_destroy(prw_composer *c)
{
    if (!c) return;
    prw_error ignored;
    prw_gpu_wait_idle(c->gpu, &ignored);
    VkDevice dev = prw_gpu_device(c->gpu);
    prw_image_destroy(c->gpu, &c->eye[0]);
    prw_image_destroy(c->gpu, &c->eye[1]);
    prw_image_destroy(c->gpu, &c->out);
    if (c->pipe) prw_pipeline_release(c->gpu, c->pipe);
    if (c->layout) vkDestroyPipelineLayout(dev, c->layout, NULL);
    if (c->set_layout) vkDestroyDescriptorSetLayout(dev, c->set_layout, NULL);
    if (c->pool) prw_desc_pool_destroy(c->gpu, c->pool);
    free(c);
}

static bool ensure_image(prw_composer *c, prw_gpu_image *img, uint32_t w, uint32_t h, VkImageUsageFlags usage,
                         prw_error *e)
{
    if (img->image && img->width == w && img->height == h) return true;
    prw_image_destroy(c->gpu, img);
    memset(img, 0, sizeof *img);
    prw_image_desc d = {.width = w, .height = h, .format = EYE_FORMAT, .usage = usage};
    return prw_image_create(c->gpu, &d, img, e);
}

static void fill_pc(const prw_compose_params *p, compose_pc *pc)
{
    memset(pc, 0, sizeof *pc);
    pc->size[0] = (int32_t)p->mode;
    pc->size[1] = (int32_t)p->out_w;
    pc->size[2] = (int32_t)p->out_h;
    pc->size[3] = (int32_t)p->eye_w;
    pc->size2[0] = (int32_t)p->eye_h;
    float screen[4] = {(float)p->screen_w, (float)p->screen_h, (float)p->lens_unit, (float)p->eye_to_screen};
    memcpy(pc->screen, screen, sizeof screen);
    for (int i = 0; i < 4; i++) {
        pc->k[i] = (float)p->k[i];
        pc->ca[i] = (float)p->ca[i];
        pc->tan0[i] = (float)p->tan[0][i];
        pc->tan1[i] = (float)p->tan[1][i];
    }
    pc->lens_x[0] = (float)p->lens_x[0];
    pc->lens_x[1] = (float)p->lens_x[1];
}

bool prw_composer_run(prw_composer *c, const prw_compose_params *p, const prw_image *left, const prw_image *right,
                      prw_image *out, prw_error *e)
{
    /* inputs are checked before out is cleared: out may hold an image the caller still owns */
    if (out == left || out == right)
        return prw_fail(e, "compose: the output image is the %s eye image; it must be a separate image",
                        out == right ? "right" : "left");
    if (p->out_w < 2 || p->out_w % 2 || p->out_h < 1 || p->out_w > 16384 || p->out_h > 16384)
        return prw_fail(e, "compose: panel %ux%u must have an even width in 2..16384", p->out_w, p->out_h);
    const prw_image *in[2] = {left, right};
    for (int k = 0; k < 2; k++)
        if (!in[k]->rgba || (uint32_t)in[k]->width != p->eye_w || (uint32_t)in[k]->height != p->eye_h)
            return prw_fail(e, "compose: %s eye image is %dx%d, expected %ux%u", k ? "right" : "left", in[k]->width,
                            in[k]->height, p->eye_w, p->eye_h);
    memset(out, 0, sizeof *out);
    VkImageUsageFlags in_usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    if (!ensure_image(c, &c->eye[0], p->eye_w, p->eye_h, in_usage, e) ||
        !ensure_image(c, &c->eye[1], p->eye_w, p->eye_h, in_usage, e) ||
        !ensure_image(c, &c->out, p->out_w, p->out_h, VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, e))
        return false;
    size_t bytes = (size_t)p->eye_w * p->eye_h * 4 * sizeof(float);
    if (!prw_image_upload(c->gpu, &c->eye[0], 0, left->rgba, bytes, e) ||
        !prw_image_upload(c->gpu, &c->eye[1], 0, right->rgba, bytes, e))
        return false;
    prw_desc_pool_reset(c->gpu, c->pool);
    VkDescriptorSet set;
    if (!prw_desc_alloc(c->gpu, c->pool, c->set_layout, &set, e)) return false;
    VkSampler smp = prw_gpu_sampler(c->gpu, PRW_SAMPLER_NEAREST_CLAMP);
    for (uint32_t k = 0; k < 2; k++)
        prw_desc_write_image(c->gpu, set, 0, k, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, c->eye[k].view, smp,
                             VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    prw_desc_write_image(c->gpu, set, 1, 0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, c->out.view, VK_NULL_HANDLE,
                         VK_IMAGE_LAYOUT_GENERAL);
    compose_pc pc;
    fill_pc(p, &pc);
    VkCommandBuffer cmd;
    if (!prw_cmd_begin(c->gpu, &cmd, e)) return false;
    prw_cmd_transition(cmd, &c->eye[0], VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    prw_cmd_transition(cmd, &c->eye[1], VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    prw_cmd_transition(cmd, &c->out, VK_IMAGE_LAYOUT_GENERAL);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, c->pipe);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, c->layout, 0, 1, &set, 0, NULL);
    vkCmdPushConstants(cmd, c->layout, VK_SHADER_STAGE_ALL, 0, sizeof pc, &pc);
    vkCmdDispatch(cmd, (p->out_w + 7) / 8, (p->out_h + 7) / 8, 1);
    if (!prw_cmd_submit_wait(c->gpu, cmd, e)) return false;
    if (!prw_image_alloc(out, (int)p->out_w, (int)p->out_h, e)) return false;
    if (!prw_image_readback(c->gpu, &c->out, out->rgba, e)) {
        prw_image_free(out);
        return false;
    }
    return true;
}

bool prw_composer_view_set(prw_composer *c, const prw_gpu_image *left, const prw_gpu_image *right,
                           const prw_gpu_image *out, VkDescriptorSet *set, prw_error *e)
{
    if (!prw_desc_alloc(c->gpu, c->pool, c->set_layout, set, e)) return false;
    VkSampler smp = prw_gpu_sampler(c->gpu, PRW_SAMPLER_NEAREST_CLAMP);
    const prw_gpu_image *eye[2] = {left, right};
    for (uint32_t k = 0; k < 2; k++)
        prw_desc_write_image(c->gpu, *set, 0, k, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, eye[k]->view, smp,
                             VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    prw_desc_write_image(c->gpu, *set, 1, 0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, out->view, VK_NULL_HANDLE,
                         VK_IMAGE_LAYOUT_GENERAL);
    return true;
}

void prw_composer_record(prw_composer *c, VkCommandBuffer cmd, VkDescriptorSet set, const prw_compose_params *p)
{
    compose_pc pc;
    fill_pc(p, &pc);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, c->pipe);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, c->layout, 0, 1, &set, 0, NULL);
    vkCmdPushConstants(cmd, c->layout, VK_SHADER_STAGE_ALL, 0, sizeof pc, &pc);
    vkCmdDispatch(cmd, (p->out_w + 7) / 8, (p->out_h + 7) / 8, 1);
}
