/* vk_count — an LD_PRELOAD shim that counts the barrier commands and render-pass begins a process
 * records (each flushes lavapipe's command stream) and prints the totals at exit:
 *   LD_PRELOAD=build/tests/tools/libvk_count.so prw render ...
 * It wraps the loader's exported entry points (prw calls them directly), forwarding to the next
 * definition; counts cover every command buffer of the process. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <vulkan/vulkan.h>

static unsigned long g_barriers, g_begins, g_submits;

static void report(void)
{
    fprintf(stderr, "vk_count: %lu barrier commands, %lu render-pass begins, %lu queue submits\n", g_barriers,
            g_begins, g_submits);
}

static void *next(const char *name)
{
    static int registered;
    if (!registered) {
        registered = 1;
        atexit(report);
    }
    return dlsym(RTLD_NEXT, name);
}

VKAPI_ATTR void VKAPI_CALL vkCmdPipelineBarrier2(VkCommandBuffer cmd, const VkDependencyInfo *d)
{
    static PFN_vkCmdPipelineBarrier2 f;
    if (!f) f = (PFN_vkCmdPipelineBarrier2)next("vkCmdPipelineBarrier2");
    g_barriers++;
    f(cmd, d);
}

VKAPI_ATTR void VKAPI_CALL vkCmdPipelineBarrier(VkCommandBuffer cmd, VkPipelineStageFlags src, VkPipelineStageFlags dst,
                                                VkDependencyFlags flags, uint32_t nm, const VkMemoryBarrier *m,
                                                uint32_t nb, const VkBufferMemoryBarrier *b, uint32_t ni,
                                                const VkImageMemoryBarrier *im)
{
    static PFN_vkCmdPipelineBarrier f;
    if (!f) f = (PFN_vkCmdPipelineBarrier)next("vkCmdPipelineBarrier");
    g_barriers++;
    f(cmd, src, dst, flags, nm, m, nb, b, ni, im);
}

VKAPI_ATTR void VKAPI_CALL vkCmdBeginRendering(VkCommandBuffer cmd, const VkRenderingInfo *ri)
{
    static PFN_vkCmdBeginRendering f;
    if (!f) f = (PFN_vkCmdBeginRendering)next("vkCmdBeginRendering");
    g_begins++;
    f(cmd, ri);
}

VKAPI_ATTR VkResult VKAPI_CALL vkQueueSubmit2(VkQueue q, uint32_t n, const VkSubmitInfo2 *s, VkFence fence)
{
    static PFN_vkQueueSubmit2 f;
    if (!f) f = (PFN_vkQueueSubmit2)next("vkQueueSubmit2");
    g_submits++;
    return f(q, n, s, fence);
}
