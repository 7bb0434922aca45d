/* gpu_pipeline.c — pipeline layouts, graphics pipelines for dynamic rendering, compute pipelines.
 * Every pipeline goes through the gpu's persistent VkPipelineCache, and is shared within the process
 * by gpu_pipeline_memo.c. */
#include <string.h>

#include "gpu_internal.h"

static bool make_module(prw_gpu *gpu, prw_spirv code, const char *what, VkShaderModule *out, prw_error *e)
{
    if (!code.code || code.size == 0 || code.size % 4 != 0)
        return prw_fail(e, "gpu: %s shader: empty or malformed SPIR-V (%zu bytes)", what, code.size);
    VkShaderModuleCreateInfo ci = {
        .sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO,
        .codeSize = code.size,
        .pCode = code.code,
    };
    if (!prw_vk_check(vkCreateShaderModule(gpu->device, &ci, NULL, out), "vkCreateShaderModule", e))
        return prw_fail_wrap(e, "gpu: %s shader", what);
    return true;
}

bool prw_pipeline_layout_create(prw_gpu *gpu, const VkDescriptorSetLayout *sets, uint32_t set_count,
                                uint32_t push_constant_bytes, VkPipelineLayout *out, prw_error *e)
{
    return prw_pipeline_layout_create_stages(gpu, sets, set_count, push_constant_bytes, 0, out, e);
}

bool prw_pipeline_layout_create_stages(prw_gpu *gpu, const VkDescriptorSetLayout *sets, uint32_t set_count,
                                       uint32_t push_constant_bytes, VkShaderStageFlags push_stages,
                                       VkPipelineLayout *out, prw_error *e)
{
    if (push_constant_bytes > gpu->props.limits.maxPushConstantsSize)
        return prw_fail(e, "gpu: %u push-constant bytes exceed the device limit %u", push_constant_bytes,
                        gpu->props.limits.maxPushConstantsSize);
    /* Default: one range visible to all stages, so any shader may read it without layout changes. */
    VkPushConstantRange range = {.stageFlags = push_stages ? push_stages : VK_SHADER_STAGE_ALL,
                                 .offset = 0,
                                 .size = push_constant_bytes};
    VkPipelineLayoutCreateInfo ci = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO,
        .setLayoutCount = set_count,
        .pSetLayouts = sets,
        .pushConstantRangeCount = push_constant_bytes ? 1 : 0,
        .pPushConstantRanges = &range,
    };
    if (!prw_vk_check(vkCreatePipelineLayout(gpu->device, &ci, NULL, out), "gpu: vkCreatePipelineLayout", e))
        return false;
    /* its content, so that a pipeline made with an equal layout of another renderer can be shared */
    prw_hash128 sig;
    prw_hash128_init(&sig);
    for (uint32_t i = 0; i < set_count; i++) {
        bool known = false;
        for (uint32_t k = 0; k < gpu->layout_count && !known; k++)
            if (gpu->layouts[k].layout == sets[i]) {
                prw_hash128_add(&sig, &gpu->layouts[k].sig, sizeof gpu->layouts[k].sig);
                known = true;
            }
        if (!known) prw_hash128_add(&sig, &sets[i], sizeof sets[i]); /* not ours: its handle */
    }
    uint32_t push[3] = {set_count, push_constant_bytes, push_constant_bytes ? (uint32_t)range.stageFlags : 0};
    prw_hash128_add(&sig, push, sizeof push);
    prw_playout_note(gpu, *out, &sig);
    return true;
}

static void hash_spirv(prw_hash128 *h, prw_spirv s)
{
    prw_hash128_add(h, &s.size, sizeof s.size);
    if (s.code) prw_hash128_add(h, s.code, s.size);
}

/* Everything prw_pipeline_graphics reads from d, field by field (no struct padding hashed). */
static void hash_graphics(prw_gpu *gpu, const prw_graphics_desc *d, prw_hash128 *h)
{
    prw_hash128_init(h);
    static const char tag[] = "graphics";
    prw_hash128_add(h, tag, sizeof tag);
    hash_spirv(h, d->vs);
    hash_spirv(h, d->fs);
    prw_hash128_add(h, &d->fs_spec_count, sizeof d->fs_spec_count);
    prw_hash128_add(h, d->fs_spec, d->fs_spec_count * sizeof d->fs_spec[0]);
    prw_playout_hash(gpu, d->layout, h);
    for (uint32_t i = 0; i < d->vertex_binding_count; i++) {
        const VkVertexInputBindingDescription *b = &d->vertex_bindings[i];
        uint32_t f[3] = {b->binding, b->stride, (uint32_t)b->inputRate};
        prw_hash128_add(h, f, sizeof f);
    }
    for (uint32_t i = 0; i < d->vertex_attr_count; i++) {
        const VkVertexInputAttributeDescription *a = &d->vertex_attrs[i];
        uint32_t f[4] = {a->location, a->binding, (uint32_t)a->format, a->offset};
        prw_hash128_add(h, f, sizeof f);
    }
    uint32_t f[] = {d->vertex_binding_count,
                    d->vertex_attr_count,
                    (uint32_t)d->topology,
                    d->color_count,
                    (uint32_t)d->color_formats[0],
                    (uint32_t)d->color_formats[1],
                    (uint32_t)d->color_formats[2],
                    (uint32_t)d->color_formats[3],
                    (uint32_t)d->depth_format,
                    (uint32_t)d->samples,
                    (uint32_t)d->cull,
                    (uint32_t)d->front_face,
                    d->depth_test,
                    d->depth_write,
                    (uint32_t)d->depth_compare,
                    d->depth_bias,
                    d->blend_additive,
                    d->blend_over,
                    d->no_color_write,
                    d->stencil_test,
                    (uint32_t)d->stencil.failOp,
                    (uint32_t)d->stencil.passOp,
                    (uint32_t)d->stencil.depthFailOp,
                    (uint32_t)d->stencil.compareOp,
                    d->stencil.compareMask,
                    d->stencil.writeMask,
                    d->stencil.reference,
                    d->view_mask};
    prw_hash128_add(h, f, sizeof f);
}

static bool has_stencil(VkFormat f) { return prw_format_aspect(f) & VK_IMAGE_ASPECT_STENCIL_BIT; }

bool prw_pipeline_graphics(prw_gpu *gpu, const prw_graphics_desc *d, VkPipeline *out, prw_error *e)
{
    *out = VK_NULL_HANDLE;
    if (d->color_count > PRW_ARRAY_LEN(d->color_formats))
        return prw_fail(e, "gpu: graphics pipeline with %u colour attachments (max 4)", d->color_count);
    if (d->stencil_test && !has_stencil(d->depth_format))
        return prw_fail(e, "gpu: graphics pipeline with a stencil test but no stencil in its depth format");
    if (d->view_mask && !gpu->features.multiview)
        return prw_fail(e, "gpu: graphics pipeline uses multiview (view mask 0x%x) but the device lacks it",
                        d->view_mask);
    if (d->fs_spec_count > PRW_GPU_MAX_FS_SPEC)
        return prw_fail(e, "gpu: %u specialisation constants (at most %d)", d->fs_spec_count, PRW_GPU_MAX_FS_SPEC);
    prw_hash128 key;
    bool memo = prw_pipe_memo_enabled(gpu);
    if (memo) {
        hash_graphics(gpu, d, &key);
        if (prw_pipe_memo_find(gpu, &key, out)) return true;
    }
    VkShaderModule vs = VK_NULL_HANDLE, fs = VK_NULL_HANDLE;
    if (!make_module(gpu, d->vs, "vertex", &vs, e)) return false;
    if (d->fs.code && !make_module(gpu, d->fs, "fragment", &fs, e)) {
        vkDestroyShaderModule(gpu->device, vs, NULL);
        return false;
    }
    VkSpecializationMapEntry spec_map[PRW_GPU_MAX_FS_SPEC];
    for (uint32_t i = 0; i < d->fs_spec_count; i++)
        spec_map[i] = (VkSpecializationMapEntry){.constantID = i, .offset = 4 * i, .size = 4};
    VkSpecializationInfo spec = {.mapEntryCount = d->fs_spec_count, .pMapEntries = spec_map,
                                 .dataSize = 4 * (size_t)d->fs_spec_count, .pData = d->fs_spec};
    VkPipelineShaderStageCreateInfo stages[2] = {
        {.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
         .stage = VK_SHADER_STAGE_VERTEX_BIT,
         .module = vs,
         .pName = "main"},
        {.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
         .stage = VK_SHADER_STAGE_FRAGMENT_BIT,
         .module = fs,
         .pName = "main",
         .pSpecializationInfo = d->fs_spec_count ? &spec : NULL},
    };
    VkPipelineVertexInputStateCreateInfo vi = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO,
        .vertexBindingDescriptionCount = d->vertex_binding_count,
        .pVertexBindingDescriptions = d->vertex_bindings,
        .vertexAttributeDescriptionCount = d->vertex_attr_count,
        .pVertexAttributeDescriptions = d->vertex_attrs,
    };
    VkPipelineInputAssemblyStateCreateInfo ia = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO,
        /* The desc's 0 means TRIANGLE_LIST (Vulkan's 0 is POINT_LIST, which prw never draws). */
        .topology = d->topology ? d->topology : VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST,
    };
    VkPipelineViewportStateCreateInfo vp = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO,
        .viewportCount = 1,
        .scissorCount = 1,
    };
    VkPipelineRasterizationStateCreateInfo rs = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO,
        .polygonMode = VK_POLYGON_MODE_FILL,
        .cullMode = d->cull,
        .frontFace = d->front_face,
        .depthBiasEnable = d->depth_bias,
        .lineWidth = 1.0f,
    };
    VkPipelineMultisampleStateCreateInfo ms = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO,
        .rasterizationSamples = d->samples ? d->samples : VK_SAMPLE_COUNT_1_BIT,
    };
    VkPipelineDepthStencilStateCreateInfo ds = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO,
        .depthTestEnable = d->depth_test,
        .depthWriteEnable = d->depth_write,
        /* Reversed Z: near = 1, far = 0, so nearer fragments have greater depth. */
        .depthCompareOp = d->depth_compare ? d->depth_compare : VK_COMPARE_OP_GREATER_OR_EQUAL,
        .stencilTestEnable = d->stencil_test,
        .front = d->stencil,
        .back = d->stencil,
    };
    VkPipelineColorBlendAttachmentState blend[4];
    for (uint32_t i = 0; i < d->color_count; i++) {
        blend[i] = (VkPipelineColorBlendAttachmentState){
            .blendEnable = d->blend_additive,
            .srcColorBlendFactor = VK_BLEND_FACTOR_ONE,
            .dstColorBlendFactor = VK_BLEND_FACTOR_ONE,
            .colorBlendOp = VK_BLEND_OP_ADD,
            .srcAlphaBlendFactor = VK_BLEND_FACTOR_ONE,
            .dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE,
            .alphaBlendOp = VK_BLEND_OP_ADD,
            .colorWriteMask = d->no_color_write ? 0
                                                : VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT |
                                                      VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT,
        };
        if (d->blend_over && i == 0) { /* rgb = a src + (1 - a) dst; the target's alpha is kept */
            blend[i].blendEnable = VK_TRUE;
            blend[i].srcColorBlendFactor = VK_BLEND_FACTOR_SRC_ALPHA;
            blend[i].dstColorBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA;
            blend[i].srcAlphaBlendFactor = VK_BLEND_FACTOR_ZERO;
            blend[i].dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
        } else if (d->blend_over) {
            blend[i].colorWriteMask = 0;
        }
    }
    VkPipelineColorBlendStateCreateInfo cb = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO,
        .attachmentCount = d->color_count,
        .pAttachments = blend,
    };
    VkDynamicState dyn[3] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR, VK_DYNAMIC_STATE_DEPTH_BIAS};
    VkPipelineDynamicStateCreateInfo dy = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO,
        .dynamicStateCount = d->depth_bias ? 3 : 2,
        .pDynamicStates = dyn,
    };
    VkPipelineRenderingCreateInfo ri = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO,
        .viewMask = d->view_mask,
        .colorAttachmentCount = d->color_count,
        .pColorAttachmentFormats = d->color_formats,
        .depthAttachmentFormat = d->depth_format,
        .stencilAttachmentFormat = has_stencil(d->depth_format) ? d->depth_format : VK_FORMAT_UNDEFINED,
    };
    VkGraphicsPipelineCreateInfo ci = {
        .sType = VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO,
        .pNext = &ri,
        .stageCount = fs ? 2 : 1,
        .pStages = stages,
        .pVertexInputState = &vi,
        .pInputAssemblyState = &ia,
        .pViewportState = &vp,
        .pRasterizationState = &rs,
        .pMultisampleState = &ms,
        .pDepthStencilState = d->depth_format ? &ds : NULL,
        .pColorBlendState = d->color_count ? &cb : NULL,
        .pDynamicState = &dy,
        .layout = d->layout,
    };
    VkResult r = vkCreateGraphicsPipelines(gpu->device, gpu->pipeline_cache, 1, &ci, NULL, out);
    vkDestroyShaderModule(gpu->device, vs, NULL);
    if (fs) vkDestroyShaderModule(gpu->device, fs, NULL);
    if (!prw_vk_check(r, "gpu: vkCreateGraphicsPipelines", e)) return false;
    if (memo) prw_pipe_memo_add(gpu, &key, *out);
    return true;
}

bool prw_pipeline_compute(prw_gpu *gpu, prw_spirv cs, VkPipelineLayout layout, VkPipeline *out, prw_error *e)
{
    return prw_pipeline_compute_spec(gpu, cs, layout, NULL, 0, out, e);
}

bool prw_pipeline_compute_spec(prw_gpu *gpu, prw_spirv cs, VkPipelineLayout layout, const uint32_t *spec,
                               uint32_t spec_count, VkPipeline *out, prw_error *e)
{
    *out = VK_NULL_HANDLE;
    if (spec_count > 8) return prw_fail(e, "gpu: %u specialisation constants (at most 8)", spec_count);
    VkSpecializationMapEntry map[8];
    for (uint32_t i = 0; i < spec_count; i++) map[i] = (VkSpecializationMapEntry){.constantID = i, .offset = 4 * i, .size = 4};
    VkSpecializationInfo si = {.mapEntryCount = spec_count, .pMapEntries = map, .dataSize = 4 * (size_t)spec_count,
                               .pData = spec};
    prw_hash128 key;
    bool memo = prw_pipe_memo_enabled(gpu);
    if (memo) {
        prw_hash128_init(&key);
        static const char tag[] = "compute";
        prw_hash128_add(&key, tag, sizeof tag);
        hash_spirv(&key, cs);
        prw_hash128_add(&key, &spec_count, sizeof spec_count);
        if (spec_count) prw_hash128_add(&key, spec, spec_count * sizeof spec[0]);
        prw_playout_hash(gpu, layout, &key);
        if (prw_pipe_memo_find(gpu, &key, out)) return true;
    }
    VkShaderModule m;
    if (!make_module(gpu, cs, "compute", &m, e)) return false;
    VkComputePipelineCreateInfo ci = {
        .sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO,
        .stage = {.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
                  .stage = VK_SHADER_STAGE_COMPUTE_BIT,
                  .module = m,
                  .pName = "main",
                  .pSpecializationInfo = spec_count ? &si : NULL},
        .layout = layout,
    };
    VkResult r = vkCreateComputePipelines(gpu->device, gpu->pipeline_cache, 1, &ci, NULL, out);
    vkDestroyShaderModule(gpu->device, m, NULL);
    if (!prw_vk_check(r, "gpu: vkCreateComputePipelines", e)) return false;
    if (memo) prw_pipe_memo_add(gpu, &key, *out);
    return true;
}
