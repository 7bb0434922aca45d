/* gpu_transfer.c — moving image pixels between CPU and GPU: staged uploads with blit-generated
 * mip chains, and readback to float RGBA. */
#include <math.h>
#include <string.h>

#include "gpu_internal.h"

static void mip_barrier(VkCommandBuffer cmd, prw_gpu_image *img, uint32_t mip, uint32_t mip_count, uint32_t layer,
                        VkImageLayout from, VkImageLayout to)
{
    /* Only used inside the blit chain: transfer write -> transfer read (or back). */
    bool to_src = to == VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    VkImageMemoryBarrier2 b = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2,
        .srcStageMask = VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
        .srcAccessMask = to_src ? VK_ACCESS_2_TRANSFER_WRITE_BIT : VK_ACCESS_2_NONE,
        .dstStageMask = VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
        .dstAccessMask = to_src ? VK_ACCESS_2_TRANSFER_READ_BIT : VK_ACCESS_2_TRANSFER_WRITE_BIT,
        .oldLayout = from,
        .newLayout = to,
        .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
        .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
        .image = img->image,
        .subresourceRange = {img->aspect, mip, mip_count, layer, 1},
    };
    VkDependencyInfo dep = {.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO, .imageMemoryBarrierCount = 1,
                            .pImageMemoryBarriers = &b};
    vkCmdPipelineBarrier2(cmd, &dep);
}

static void record_mip_chain(VkCommandBuffer cmd, prw_gpu_image *img, uint32_t layer, VkFilter filter)
{
    int32_t w = (int32_t)img->width, h = (int32_t)img->height;
    for (uint32_t m = 1; m < img->mips; m++) {
        mip_barrier(cmd, img, m - 1, 1, layer, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                    VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
        int32_t nw = w > 1 ? w / 2 : 1, nh = h > 1 ? h / 2 : 1;
        VkImageBlit2 region = {
            .sType = VK_STRUCTURE_TYPE_IMAGE_BLIT_2,
            .srcSubresource = {img->aspect, m - 1, layer, 1},
            .srcOffsets = {{0, 0, 0}, {w, h, 1}},
            .dstSubresource = {img->aspect, m, layer, 1},
            .dstOffsets = {{0, 0, 0}, {nw, nh, 1}},
        };
        VkBlitImageInfo2 bi = {
            .sType = VK_STRUCTURE_TYPE_BLIT_IMAGE_INFO_2,
            .srcImage = img->image,
            .srcImageLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
            .dstImage = img->image,
            .dstImageLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
            .regionCount = 1,
            .pRegions = &region,
            .filter = filter,
        };
        vkCmdBlitImage2(cmd, &bi);
        w = nw;
        h = nh;
    }
    /* Back to one layout for the whole image so prw_cmd_transition can take over. */
    if (img->mips > 1)
        mip_barrier(cmd, img, 0, img->mips - 1, layer, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                    VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
}

bool prw_image_upload(prw_gpu *gpu, prw_gpu_image *img, uint32_t layer, const void *pixels, size_t bytes,
                      prw_error *e)
{
    uint32_t bw, bh;
    uint32_t texel = prw_format_texel_bytes(img->format, &bw, &bh);
    if (!texel) return prw_fail(e, "gpu: image upload: format %d has no known texel size", (int)img->format);
    size_t expect = (size_t)((img->width + bw - 1) / bw) * ((img->height + bh - 1) / bh) * texel;
    if (bytes != expect)
        return prw_fail(e, "gpu: image upload: %zu bytes given, %ux%u of format %d needs %zu", bytes, img->width,
                        img->height, (int)img->format, expect);
    if (layer >= img->layers) return prw_fail(e, "gpu: image upload: layer %u of %u", layer, img->layers);
    if (img->samples != VK_SAMPLE_COUNT_1_BIT) return prw_fail(e, "gpu: image upload into a multisampled image");
    if (!(img->usage & VK_IMAGE_USAGE_TRANSFER_DST_BIT))
        return prw_fail(e, "gpu: image upload needs VK_IMAGE_USAGE_TRANSFER_DST_BIT");
    VkFilter filter = VK_FILTER_LINEAR;
    if (img->mips > 1) {
        if (!(img->usage & VK_IMAGE_USAGE_TRANSFER_SRC_BIT))
            return prw_fail(e, "gpu: mip generation needs VK_IMAGE_USAGE_TRANSFER_SRC_BIT");
        VkFormatProperties fp;
        vkGetPhysicalDeviceFormatProperties(gpu->physical, img->format, &fp);
        VkFormatFeatureFlags f = fp.optimalTilingFeatures;
        if (!(f & VK_FORMAT_FEATURE_BLIT_SRC_BIT) || !(f & VK_FORMAT_FEATURE_BLIT_DST_BIT))
            return prw_fail(e, "gpu: format %d cannot be blitted, so its mips cannot be generated", (int)img->format);
        if (!(f & VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT)) filter = VK_FILTER_NEAREST;
    }

    prw_buffer staging;
    if (!prw_buffer_create(gpu, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, PRW_MEM_UPLOAD, &staging, e))
        return prw_fail_wrap(e, "gpu: image upload staging");
    memcpy(staging.mapped, pixels, bytes);
    VkCommandBuffer cmd;
    if (!prw_cmd_begin(gpu, &cmd, e)) {
        prw_buffer_destroy(gpu, &staging);
        return false;
    }
    /* Other layers keep their content: the old layout is the tracked one, not UNDEFINED. */
    prw_cmd_transition(cmd, img, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    VkBufferImageCopy region = {
        .imageSubresource = {img->aspect & VK_IMAGE_ASPECT_DEPTH_BIT ? VK_IMAGE_ASPECT_DEPTH_BIT : img->aspect, 0,
                             layer, 1},
        .imageExtent = {img->width, img->height, 1},
    };
    vkCmdCopyBufferToImage(cmd, staging.buffer, img->image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
    record_mip_chain(cmd, img, layer, filter);
    /* SHADER_READ_ONLY is only legal for sampled / input-attachment images; a transfer-only image
     * (e.g. a test pattern to read back) ends up ready for reading by transfer instead. */
    if (img->usage & (VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_INPUT_ATTACHMENT_BIT))
        prw_cmd_transition(cmd, img, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    else if (img->usage & VK_IMAGE_USAGE_TRANSFER_SRC_BIT)
        prw_cmd_transition(cmd, img, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    uint32_t orphans = gpu->orphan_count;
    bool ok = prw_cmd_submit_wait(gpu, cmd, e);
    if (ok || gpu->orphan_count == orphans) prw_buffer_destroy(gpu, &staging);
    return ok;
}

/* IEEE half -> float, including subnormals, infinities and NaN. */
static float half_to_float(uint16_t h)
{
    uint32_t sign = (uint32_t)(h >> 15) & 1u, exp = (h >> 10) & 0x1fu, man = h & 0x3ffu;
    float v;
    if (exp == 0) v = ldexpf((float)man, -24);                     /* zero / subnormal: man * 2^-24 */
    else if (exp == 31) v = man ? NAN : INFINITY;
    else v = ldexpf((float)(man | 0x400u), (int)exp - 25);          /* 1.man * 2^(exp-15) */
    return sign ? -v : v;
}

/* Copies mip 0 / layer 0 (aspect) of a single-sample image into a new READBACK buffer *rb (texel bytes a
 * pixel) and waits; the image keeps its layout. */
static bool copy_out(prw_gpu *gpu, prw_gpu_image *img, VkImageAspectFlags aspect, uint32_t texel, prw_buffer *rb,
                     prw_error *e)
{
    if (img->samples != VK_SAMPLE_COUNT_1_BIT)
        return prw_fail(e, "gpu: image readback of a multisampled image (resolve it first)");
    if (!(img->usage & VK_IMAGE_USAGE_TRANSFER_SRC_BIT))
        return prw_fail(e, "gpu: image readback needs VK_IMAGE_USAGE_TRANSFER_SRC_BIT");
    if (img->layout == VK_IMAGE_LAYOUT_UNDEFINED)
        return prw_fail(e, "gpu: image readback of an image that was never written (layout UNDEFINED)");
    size_t n = (size_t)img->width * img->height;
    if (!prw_buffer_create(gpu, n * texel, VK_BUFFER_USAGE_TRANSFER_DST_BIT, PRW_MEM_READBACK, rb, e))
        return prw_fail_wrap(e, "gpu: image readback buffer");
    VkCommandBuffer cmd;
    if (!prw_cmd_begin(gpu, &cmd, e)) {
        prw_buffer_destroy(gpu, rb);
        return false;
    }
    VkImageLayout restore = img->layout;
    prw_cmd_transition(cmd, img, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    VkBufferImageCopy region = {
        .imageSubresource = {aspect, 0, 0, 1},
        .imageExtent = {img->width, img->height, 1},
    };
    vkCmdCopyImageToBuffer(cmd, img->image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, rb->buffer, 1, &region);
    /* The copy's writes must be available to the host before the fence wait returns. */
    VkMemoryBarrier2 mb = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER_2,
        .srcStageMask = VK_PIPELINE_STAGE_2_COPY_BIT,
        .srcAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT,
        .dstStageMask = VK_PIPELINE_STAGE_2_HOST_BIT,
        .dstAccessMask = VK_ACCESS_2_HOST_READ_BIT,
    };
    VkDependencyInfo dep = {.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO, .memoryBarrierCount = 1,
                            .pMemoryBarriers = &mb};
    vkCmdPipelineBarrier2(cmd, &dep);
    prw_cmd_transition(cmd, img, restore);
    uint32_t orphans = gpu->orphan_count;
    if (!prw_cmd_submit_wait(gpu, cmd, e)) {
        if (gpu->orphan_count == orphans) prw_buffer_destroy(gpu, rb);
        return false;
    }
    return true;
}

bool prw_image_readback(prw_gpu *gpu, prw_gpu_image *img, float *rgba, prw_error *e)
{
    uint32_t texel;
    switch (img->format) {
    case VK_FORMAT_R16G16B16A16_SFLOAT: texel = 8; break;
    case VK_FORMAT_R32G32B32A32_SFLOAT: texel = 16; break;
    case VK_FORMAT_R8G8B8A8_UNORM:
    case VK_FORMAT_R8G8B8A8_SRGB: texel = 4; break;
    default: return prw_fail(e, "gpu: image readback: unsupported format %d", (int)img->format);
    }
    prw_buffer rb;
    if (!copy_out(gpu, img, VK_IMAGE_ASPECT_COLOR_BIT, texel, &rb, e)) return false;
    size_t n = (size_t)img->width * img->height;
    const unsigned char *src = rb.mapped;
    for (size_t i = 0; i < n * 4; i++) {
        switch (texel) {
        case 8: {
            uint16_t h;
            memcpy(&h, src + i * 2, 2);
            rgba[i] = half_to_float(h);
            break;
        }
        case 16: memcpy(&rgba[i], src + i * 4, 4); break;
        default: rgba[i] = (float)src[i] / 255.0f; break;
        }
    }
    prw_buffer_destroy(gpu, &rb);
    return true;
}

bool prw_image_readback_r32(prw_gpu *gpu, prw_gpu_image *img, void *out, prw_error *e)
{
    VkImageAspectFlags aspect;
    switch (img->format) {
    case VK_FORMAT_D32_SFLOAT: aspect = VK_IMAGE_ASPECT_DEPTH_BIT; break;
    case VK_FORMAT_R32_UINT:
    case VK_FORMAT_R32_SFLOAT: aspect = VK_IMAGE_ASPECT_COLOR_BIT; break;
    default: return prw_fail(e, "gpu: 32-bit readback: unsupported format %d", (int)img->format);
    }
    prw_buffer rb;
    if (!copy_out(gpu, img, aspect, 4, &rb, e)) return false;
    memcpy(out, rb.mapped, (size_t)img->width * img->height * 4);
    prw_buffer_destroy(gpu, &rb);
    return true;
}
