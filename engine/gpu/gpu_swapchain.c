/* gpu_swapchain.c — presenting to a GLFW window: surface, swapchain (recreated on resize / out of
 * date), two frames in flight.  The only file of prw_gpu that knows GLFW. */
#include <stdlib.h>
#include <string.h>

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include "gpu_internal.h"
#include "prw_swapchain.h"

#define FRAMES 2

typedef struct frame {
    VkCommandBuffer cmd;
    VkFence done;         /* signalled when this slot's submit completes */
    VkSemaphore acquired; /* acquire -> submit */
} frame;

struct prw_swapchain {
    GLFWwindow *window;
    VkSurfaceKHR surface;
    VkSwapchainKHR swapchain;
    VkExtent2D extent;
    VkFormat format;
    VkPresentModeKHR mode;
    uint32_t image_count;
    prw_gpu_image *images;
    VkSemaphore *rendered; /* submit -> present, one per image: reusable once that image is re-acquired */
    frame frames[FRAMES];
    uint32_t frame, image;
    bool recording, stale;
};

const char **prw_swapchain_instance_extensions(uint32_t *count, prw_error *e)
{
    *count = 0;
    if (!glfwVulkanSupported()) {
        prw_fail(e, "gpu: present requested but GLFW has no Vulkan support (glfwInit not called, or no loader)");
        return NULL;
    }
    const char **ext = glfwGetRequiredInstanceExtensions(count);
    if (!ext) prw_fail(e, "gpu: present requested but GLFW reports no surface extensions for this platform");
    return ext;
}

static void destroy_images(prw_gpu *gpu, prw_swapchain *sc)
{
    for (uint32_t i = 0; i < sc->image_count; i++)
        if (sc->rendered && sc->rendered[i]) vkDestroySemaphore(gpu->device, sc->rendered[i], NULL);
    free(sc->rendered);
    free(sc->images); /* swapchain images are owned by the swapchain: no vkDestroyImage */
    sc->rendered = NULL;
    sc->images = NULL;
    sc->image_count = 0;
}

static bool pick_format(prw_gpu *gpu, prw_swapchain *sc, prw_error *e)
{
    uint32_t n = 0;
    vkGetPhysicalDeviceSurfaceFormatsKHR(gpu->physical, sc->surface, &n, NULL);
    VkSurfaceFormatKHR *f = prw_calloc(n, sizeof *f);
    vkGetPhysicalDeviceSurfaceFormatsKHR(gpu->physical, sc->surface, &n, f);
    /* UNORM on purpose: the renderer blits pixels that are already display-encoded (sRGB curve
     * applied, 8 bits), so the swapchain must store them as-is, not encode them again. */
    sc->format = VK_FORMAT_UNDEFINED;
    for (uint32_t i = 0; i < n && !sc->format; i++)
        if ((f[i].format == VK_FORMAT_B8G8R8A8_UNORM || f[i].format == VK_FORMAT_R8G8B8A8_UNORM) &&
            f[i].colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR)
            sc->format = f[i].format;
    free(f);
    if (!sc->format) return prw_fail(e, "gpu: swapchain: surface offers neither B8G8R8A8_UNORM nor R8G8B8A8_UNORM");
    return true;
}

static void pick_mode(prw_gpu *gpu, prw_swapchain *sc, bool vsync)
{
    sc->mode = VK_PRESENT_MODE_FIFO_KHR; /* always supported */
    if (vsync) return;
    uint32_t n = 0;
    vkGetPhysicalDeviceSurfacePresentModesKHR(gpu->physical, sc->surface, &n, NULL);
    VkPresentModeKHR *m = prw_calloc(n, sizeof *m);
    vkGetPhysicalDeviceSurfacePresentModesKHR(gpu->physical, sc->surface, &n, m);
    for (uint32_t i = 0; i < n; i++) {
        if (m[i] == VK_PRESENT_MODE_MAILBOX_KHR) sc->mode = m[i];
        if (m[i] == VK_PRESENT_MODE_IMMEDIATE_KHR && sc->mode != VK_PRESENT_MODE_MAILBOX_KHR) sc->mode = m[i];
    }
    free(m);
}

/* (Re)builds the swapchain for the window's current size.  *skip when the window has no area. */
static bool build(prw_gpu *gpu, prw_swapchain *sc, bool *skip, prw_error *e)
{
    *skip = false;
    VkSurfaceCapabilitiesKHR caps;
    VkResult r = vkGetPhysicalDeviceSurfaceCapabilitiesKHR(gpu->physical, sc->surface, &caps);
    if (!prw_vk_check(r, "gpu: vkGetPhysicalDeviceSurfaceCapabilitiesKHR", e)) return false;
    VkExtent2D ext = caps.currentExtent;
    if (ext.width == UINT32_MAX) { /* the surface lets us choose: use the framebuffer size */
        int w, h;
        glfwGetFramebufferSize(sc->window, &w, &h);
        ext.width = PRW_MAX(caps.minImageExtent.width, PRW_MIN(caps.maxImageExtent.width, (uint32_t)w));
        ext.height = PRW_MAX(caps.minImageExtent.height, PRW_MIN(caps.maxImageExtent.height, (uint32_t)h));
    }
    if (ext.width == 0 || ext.height == 0) {
        *skip = true;
        return true;
    }
    const VkImageUsageFlags usage = VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
    if ((caps.supportedUsageFlags & usage) != usage)
        return prw_fail(e, "gpu: swapchain images cannot be transfer destinations on this surface");
    uint32_t count = caps.minImageCount + 1;
    if (caps.maxImageCount && count > caps.maxImageCount) count = caps.maxImageCount;
    /* The old swapchain's images may still be in use by earlier frames. */
    if (!prw_gpu_wait_idle(gpu, e)) return false;
    VkSwapchainKHR old = sc->swapchain;
    VkSwapchainCreateInfoKHR ci = {
        .sType = VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR,
        .surface = sc->surface,
        .minImageCount = count,
        .imageFormat = sc->format,
        .imageColorSpace = VK_COLOR_SPACE_SRGB_NONLINEAR_KHR,
        .imageExtent = ext,
        .imageArrayLayers = 1,
        .imageUsage = usage,
        .imageSharingMode = VK_SHARING_MODE_EXCLUSIVE,
        .preTransform = caps.currentTransform,
        .compositeAlpha = (caps.supportedCompositeAlpha & VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR)
                              ? VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR
                              : (VkCompositeAlphaFlagBitsKHR)(caps.supportedCompositeAlpha &
                                                              -caps.supportedCompositeAlpha),
        .presentMode = sc->mode,
        .clipped = VK_TRUE,
        .oldSwapchain = old,
    };
    r = vkCreateSwapchainKHR(gpu->device, &ci, NULL, &sc->swapchain);
    if (old) {
        destroy_images(gpu, sc);
        vkDestroySwapchainKHR(gpu->device, old, NULL);
    }
    if (r != VK_SUCCESS) {
        sc->swapchain = VK_NULL_HANDLE;
        return prw_vk_check(r, "gpu: vkCreateSwapchainKHR", e);
    }
    sc->extent = ext;
    vkGetSwapchainImagesKHR(gpu->device, sc->swapchain, &sc->image_count, NULL);
    VkImage *imgs = prw_calloc(sc->image_count, sizeof *imgs);
    vkGetSwapchainImagesKHR(gpu->device, sc->swapchain, &sc->image_count, imgs);
    sc->images = prw_calloc(sc->image_count, sizeof *sc->images);
    sc->rendered = prw_calloc(sc->image_count, sizeof *sc->rendered);
    bool ok = true;
    for (uint32_t i = 0; i < sc->image_count; i++) {
        prw_gpu_image *im = &sc->images[i];
        im->image = imgs[i];
        im->format = sc->format;
        im->aspect = VK_IMAGE_ASPECT_COLOR_BIT;
        im->width = ext.width;
        im->height = ext.height;
        im->layers = im->mips = 1;
        im->samples = VK_SAMPLE_COUNT_1_BIT;
        im->layout = VK_IMAGE_LAYOUT_UNDEFINED;
        im->usage = usage;
        VkSemaphoreCreateInfo si = {.sType = VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        if (ok) ok = prw_vk_check(vkCreateSemaphore(gpu->device, &si, NULL, &sc->rendered[i]), "gpu: vkCreateSemaphore", e);
    }
    free(imgs);
    sc->stale = false;
    return ok;
}

bool prw_swapchain_create(prw_gpu *gpu, void *window, bool vsync, prw_swapchain **out, prw_error *e)
{
    *out = NULL;
    if (!gpu->present) return prw_fail(e, "gpu: swapchain needs a gpu created with desc.present");
    prw_swapchain *sc = prw_calloc(1, sizeof *sc);
    sc->window = window;
    VkResult r = glfwCreateWindowSurface(gpu->instance, sc->window, NULL, &sc->surface);
    bool ok = prw_vk_check(r, "gpu: glfwCreateWindowSurface", e);
    if (ok) {
        VkBool32 supported = VK_FALSE;
        vkGetPhysicalDeviceSurfaceSupportKHR(gpu->physical, gpu->queue_family, sc->surface, &supported);
        if (!supported) ok = prw_fail(e, "gpu: the device's queue cannot present to this window");
    }
    ok = ok && pick_format(gpu, sc, e);
    if (ok) pick_mode(gpu, sc, vsync);
    for (int i = 0; ok && i < FRAMES; i++) {
        frame *f = &sc->frames[i];
        VkCommandBufferAllocateInfo ai = {
            .sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
            .commandPool = gpu->cmd_pool,
            .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
            .commandBufferCount = 1,
        };
        VkFenceCreateInfo fi = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO, .flags = VK_FENCE_CREATE_SIGNALED_BIT};
        VkSemaphoreCreateInfo si = {.sType = VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        ok = prw_vk_check(vkAllocateCommandBuffers(gpu->device, &ai, &f->cmd), "gpu: vkAllocateCommandBuffers", e) &&
             prw_vk_check(vkCreateFence(gpu->device, &fi, NULL, &f->done), "gpu: vkCreateFence", e) &&
             prw_vk_check(vkCreateSemaphore(gpu->device, &si, NULL, &f->acquired), "gpu: vkCreateSemaphore", e);
    }
    bool skip = false;
    ok = ok && build(gpu, sc, &skip, e);
    if (ok && skip) sc->stale = true; /* minimised at start: built on the first visible frame */
    if (!ok) {
        prw_swapchain_destroy(gpu, sc);
        return false;
    }
    *out = sc;
    return true;
}

void prw_swapchain_destroy(prw_gpu *gpu, prw_swapchain *sc)
{
    if (!sc) return;
    prw_error ignored;
    if (!prw_gpu_wait_idle(gpu, &ignored)) prw_log(PRW_LOG_WARN, "swapchain destroy: %s", ignored.msg);
    for (int i = 0; i < FRAMES; i++) {
        frame *f = &sc->frames[i];
        if (f->cmd) vkFreeCommandBuffers(gpu->device, gpu->cmd_pool, 1, &f->cmd);
        if (f->done) vkDestroyFence(gpu->device, f->done, NULL);
        if (f->acquired) vkDestroySemaphore(gpu->device, f->acquired, NULL);
    }
    destroy_images(gpu, sc);
    if (sc->swapchain) vkDestroySwapchainKHR(gpu->device, sc->swapchain, NULL);
    if (sc->surface) vkDestroySurfaceKHR(gpu->instance, sc->surface, NULL);
    free(sc);
}

bool prw_swapchain_begin_frame(prw_gpu *gpu, prw_swapchain *sc, VkCommandBuffer *cmd, prw_gpu_image **target,
                               bool *skip, prw_error *e)
{
    *skip = false;
    *cmd = VK_NULL_HANDLE;
    *target = NULL;
    int w, h;
    glfwGetFramebufferSize(sc->window, &w, &h);
    if (w <= 0 || h <= 0) {
        *skip = true;
        return false;
    }
    if ((uint32_t)w != sc->extent.width || (uint32_t)h != sc->extent.height) sc->stale = true;
    frame *f = &sc->frames[sc->frame];
    if (!prw_fence_wait(gpu, f->done, "gpu: swapchain frame wait", e)) return false;
    for (int attempt = 0;; attempt++) {
        if (sc->stale || !sc->swapchain) {
            if (!build(gpu, sc, skip, e)) return false;
            if (*skip) return false;
        }
        VkResult r = vkAcquireNextImageKHR(gpu->device, sc->swapchain, UINT64_MAX, f->acquired, VK_NULL_HANDLE,
                                           &sc->image);
        if (r == VK_ERROR_OUT_OF_DATE_KHR && attempt < 2) {
            sc->stale = true;
            continue;
        }
        if (r == VK_SUBOPTIMAL_KHR) sc->stale = true; /* usable now; rebuilt after present */
        else if (!prw_vk_check(r, "gpu: vkAcquireNextImageKHR", e)) return false;
        break;
    }
    /* Reset only once an image is ours: an early return above leaves the fence signalled. */
    vkResetFences(gpu->device, 1, &f->done);
    vkResetCommandBuffer(f->cmd, 0);
    VkCommandBufferBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
                                   .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};
    if (!prw_vk_check(vkBeginCommandBuffer(f->cmd, &bi), "gpu: vkBeginCommandBuffer", e)) return false;
    sc->recording = true;
    *cmd = f->cmd;
    *target = &sc->images[sc->image];
    return true;
}

bool prw_swapchain_end_frame(prw_gpu *gpu, prw_swapchain *sc, prw_error *e)
{
    if (!sc->recording) return prw_fail(e, "gpu: swapchain end_frame without a successful begin_frame");
    sc->recording = false;
    frame *f = &sc->frames[sc->frame];
    prw_gpu_image *img = &sc->images[sc->image];
    prw_cmd_transition(f->cmd, img, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR);
    if (!prw_vk_check(vkEndCommandBuffer(f->cmd), "gpu: vkEndCommandBuffer", e)) return false;
    /* Wait at ALL_COMMANDS: prw_cmd_transition's barriers out of UNDEFINED/PRESENT_SRC start there. */
    VkSemaphoreSubmitInfo wait = {.sType = VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO,
                                  .semaphore = f->acquired,
                                  .stageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT};
    VkSemaphoreSubmitInfo signal = {.sType = VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO,
                                    .semaphore = sc->rendered[sc->image],
                                    .stageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT};
    VkCommandBufferSubmitInfo cbi = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO, .commandBuffer = f->cmd};
    VkSubmitInfo2 si = {
        .sType = VK_STRUCTURE_TYPE_SUBMIT_INFO_2,
        .waitSemaphoreInfoCount = 1,
        .pWaitSemaphoreInfos = &wait,
        .commandBufferInfoCount = 1,
        .pCommandBufferInfos = &cbi,
        .signalSemaphoreInfoCount = 1,
        .pSignalSemaphoreInfos = &signal,
    };
    if (!prw_vk_check(vkQueueSubmit2(gpu->queue, 1, &si, f->done), "gpu: vkQueueSubmit2 (frame)", e)) return false;
    VkPresentInfoKHR pi = {
        .sType = VK_STRUCTURE_TYPE_PRESENT_INFO_KHR,
        .waitSemaphoreCount = 1,
        .pWaitSemaphores = &sc->rendered[sc->image],
        .swapchainCount = 1,
        .pSwapchains = &sc->swapchain,
        .pImageIndices = &sc->image,
    };
    VkResult r = vkQueuePresentKHR(gpu->queue, &pi);
    sc->frame = (sc->frame + 1) % FRAMES;
    if (r == VK_ERROR_OUT_OF_DATE_KHR || r == VK_SUBOPTIMAL_KHR) {
        sc->stale = true; /* rebuilt at the next begin_frame */
        return true;
    }
    return prw_vk_check(r, "gpu: vkQueuePresentKHR", e);
}
