/* gpu_desc.c — descriptor set layouts, a growing pool (a chain of VkDescriptorPools) and writers.
 *
 * The pool counts descriptors itself and moves to the next VkDescriptorPool before one would be
 * exhausted: drivers differ in whether they report VK_ERROR_OUT_OF_POOL_MEMORY (lavapipe never
 * does), and over-allocating a pool is invalid usage either way.
 */
#include <stdlib.h>
#include <string.h>

#include "gpu_internal.h"

#define POOL_SETS 256
static const uint32_t k_pool_counts[PRW_DESC_TYPES] = {
    [VK_DESCRIPTOR_TYPE_SAMPLER] = 64,
    [VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER] = 1024,
    [VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE] = 256,
    [VK_DESCRIPTOR_TYPE_STORAGE_IMAGE] = 128,
    [VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER] = 32,
    [VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER] = 32,
    [VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER] = 512,
    [VK_DESCRIPTOR_TYPE_STORAGE_BUFFER] = 512,
    [VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC] = 64,
    [VK_DESCRIPTOR_TYPE_STORAGE_BUFFER_DYNAMIC] = 64,
    [VK_DESCRIPTOR_TYPE_INPUT_ATTACHMENT] = 32,
};

typedef struct pool_entry {
    VkDescriptorPool pool;
    uint32_t max_sets, sets;
    uint32_t max[PRW_DESC_TYPES], used[PRW_DESC_TYPES];
} pool_entry;

struct prw_desc_pool {
    pool_entry *pools;
    uint32_t count, cap;
    uint32_t current;
};

bool prw_desc_layout_create(prw_gpu *gpu, const VkDescriptorSetLayoutBinding *bindings, uint32_t count,
                            VkDescriptorSetLayout *out, prw_error *e)
{
    prw_desc_layout_info info = {0};
    for (uint32_t i = 0; i < count; i++) {
        if ((uint32_t)bindings[i].descriptorType >= PRW_DESC_TYPES)
            return prw_fail(e, "gpu: descriptor layout binding %u: unsupported descriptor type %d",
                            bindings[i].binding, (int)bindings[i].descriptorType);
        info.counts[bindings[i].descriptorType] += bindings[i].descriptorCount;
    }
    VkDescriptorSetLayoutCreateInfo ci = {
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO,
        .bindingCount = count,
        .pBindings = bindings,
    };
    if (!prw_vk_check(vkCreateDescriptorSetLayout(gpu->device, &ci, NULL, out), "gpu: vkCreateDescriptorSetLayout",
                      e))
        return false;
    /* Remember the counts; a handle value reused after the caller destroyed a layout overwrites. */
    info.layout = *out;
    prw_hash128_init(&info.sig);
    for (uint32_t i = 0; i < count; i++) {
        const VkDescriptorSetLayoutBinding *b = &bindings[i];
        uint32_t f[4] = {b->binding, (uint32_t)b->descriptorType, b->descriptorCount, (uint32_t)b->stageFlags};
        prw_hash128_add(&info.sig, f, sizeof f);
        if (b->pImmutableSamplers) prw_hash128_add(&info.sig, b->pImmutableSamplers, b->descriptorCount * sizeof(VkSampler));
    }
    for (uint32_t i = 0; i < gpu->layout_count; i++) {
        if (gpu->layouts[i].layout == *out) {
            gpu->layouts[i] = info;
            return true;
        }
    }
    gpu->layouts = prw_realloc(gpu->layouts, (gpu->layout_count + 1) * sizeof *gpu->layouts);
    gpu->layouts[gpu->layout_count++] = info;
    return true;
}

void prw_desc_shutdown(prw_gpu *gpu)
{
    free(gpu->layouts);
    gpu->layouts = NULL;
    gpu->layout_count = 0;
}

static bool pool_add(prw_gpu *gpu, prw_desc_pool *p, const uint32_t *need, prw_error *e)
{
    pool_entry pe = {.max_sets = POOL_SETS};
    VkDescriptorPoolSize sizes[PRW_DESC_TYPES];
    uint32_t n = 0;
    for (uint32_t t = 0; t < PRW_DESC_TYPES; t++) {
        /* A set bigger than the default pool gets a pool sized for it. */
        pe.max[t] = PRW_MAX(k_pool_counts[t], need ? need[t] : 0);
        sizes[n++] = (VkDescriptorPoolSize){(VkDescriptorType)t, pe.max[t]};
    }
    VkDescriptorPoolCreateInfo ci = {
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO,
        .maxSets = pe.max_sets,
        .poolSizeCount = n,
        .pPoolSizes = sizes,
    };
    if (!prw_vk_check(vkCreateDescriptorPool(gpu->device, &ci, NULL, &pe.pool), "gpu: vkCreateDescriptorPool", e))
        return false;
    if (p->count == p->cap) {
        p->cap = p->cap ? p->cap * 2 : 4;
        p->pools = prw_realloc(p->pools, p->cap * sizeof *p->pools);
    }
    p->pools[p->count++] = pe;
    return true;
}

bool prw_desc_pool_create(prw_gpu *gpu, prw_desc_pool **out, prw_error *e)
{
    prw_desc_pool *p = prw_calloc(1, sizeof *p);
    if (!pool_add(gpu, p, NULL, e)) {
        free(p);
        return false;
    }
    *out = p;
    return true;
}

void prw_desc_pool_destroy(prw_gpu *gpu, prw_desc_pool *pool)
{
    if (!pool) return;
    for (uint32_t i = 0; i < pool->count; i++) vkDestroyDescriptorPool(gpu->device, pool->pools[i].pool, NULL);
    free(pool->pools);
    free(pool);
}

void prw_desc_pool_reset(prw_gpu *gpu, prw_desc_pool *pool)
{
    for (uint32_t i = 0; i < pool->count; i++) {
        vkResetDescriptorPool(gpu->device, pool->pools[i].pool, 0);
        pool->pools[i].sets = 0;
        memset(pool->pools[i].used, 0, sizeof pool->pools[i].used);
    }
    pool->current = 0;
}

static bool fits(const pool_entry *pe, const uint32_t *need)
{
    if (pe->sets >= pe->max_sets) return false;
    for (uint32_t t = 0; t < PRW_DESC_TYPES; t++)
        if (pe->used[t] + need[t] > pe->max[t]) return false;
    return true;
}

bool prw_desc_alloc(prw_gpu *gpu, prw_desc_pool *pool, VkDescriptorSetLayout layout, VkDescriptorSet *out,
                    prw_error *e)
{
    const uint32_t *need = NULL;
    for (uint32_t i = 0; i < gpu->layout_count && !need; i++)
        if (gpu->layouts[i].layout == layout) need = gpu->layouts[i].counts;
    if (!need) return prw_fail(e, "gpu: descriptor set layout was not made by prw_desc_layout_create");
    /* Earlier pools are full (or too small for this layout); look from the current one on. */
    while (pool->current < pool->count && !fits(&pool->pools[pool->current], need)) pool->current++;
    if (pool->current == pool->count && !pool_add(gpu, pool, need, e)) return false;
    pool_entry *pe = &pool->pools[pool->current];
    VkDescriptorSetAllocateInfo ai = {
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO,
        .descriptorPool = pe->pool,
        .descriptorSetCount = 1,
        .pSetLayouts = &layout,
    };
    if (!prw_vk_check(vkAllocateDescriptorSets(gpu->device, &ai, out), "gpu: vkAllocateDescriptorSets", e))
        return false;
    pe->sets++;
    for (uint32_t t = 0; t < PRW_DESC_TYPES; t++) pe->used[t] += need[t];
    return true;
}

void prw_desc_write_buffer(prw_gpu *gpu, VkDescriptorSet set, uint32_t binding, VkDescriptorType type,
                           const prw_buffer *b, VkDeviceSize offset, VkDeviceSize range)
{
    VkDescriptorBufferInfo bi = {.buffer = b->buffer, .offset = offset, .range = range ? range : VK_WHOLE_SIZE};
    VkWriteDescriptorSet w = {
        .sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
        .dstSet = set,
        .dstBinding = binding,
        .descriptorCount = 1,
        .descriptorType = type,
        .pBufferInfo = &bi,
    };
    vkUpdateDescriptorSets(gpu->device, 1, &w, 0, NULL);
}

void prw_desc_write_image(prw_gpu *gpu, VkDescriptorSet set, uint32_t binding, uint32_t array_element,
                          VkDescriptorType type, VkImageView view, VkSampler sampler, VkImageLayout layout)
{
    VkDescriptorImageInfo ii = {.sampler = sampler, .imageView = view, .imageLayout = layout};
    VkWriteDescriptorSet w = {
        .sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
        .dstSet = set,
        .dstBinding = binding,
        .dstArrayElement = array_element,
        .descriptorCount = 1,
        .descriptorType = type,
        .pImageInfo = &ii,
    };
    vkUpdateDescriptorSets(gpu->device, 1, &w, 0, NULL);
}
