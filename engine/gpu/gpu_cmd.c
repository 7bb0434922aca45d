/* gpu_cmd.c — the command pool, one-shot submits with bounded waits, and VkResult naming. */
#include <math.h>
#include <stdlib.h>

#include "gpu_internal.h"

const char *prw_vk_result_name(VkResult r)
{
    switch (r) {
#define N(x) \
    case x: return #x;
        N(VK_SUCCESS) N(VK_NOT_READY) N(VK_TIMEOUT) N(VK_EVENT_SET) N(VK_EVENT_RESET) N(VK_INCOMPLETE)
        N(VK_ERROR_OUT_OF_HOST_MEMORY) N(VK_ERROR_OUT_OF_DEVICE_MEMORY) N(VK_ERROR_INITIALIZATION_FAILED)
        N(VK_ERROR_DEVICE_LOST) N(VK_ERROR_MEMORY_MAP_FAILED) N(VK_ERROR_LAYER_NOT_PRESENT)
        N(VK_ERROR_EXTENSION_NOT_PRESENT) N(VK_ERROR_FEATURE_NOT_PRESENT) N(VK_ERROR_INCOMPATIBLE_DRIVER)
        N(VK_ERROR_TOO_MANY_OBJECTS) N(VK_ERROR_FORMAT_NOT_SUPPORTED) N(VK_ERROR_FRAGMENTED_POOL)
        N(VK_ERROR_UNKNOWN) N(VK_ERROR_OUT_OF_POOL_MEMORY) N(VK_ERROR_INVALID_EXTERNAL_HANDLE)
        N(VK_ERROR_FRAGMENTATION) N(VK_ERROR_INVALID_OPAQUE_CAPTURE_ADDRESS) N(VK_PIPELINE_COMPILE_REQUIRED)
        N(VK_ERROR_SURFACE_LOST_KHR) N(VK_ERROR_NATIVE_WINDOW_IN_USE_KHR) N(VK_SUBOPTIMAL_KHR)
        N(VK_ERROR_OUT_OF_DATE_KHR) N(VK_ERROR_INCOMPATIBLE_DISPLAY_KHR) N(VK_ERROR_VALIDATION_FAILED_EXT)
#undef N
    default: return "VK_RESULT_UNKNOWN";
    }
}

bool prw_vk_check(VkResult r, const char *what, prw_error *e)
{
    if (r == VK_SUCCESS) return true;
    const char *hint = "";
    switch (r) {
    case VK_ERROR_DEVICE_LOST: hint = " (device lost)"; break;
    case VK_ERROR_OUT_OF_DEVICE_MEMORY: hint = " (out of device memory)"; break;
    case VK_ERROR_OUT_OF_HOST_MEMORY: hint = " (out of host memory)"; break;
    case VK_TIMEOUT: hint = " (GPU timeout)"; break;
    default: break;
    }
    return prw_fail(e, "%s: %s (%d)%s", what, prw_vk_result_name(r), (int)r, hint);
}

bool prw_cmd_init(prw_gpu *gpu, prw_error *e)
{
    VkCommandPoolCreateInfo ci = {
        .sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
        .flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT | VK_COMMAND_POOL_CREATE_TRANSIENT_BIT,
        .queueFamilyIndex = gpu->queue_family,
    };
    return prw_vk_check(vkCreateCommandPool(gpu->device, &ci, NULL, &gpu->cmd_pool), "gpu: vkCreateCommandPool", e);
}

static void free_orphans(prw_gpu *gpu)
{
    for (uint32_t i = 0; i < gpu->orphan_count; i++) {
        vkFreeCommandBuffers(gpu->device, gpu->cmd_pool, 1, &gpu->orphans[i].cmd);
        vkDestroyFence(gpu->device, gpu->orphans[i].fence, NULL);
    }
    free(gpu->orphans);
    gpu->orphans = NULL;
    gpu->orphan_count = 0;
}

void prw_cmd_shutdown(prw_gpu *gpu)
{
    free_orphans(gpu); /* called after vkDeviceWaitIdle */
    if (gpu->cmd_pool) vkDestroyCommandPool(gpu->device, gpu->cmd_pool, NULL);
    gpu->cmd_pool = VK_NULL_HANDLE;
}

bool prw_fence_wait(prw_gpu *gpu, VkFence fence, const char *what, prw_error *e)
{
    double t = gpu->timeout_s * 1e9;
    uint64_t ns = t >= 1.8e19 ? UINT64_MAX - 1 : (uint64_t)t;
    VkResult r = vkWaitForFences(gpu->device, 1, &fence, VK_TRUE, ns);
    if (r == VK_TIMEOUT)
        return prw_fail(e, "%s: GPU timeout: no completion after %.3g s (PRW_GPU_TIMEOUT_S)", what, gpu->timeout_s);
    return prw_vk_check(r, what, e);
}

bool prw_cmd_begin(prw_gpu *gpu, VkCommandBuffer *out, prw_error *e)
{
    VkCommandBufferAllocateInfo ai = {
        .sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
        .commandPool = gpu->cmd_pool,
        .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
        .commandBufferCount = 1,
    };
    if (!prw_vk_check(vkAllocateCommandBuffers(gpu->device, &ai, out), "gpu: vkAllocateCommandBuffers", e))
        return false;
    VkCommandBufferBeginInfo bi = {
        .sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
        .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT,
    };
    if (!prw_vk_check(vkBeginCommandBuffer(*out, &bi), "gpu: vkBeginCommandBuffer", e)) {
        vkFreeCommandBuffers(gpu->device, gpu->cmd_pool, 1, out);
        return false;
    }
    return true;
}

/* Submits cmd (may be VK_NULL_HANDLE: an empty submit that only signals the fence) and waits. */
static bool submit_and_wait(prw_gpu *gpu, VkCommandBuffer cmd, const char *what, prw_error *e)
{
    VkFenceCreateInfo fci = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VkFence fence;
    if (!prw_vk_check(vkCreateFence(gpu->device, &fci, NULL, &fence), "gpu: vkCreateFence", e)) return false;
    VkCommandBufferSubmitInfo cbi = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO, .commandBuffer = cmd};
    VkSubmitInfo2 si = {
        .sType = VK_STRUCTURE_TYPE_SUBMIT_INFO_2,
        .commandBufferInfoCount = cmd ? 1 : 0,
        .pCommandBufferInfos = &cbi,
    };
    VkResult r = vkQueueSubmit2(gpu->queue, 1, &si, fence);
    if (r != VK_SUCCESS) {
        vkDestroyFence(gpu->device, fence, NULL);
        return prw_vk_check(r, "gpu: vkQueueSubmit2", e);
    }
    if (!prw_fence_wait(gpu, fence, what, e)) {
        /* Still (possibly) executing: keep both until the queue is known idle. */
        gpu->orphans = prw_realloc(gpu->orphans, (gpu->orphan_count + 1) * sizeof *gpu->orphans);
        gpu->orphans[gpu->orphan_count++] = (prw_orphan){.cmd = cmd, .fence = fence};
        return false;
    }
    vkDestroyFence(gpu->device, fence, NULL);
    return true;
}

bool prw_cmd_submit_wait(prw_gpu *gpu, VkCommandBuffer cmd, prw_error *e)
{
    VkResult r = vkEndCommandBuffer(cmd);
    if (r != VK_SUCCESS) {
        vkFreeCommandBuffers(gpu->device, gpu->cmd_pool, 1, &cmd);
        return prw_vk_check(r, "gpu: vkEndCommandBuffer", e);
    }
    uint32_t orphans_before = gpu->orphan_count;
    if (!submit_and_wait(gpu, cmd, "gpu: submit", e)) {
        if (gpu->orphan_count == orphans_before) vkFreeCommandBuffers(gpu->device, gpu->cmd_pool, 1, &cmd);
        return false;
    }
    vkFreeCommandBuffers(gpu->device, gpu->cmd_pool, 1, &cmd);
    return true;
}

bool prw_gpu_wait_idle(prw_gpu *gpu, prw_error *e)
{
    /* An empty submit signals its fence once everything before it on the (only) queue is done. */
    uint32_t orphans_before = gpu->orphan_count;
    if (!submit_and_wait(gpu, VK_NULL_HANDLE, "gpu: wait idle", e)) return false;
    if (orphans_before) {
        /* Earlier timed-out submits are complete now: their fences must be signalled, else the
         * device broke the submission order promise and we keep them. */
        VkResult r = VK_SUCCESS;
        for (uint32_t i = 0; i < gpu->orphan_count && r == VK_SUCCESS; i++)
            r = vkGetFenceStatus(gpu->device, gpu->orphans[i].fence);
        if (r == VK_SUCCESS) free_orphans(gpu);
    }
    return true;
}

void prw_cmd_viewport(VkCommandBuffer cmd, uint32_t width, uint32_t height)
{
    VkViewport vp = {.x = 0, .y = 0, .width = (float)width, .height = (float)height, .minDepth = 0, .maxDepth = 1};
    VkRect2D sc = {.offset = {0, 0}, .extent = {width, height}};
    vkCmdSetViewport(cmd, 0, 1, &vp);
    vkCmdSetScissor(cmd, 0, 1, &sc);
}
