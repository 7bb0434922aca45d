/* gpu_image.c — images, their views, and layout transitions with synchronization2 barriers. */
#include <stdlib.h>
#include <string.h>

#include "gpu_internal.h"

VkImageAspectFlags prw_format_aspect(VkFormat f)
{
    switch (f) {
    case VK_FORMAT_D16_UNORM:
    case VK_FORMAT_X8_D24_UNORM_PACK32:
    case VK_FORMAT_D32_SFLOAT: return VK_IMAGE_ASPECT_DEPTH_BIT;
    case VK_FORMAT_S8_UINT: return VK_IMAGE_ASPECT_STENCIL_BIT;
    case VK_FORMAT_D16_UNORM_S8_UINT:
    case VK_FORMAT_D24_UNORM_S8_UINT:
    case VK_FORMAT_D32_SFLOAT_S8_UINT: return VK_IMAGE_ASPECT_DEPTH_BIT | VK_IMAGE_ASPECT_STENCIL_BIT;
    default: return VK_IMAGE_ASPECT_COLOR_BIT;
    }
}

/* Bytes per texel (or per block for compressed formats, with the block size); 0 if unknown. */
uint32_t prw_format_texel_bytes(VkFormat f, uint32_t *block_w, uint32_t *block_h)
{
    *block_w = *block_h = 1;
    switch (f) {
    case VK_FORMAT_R8_UNORM:
    case VK_FORMAT_R8_SRGB:
    case VK_FORMAT_R8_UINT:
    case VK_FORMAT_S8_UINT: return 1;
    case VK_FORMAT_R8G8_UNORM:
    case VK_FORMAT_R16_SFLOAT:
    case VK_FORMAT_R16_UNORM:
    case VK_FORMAT_R16_UINT:
    case VK_FORMAT_D16_UNORM: return 2;
    case VK_FORMAT_R8G8B8A8_UNORM:
    case VK_FORMAT_R8G8B8A8_SRGB:
    case VK_FORMAT_B8G8R8A8_UNORM:
    case VK_FORMAT_B8G8R8A8_SRGB:
    case VK_FORMAT_R16G16_SFLOAT:
    case VK_FORMAT_R16G16_UNORM:
    case VK_FORMAT_R32_SFLOAT:
    case VK_FORMAT_R32_UINT:
    case VK_FORMAT_B10G11R11_UFLOAT_PACK32:
    case VK_FORMAT_E5B9G9R9_UFLOAT_PACK32:
    case VK_FORMAT_A2B10G10R10_UNORM_PACK32:
    case VK_FORMAT_D32_SFLOAT:
    case VK_FORMAT_X8_D24_UNORM_PACK32: return 4;
    case VK_FORMAT_R16G16B16A16_SFLOAT:
    case VK_FORMAT_R16G16B16A16_UNORM:
    case VK_FORMAT_R32G32_SFLOAT: return 8;
    case VK_FORMAT_R32G32B32_SFLOAT: return 12;
    case VK_FORMAT_R32G32B32A32_SFLOAT:
    case VK_FORMAT_R32G32B32A32_UINT: return 16;
    case VK_FORMAT_BC1_RGB_UNORM_BLOCK:
    case VK_FORMAT_BC1_RGB_SRGB_BLOCK:
    case VK_FORMAT_BC1_RGBA_UNORM_BLOCK:
    case VK_FORMAT_BC1_RGBA_SRGB_BLOCK:
    case VK_FORMAT_BC4_UNORM_BLOCK: *block_w = *block_h = 4; return 8;
    case VK_FORMAT_BC3_UNORM_BLOCK:
    case VK_FORMAT_BC3_SRGB_BLOCK:
    case VK_FORMAT_BC5_UNORM_BLOCK:
    case VK_FORMAT_BC6H_UFLOAT_BLOCK:
    case VK_FORMAT_BC7_UNORM_BLOCK:
    case VK_FORMAT_BC7_SRGB_BLOCK: *block_w = *block_h = 4; return 16;
    default: return 0;
    }
}

static bool make_view(prw_gpu *gpu, prw_gpu_image *img, VkImageViewType type, uint32_t base_layer,
                      uint32_t layer_count, uint32_t mip_count, VkImageView *out, prw_error *e)
{
    /* A view for sampling or attachment use must name one aspect: depth for depth/stencil formats. */
    VkImageAspectFlags aspect = img->aspect;
    if (aspect & VK_IMAGE_ASPECT_DEPTH_BIT) aspect = VK_IMAGE_ASPECT_DEPTH_BIT;
    VkImageViewCreateInfo ci = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO,
        .image = img->image,
        .viewType = type,
        .format = img->format,
        .subresourceRange = {aspect, 0, mip_count, base_layer, layer_count},
    };
    return prw_vk_check(vkCreateImageView(gpu->device, &ci, NULL, out), "gpu: vkCreateImageView", e);
}

static uint32_t full_mip_count(uint32_t w, uint32_t h)
{
    uint32_t n = 1;
    for (uint32_t m = PRW_MAX(w, h); m > 1; m >>= 1) n++;
    return n;
}

bool prw_image_create(prw_gpu *gpu, const prw_image_desc *desc, prw_gpu_image *out, prw_error *e)
{
    memset(out, 0, sizeof *out);
    out->width = desc->width;
    out->height = desc->height;
    out->layers = desc->layers ? desc->layers : 1;
    out->mips = desc->mips ? desc->mips : 1;
    out->samples = desc->samples ? desc->samples : VK_SAMPLE_COUNT_1_BIT;
    out->format = desc->format;
    out->aspect = prw_format_aspect(desc->format);
    out->usage = desc->usage;
    out->layout = VK_IMAGE_LAYOUT_UNDEFINED;
    if (!desc->width || !desc->height) return prw_fail(e, "gpu: image of size %ux%u", desc->width, desc->height);
    if (out->mips > full_mip_count(desc->width, desc->height))
        return prw_fail(e, "gpu: %u mips requested for a %ux%u image (max %u)", out->mips, desc->width,
                        desc->height, full_mip_count(desc->width, desc->height));
    if (out->samples > 1 && out->mips > 1) return prw_fail(e, "gpu: a multisampled image cannot have mips");
    if (desc->cube && (out->layers % 6 != 0 || desc->width != desc->height))
        return prw_fail(e, "gpu: cube image needs square faces and 6*n layers (got %ux%u, %u layers)", desc->width,
                        desc->height, out->layers);

    VkImageCreateFlags flags = desc->cube ? VK_IMAGE_CREATE_CUBE_COMPATIBLE_BIT : 0;
    VkImageFormatProperties fp;
    VkResult r = vkGetPhysicalDeviceImageFormatProperties(gpu->physical, desc->format, VK_IMAGE_TYPE_2D,
                                                          VK_IMAGE_TILING_OPTIMAL, desc->usage, flags, &fp);
    if (r == VK_ERROR_FORMAT_NOT_SUPPORTED)
        return prw_fail(e, "gpu: image format %d not supported with usage 0x%x", (int)desc->format, desc->usage);
    if (!prw_vk_check(r, "gpu: vkGetPhysicalDeviceImageFormatProperties", e)) return false;
    if (!(fp.sampleCounts & out->samples))
        return prw_fail(e, "gpu: image format %d does not support %u samples", (int)desc->format, out->samples);
    if (desc->width > fp.maxExtent.width || desc->height > fp.maxExtent.height || out->layers > fp.maxArrayLayers)
        return prw_fail(e, "gpu: image %ux%u x%u layers exceeds the format's limits (%ux%u x%u)", desc->width,
                        desc->height, out->layers, fp.maxExtent.width, fp.maxExtent.height, fp.maxArrayLayers);

    VkImageCreateInfo ci = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO,
        .flags = flags,
        .imageType = VK_IMAGE_TYPE_2D,
        .format = desc->format,
        .extent = {desc->width, desc->height, 1},
        .mipLevels = out->mips,
        .arrayLayers = out->layers,
        .samples = out->samples,
        .tiling = VK_IMAGE_TILING_OPTIMAL,
        .usage = desc->usage,
        .sharingMode = VK_SHARING_MODE_EXCLUSIVE,
        .initialLayout = VK_IMAGE_LAYOUT_UNDEFINED,
    };
    if (!prw_vk_check(vkCreateImage(gpu->device, &ci, NULL, &out->image), "gpu: vkCreateImage", e)) return false;
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(gpu->device, out->image, &req);
    bool ok = prw_mem_alloc(gpu, &req, PRW_MEM_GPU, false, &out->alloc, e);
    if (!ok) prw_fail_wrap(e, "gpu: image %ux%u", desc->width, desc->height);
    ok = ok && prw_vk_check(vkBindImageMemory(gpu->device, out->image, out->alloc.memory, out->alloc.offset),
                            "gpu: vkBindImageMemory", e);

    /* Views only make sense for usages that read or attach the image. */
    const VkImageUsageFlags view_usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT |
                                         VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT |
                                         VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT |
                                         VK_IMAGE_USAGE_INPUT_ATTACHMENT_BIT;
    if (ok && (desc->usage & view_usage)) {
        VkImageViewType type = desc->view_type;
        if (!type && desc->cube) type = out->layers == 6 ? VK_IMAGE_VIEW_TYPE_CUBE : VK_IMAGE_VIEW_TYPE_CUBE_ARRAY;
        else if (!type) type = out->layers > 1 ? VK_IMAGE_VIEW_TYPE_2D_ARRAY : VK_IMAGE_VIEW_TYPE_2D;
        ok = make_view(gpu, out, type, 0, out->layers, out->mips, &out->view, e);
        out->layer_views = prw_calloc(out->layers, sizeof *out->layer_views);
        for (uint32_t i = 0; ok && i < out->layers; i++)
            ok = make_view(gpu, out, VK_IMAGE_VIEW_TYPE_2D, i, 1, 1, &out->layer_views[i], e);
    }
    if (!ok) {
        prw_image_destroy(gpu, out);
        return false;
    }
    return true;
}

void prw_image_destroy(prw_gpu *gpu, prw_gpu_image *img)
{
    if (!img) return;
    if (img->layer_views) {
        for (uint32_t i = 0; i < img->layers; i++)
            if (img->layer_views[i]) vkDestroyImageView(gpu->device, img->layer_views[i], NULL);
        free(img->layer_views);
    }
    if (img->view) vkDestroyImageView(gpu->device, img->view, NULL);
    if (img->image) vkDestroyImage(gpu->device, img->image, NULL);
    prw_mem_free(gpu, &img->alloc);
    memset(img, 0, sizeof *img);
}

/* What a layout implies about who touches the image: the stages and the accesses (split into
 * writes, which a barrier must make available, and reads). */
typedef struct layout_use {
    VkPipelineStageFlags2 stages;
    VkAccessFlags2 reads, writes;
} layout_use;

static layout_use use_of(VkImageLayout layout, VkImageAspectFlags aspect)
{
    const VkPipelineStageFlags2 shaders = VK_PIPELINE_STAGE_2_PRE_RASTERIZATION_SHADERS_BIT |
                                          VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT |
                                          VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
    const VkPipelineStageFlags2 depth_tests = VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT |
                                              VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;
    bool depth = aspect & (VK_IMAGE_ASPECT_DEPTH_BIT | VK_IMAGE_ASPECT_STENCIL_BIT);
    switch (layout) {
    case VK_IMAGE_LAYOUT_UNDEFINED:
    case VK_IMAGE_LAYOUT_PRESENT_SRC_KHR:
        /* No content to keep, but earlier users (previous frame's reads, the presentation engine
         * behind an acquire semaphore waited at ALL_COMMANDS) must finish before we write. */
        return (layout_use){VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, 0, 0};
    case VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL:
        return (layout_use){VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT,
                            VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT};
    case VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL:
    case VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL:
    case VK_IMAGE_LAYOUT_STENCIL_ATTACHMENT_OPTIMAL:
        return (layout_use){depth_tests, VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT,
                            VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT};
    case VK_IMAGE_LAYOUT_ATTACHMENT_OPTIMAL:
        if (depth)
            return (layout_use){depth_tests, VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT,
                                VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT};
        return (layout_use){VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT,
                            VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT};
    case VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL:
    case VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL:
    case VK_IMAGE_LAYOUT_STENCIL_READ_ONLY_OPTIMAL:
        return (layout_use){depth_tests | shaders,
                            VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_SHADER_SAMPLED_READ_BIT |
                                VK_ACCESS_2_INPUT_ATTACHMENT_READ_BIT,
                            0};
    case VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL:
    case VK_IMAGE_LAYOUT_READ_ONLY_OPTIMAL:
        return (layout_use){shaders | (depth ? depth_tests : VK_PIPELINE_STAGE_2_NONE),
                            VK_ACCESS_2_SHADER_SAMPLED_READ_BIT | VK_ACCESS_2_INPUT_ATTACHMENT_READ_BIT |
                                (depth ? VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT : VK_ACCESS_2_NONE),
                            0};
    case VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL:
        return (layout_use){VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT, 0};
    case VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL:
        return (layout_use){VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, 0, VK_ACCESS_2_TRANSFER_WRITE_BIT};
    case VK_IMAGE_LAYOUT_GENERAL:
    default:
        /* Storage images and anything unusual: everything, everywhere. */
        return (layout_use){VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT,
                            VK_ACCESS_2_MEMORY_WRITE_BIT};
    }
}

void prw_layout_access(VkImageLayout layout, VkImageAspectFlags aspect, VkPipelineStageFlags2 *stages,
                       VkAccessFlags2 *reads, VkAccessFlags2 *writes)
{
    layout_use u = use_of(layout, aspect);
    *stages = u.stages;
    *reads = u.reads;
    *writes = u.writes;
}

void prw_cmd_transition(VkCommandBuffer cmd, prw_gpu_image *img, VkImageLayout new_layout)
{
    layout_use src = use_of(img->layout, img->aspect), dst = use_of(new_layout, img->aspect);
    VkImageMemoryBarrier2 b = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2,
        .srcStageMask = src.stages,
        .srcAccessMask = src.writes, /* only writes need to be made available */
        .dstStageMask = dst.stages,
        .dstAccessMask = dst.reads | dst.writes,
        .oldLayout = img->layout,
        .newLayout = new_layout,
        .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
        .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
        .image = img->image,
        .subresourceRange = {img->aspect, 0, VK_REMAINING_MIP_LEVELS, 0, VK_REMAINING_ARRAY_LAYERS},
    };
    if (new_layout == VK_IMAGE_LAYOUT_PRESENT_SRC_KHR) {
        /* Presentation is ordered by the submit's signal semaphore, not by a later stage. */
        b.dstStageMask = VK_PIPELINE_STAGE_2_NONE;
        b.dstAccessMask = VK_ACCESS_2_NONE;
    }
    VkDependencyInfo dep = {.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO, .imageMemoryBarrierCount = 1,
                            .pImageMemoryBarriers = &b};
    vkCmdPipelineBarrier2(cmd, &dep);
    img->layout = new_layout;
}
