/* gpu_buffer.c — buffers on suballocated memory, and uploads into them. */
#include <string.h>

#include "gpu_internal.h"

bool prw_buffer_create(prw_gpu *gpu, VkDeviceSize size, VkBufferUsageFlags usage, prw_mem_kind kind,
                       prw_buffer *out, prw_error *e)
{
    memset(out, 0, sizeof *out);
    if (size == 0) return prw_fail(e, "gpu: buffer of size 0");
    /* Transfer usage is always allowed: uploads, readbacks and clears then need no extra care. */
    VkBufferCreateInfo ci = {
        .sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO,
        .size = size,
        .usage = usage | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
        .sharingMode = VK_SHARING_MODE_EXCLUSIVE,
    };
    if (!prw_vk_check(vkCreateBuffer(gpu->device, &ci, NULL, &out->buffer), "gpu: vkCreateBuffer", e)) return false;
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(gpu->device, out->buffer, &req);
    if (!prw_mem_alloc(gpu, &req, kind, true, &out->alloc, e)) {
        vkDestroyBuffer(gpu->device, out->buffer, NULL);
        out->buffer = VK_NULL_HANDLE;
        return prw_fail_wrap(e, "gpu: buffer of %llu bytes", (unsigned long long)size);
    }
    VkResult r = vkBindBufferMemory(gpu->device, out->buffer, out->alloc.memory, out->alloc.offset);
    if (r != VK_SUCCESS) {
        prw_buffer_destroy(gpu, out);
        return prw_vk_check(r, "gpu: vkBindBufferMemory", e);
    }
    out->size = size;
    /* GPU buffers stay unmapped even on unified memory: callers rely on kind, not on luck. */
    out->mapped = kind == PRW_MEM_GPU ? NULL : out->alloc.mapped;
    return true;
}

void prw_buffer_destroy(prw_gpu *gpu, prw_buffer *b)
{
    if (!b) return;
    if (b->buffer) vkDestroyBuffer(gpu->device, b->buffer, NULL);
    prw_mem_free(gpu, &b->alloc);
    memset(b, 0, sizeof *b);
}

bool prw_buffer_upload(prw_gpu *gpu, prw_buffer *b, VkDeviceSize offset, const void *data, VkDeviceSize size,
                       prw_error *e)
{
    if (offset > b->size || size > b->size - offset)
        return prw_fail(e, "gpu: buffer upload of %llu bytes at %llu exceeds buffer size %llu",
                        (unsigned long long)size, (unsigned long long)offset, (unsigned long long)b->size);
    if (size == 0) return true;
    if (b->mapped) { /* coherent memory: a plain copy is visible to later submits */
        memcpy((char *)b->mapped + offset, data, size);
        return true;
    }
    prw_buffer staging;
    if (!prw_buffer_create(gpu, size, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, PRW_MEM_UPLOAD, &staging, e))
        return prw_fail_wrap(e, "gpu: buffer upload staging");
    memcpy(staging.mapped, data, size);
    VkCommandBuffer cmd;
    if (!prw_cmd_begin(gpu, &cmd, e)) {
        prw_buffer_destroy(gpu, &staging);
        return false;
    }
    VkBufferCopy region = {.srcOffset = 0, .dstOffset = offset, .size = size};
    vkCmdCopyBuffer(cmd, staging.buffer, b->buffer, 1, &region);
    /* Make the copy available and visible to whatever later submits do with the buffer. */
    VkMemoryBarrier2 mb = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER_2,
        .srcStageMask = VK_PIPELINE_STAGE_2_COPY_BIT,
        .srcAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT,
        .dstStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
        .dstAccessMask = VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT,
    };
    VkDependencyInfo dep = {.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO, .memoryBarrierCount = 1,
                            .pMemoryBarriers = &mb};
    vkCmdPipelineBarrier2(cmd, &dep);
    uint32_t orphans = gpu->orphan_count;
    bool ok = prw_cmd_submit_wait(gpu, cmd, e);
    /* After a timeout the copy may still be reading the staging buffer: leak it rather than free it. */
    if (ok || gpu->orphan_count == orphans) prw_buffer_destroy(gpu, &staging);
    return ok;
}
