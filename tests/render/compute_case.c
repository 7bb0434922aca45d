/* compute_case.c — see compute_case.h. */
#include <string.h>

#include "compute_case.h"
#include "prw_gpu.h"

enum { MAX_BUFS = 16 };

bool compute_case_run(prw_spirv shader, const compute_buffer *bufs, int nbufs, const compute_texture *tex,
                      const void *push, uint32_t push_size, uint32_t groups_x, prw_error *e)
{
    if (nbufs < 1 || nbufs > MAX_BUFS) return prw_fail(e, "compute_case: %d buffers (1..%d)", nbufs, MAX_BUFS);
    prw_gpu *gpu = NULL;
    prw_gpu_desc d = {.device_index = -1, .validation = true};
    if (!prw_gpu_create(&d, &gpu, e)) return false;
    prw_buffer buf[MAX_BUFS];
    memset(buf, 0, sizeof buf);
    prw_gpu_image image = {0};
    VkDescriptorSetLayoutBinding b[MAX_BUFS + 1];
    int nb = nbufs + (tex ? 1 : 0);
    for (int i = 0; i < nbufs; i++)
        b[i] = (VkDescriptorSetLayoutBinding){(uint32_t)i, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, NULL};
    if (tex)
        b[nbufs] = (VkDescriptorSetLayoutBinding){(uint32_t)nbufs, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1,
                                                  VK_SHADER_STAGE_COMPUTE_BIT, NULL};
    VkDescriptorSetLayout dsl = VK_NULL_HANDLE;
    VkPipelineLayout pl = VK_NULL_HANDLE;
    VkPipeline pipe = VK_NULL_HANDLE;
    prw_desc_pool *pool = NULL;
    VkDescriptorSet set;
    VkCommandBuffer cmd;
    bool ok = true;
    for (int i = 0; ok && i < nbufs; i++)
        ok = prw_buffer_create(gpu, bufs[i].size, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                               bufs[i].readback ? PRW_MEM_READBACK : PRW_MEM_UPLOAD, &buf[i], e);
    if (ok && tex) {
        prw_image_desc td = {.width = tex->width, .height = tex->height, .layers = tex->layers,
                             .format = VK_FORMAT_R32G32B32A32_SFLOAT,
                             .usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                             .view_type = VK_IMAGE_VIEW_TYPE_2D_ARRAY};
        size_t layer = (size_t)tex->width * tex->height * 4;
        ok = prw_image_create(gpu, &td, &image, e);
        for (uint32_t l = 0; ok && l < tex->layers; l++)
            ok = prw_image_upload(gpu, &image, l, tex->texels + l * layer, layer * sizeof(float), e);
    }
    ok = ok && prw_desc_layout_create(gpu, b, (uint32_t)nb, &dsl, e) &&
         prw_pipeline_layout_create(gpu, &dsl, 1, push_size, &pl, e) && prw_pipeline_compute(gpu, shader, pl, &pipe, e) &&
         prw_desc_pool_create(gpu, &pool, e) && prw_desc_alloc(gpu, pool, dsl, &set, e);
    if (ok) {
        for (int i = 0; i < nbufs; i++) {
            if (bufs[i].data) memcpy(buf[i].mapped, bufs[i].data, bufs[i].size);
            else memset(buf[i].mapped, 0, bufs[i].size);
            prw_desc_write_buffer(gpu, set, (uint32_t)i, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &buf[i], 0, VK_WHOLE_SIZE);
        }
        if (tex)
            prw_desc_write_image(gpu, set, (uint32_t)nbufs, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, image.view,
                                 prw_gpu_sampler(gpu, PRW_SAMPLER_LINEAR_CLAMP), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
        ok = prw_cmd_begin(gpu, &cmd, e);
    }
    if (ok) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipe);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pl, 0, 1, &set, 0, NULL);
        if (push_size) vkCmdPushConstants(cmd, pl, VK_SHADER_STAGE_ALL, 0, push_size, push);
        vkCmdDispatch(cmd, groups_x, 1, 1);
        VkMemoryBarrier2 mb = {VK_STRUCTURE_TYPE_MEMORY_BARRIER_2, NULL, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                               VK_ACCESS_2_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT};
        VkDependencyInfo di = {.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO, .memoryBarrierCount = 1, .pMemoryBarriers = &mb};
        vkCmdPipelineBarrier2(cmd, &di);
        ok = prw_cmd_submit_wait(gpu, cmd, e);
    }
    for (int i = 0; ok && i < nbufs; i++)
        if (bufs[i].readback) memcpy(bufs[i].readback, buf[i].mapped, bufs[i].size);
    if (pool) prw_desc_pool_destroy(gpu, pool);
    if (pipe) prw_pipeline_release(gpu, pipe);
    if (pl) vkDestroyPipelineLayout(prw_gpu_device(gpu), pl, NULL);
    if (dsl) vkDestroyDescriptorSetLayout(prw_gpu_device(gpu), dsl, NULL);
    if (tex) prw_image_destroy(gpu, &image);
    for (int i = 0; i < nbufs; i++) prw_buffer_destroy(gpu, &buf[i]);
    prw_gpu_destroy(gpu);
    return ok;
}
