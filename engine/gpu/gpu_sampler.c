/* gpu_sampler.c — the few samplers prw uses, created once per gpu and shared. */
#include <string.h>

#include "gpu_internal.h"

bool prw_samplers_init(prw_gpu *gpu, prw_error *e)
{
    for (int k = 0; k < PRW_SAMPLER_COUNT; k++) {
        VkSamplerCreateInfo ci = {
            .sType = VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO,
            .magFilter = VK_FILTER_LINEAR,
            .minFilter = VK_FILTER_LINEAR,
            .mipmapMode = VK_SAMPLER_MIPMAP_MODE_LINEAR,
            .addressModeU = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE,
            .addressModeV = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE,
            .addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE,
            .anisotropyEnable = VK_FALSE, /* the feature is not enabled (lavapipe has none) */
            .maxAnisotropy = 1.0f,
            .minLod = 0.0f,
            .maxLod = VK_LOD_CLAMP_NONE,
            .borderColor = VK_BORDER_COLOR_FLOAT_TRANSPARENT_BLACK,
        };
        switch ((prw_sampler_kind)k) {
        case PRW_SAMPLER_LINEAR_REPEAT:
            ci.addressModeU = ci.addressModeV = ci.addressModeW = VK_SAMPLER_ADDRESS_MODE_REPEAT;
            break;
        case PRW_SAMPLER_LINEAR_CLAMP: break;
        case PRW_SAMPLER_NEAREST_CLAMP:
            ci.magFilter = ci.minFilter = VK_FILTER_NEAREST;
            ci.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
            break;
        case PRW_SAMPLER_SHADOW:
            /* Reversed Z: depth 0 is far.  Outside the map the border depth 0 makes every receiver
             * compare "ref >= 0" true, i.e. lit.  Linear filtering of compare results = 2x2 PCF. */
            ci.compareEnable = VK_TRUE;
            ci.compareOp = VK_COMPARE_OP_GREATER_OR_EQUAL;
            ci.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
            ci.addressModeU = ci.addressModeV = ci.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_BORDER;
            ci.maxLod = 0.0f;
            break;
        case PRW_SAMPLER_SHADOW_DEPTH: /* gathered and compared in the shader (shaders/shadows.glsl) */
            ci.magFilter = ci.minFilter = VK_FILTER_NEAREST;
            ci.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
            ci.addressModeU = ci.addressModeV = ci.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_BORDER;
            ci.maxLod = 0.0f;
            break;
        case PRW_SAMPLER_COUNT: break;
        }
        if (!prw_vk_check(vkCreateSampler(gpu->device, &ci, NULL, &gpu->samplers[k]), "gpu: vkCreateSampler", e))
            return false;
    }
    return true;
}

void prw_samplers_shutdown(prw_gpu *gpu)
{
    for (int k = 0; k < PRW_SAMPLER_COUNT; k++)
        if (gpu->samplers[k]) vkDestroySampler(gpu->device, gpu->samplers[k], NULL);
    memset(gpu->samplers, 0, sizeof gpu->samplers);
}

VkSampler prw_gpu_sampler(prw_gpu *gpu, prw_sampler_kind kind)
{
    return (unsigned)kind < PRW_SAMPLER_COUNT ? gpu->samplers[kind] : VK_NULL_HANDLE;
}
