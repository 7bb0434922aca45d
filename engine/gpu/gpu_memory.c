/* gpu_memory.c — the suballocator: large VkDeviceMemory blocks per memory type, first-fit free
 * lists, dedicated blocks for big resources.
 *
 * Why separate blocks for linear (buffers) and optimal (images) resources: then neighbours in a
 * block always have the same tiling and bufferImageGranularity never applies.
 * Host-visible blocks are mapped once for their lifetime; kinds UPLOAD and READBACK only use
 * HOST_COHERENT types, so no flush/invalidate is ever needed.
 */
#include <stdlib.h>
#include <string.h>

#include "gpu_internal.h"

#define PRW_BLOCK_SIZE ((VkDeviceSize)64 << 20)

void prw_mem_init(prw_gpu *gpu)
{
    memset(&gpu->mem, 0, sizeof gpu->mem);
    gpu->mem.block_size = PRW_BLOCK_SIZE;
}

static void block_release(prw_gpu *gpu, prw_mem_block *b)
{
    if (b->mapped) vkUnmapMemory(gpu->device, b->memory);
    vkFreeMemory(gpu->device, b->memory, NULL);
    gpu->mem.reserved -= b->size;
    gpu->mem.live_blocks--;
    free(b->free);
    memset(b, 0, sizeof *b);
}

void prw_mem_shutdown(prw_gpu *gpu)
{
    for (uint32_t i = 0; i < gpu->mem.block_count; i++)
        if (gpu->mem.blocks[i].memory) block_release(gpu, &gpu->mem.blocks[i]);
    free(gpu->mem.blocks);
    memset(&gpu->mem, 0, sizeof gpu->mem);
}

void prw_gpu_mem_stats(const prw_gpu *gpu, prw_mem_stats *out)
{
    out->used_bytes = gpu->mem.used;
    out->peak_bytes = gpu->mem.peak;
    out->reserved_bytes = gpu->mem.reserved;
    out->block_count = gpu->mem.live_blocks;
    out->alloc_count = gpu->mem.live_allocs;
}

/* Best memory type for a kind among those allowed by type_bits: required flags must be present,
 * preferred flags win ties; UINT32_MAX when none fits. */
static uint32_t find_type(const prw_gpu *gpu, uint32_t type_bits, prw_mem_kind kind)
{
    VkMemoryPropertyFlags need = 0, want = 0, avoid = 0;
    switch (kind) {
    case PRW_MEM_GPU: want = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT; break;
    case PRW_MEM_UPLOAD:
        need = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
        avoid = VK_MEMORY_PROPERTY_HOST_CACHED_BIT; /* write-combined is best for CPU writes */
        break;
    case PRW_MEM_READBACK:
        need = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
        want = VK_MEMORY_PROPERTY_HOST_CACHED_BIT; /* CPU reads from uncached memory are very slow */
        break;
    }
    uint32_t best = UINT32_MAX;
    int best_score = -1;
    for (uint32_t i = 0; i < gpu->mem_props.memoryTypeCount; i++) {
        VkMemoryPropertyFlags f = gpu->mem_props.memoryTypes[i].propertyFlags;
        if (!(type_bits & (1u << i)) || (f & need) != need) continue;
        if (f & VK_MEMORY_PROPERTY_PROTECTED_BIT) continue;
        int score = ((f & want) == want ? 2 : 0) + ((f & avoid) ? 0 : 1);
        if (score > best_score) {
            best = i;
            best_score = score;
        }
    }
    return best;
}

static const char *kind_name(prw_mem_kind k)
{
    return k == PRW_MEM_GPU ? "gpu" : k == PRW_MEM_UPLOAD ? "upload" : "readback";
}

static VkDeviceSize heap_reserved(const prw_gpu *gpu, uint32_t heap)
{
    VkDeviceSize sum = 0;
    for (uint32_t i = 0; i < gpu->mem.block_count; i++) {
        const prw_mem_block *b = &gpu->mem.blocks[i];
        if (b->memory && gpu->mem_props.memoryTypes[b->type].heapIndex == heap) sum += b->size;
    }
    return sum;
}

static bool block_create(prw_gpu *gpu, uint32_t type, VkDeviceSize size, bool linear, bool dedicated,
                         uint32_t *out_index, prw_error *e)
{
    uint32_t heap = gpu->mem_props.memoryTypes[type].heapIndex;
    VkDeviceSize heap_size = gpu->mem_props.memoryHeaps[heap].size;
    VkDeviceSize reserved = heap_reserved(gpu, heap);
    /* Checked here because asking the driver for more than the heap is itself invalid usage. */
    if (size > heap_size || reserved + size > heap_size)
        return prw_fail(e, "gpu: out of device memory: need a %.1f MiB block, heap %u has %.1f MiB of which "
                           "%.1f MiB are reserved",
                        size / 1048576.0, heap, heap_size / 1048576.0, reserved / 1048576.0);
    if (gpu->mem.live_blocks >= gpu->props.limits.maxMemoryAllocationCount)
        return prw_fail(e, "gpu: out of device memory: maxMemoryAllocationCount (%u) reached",
                        gpu->props.limits.maxMemoryAllocationCount);
    VkMemoryAllocateInfo ai = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
        .allocationSize = size,
        .memoryTypeIndex = type,
    };
    VkDeviceMemory memory;
    VkResult r = vkAllocateMemory(gpu->device, &ai, NULL, &memory);
    if (r == VK_ERROR_OUT_OF_DEVICE_MEMORY || r == VK_ERROR_OUT_OF_HOST_MEMORY)
        return prw_fail(e, "gpu: out of device memory allocating a %.1f MiB block (memory type %u, %s)",
                        size / 1048576.0, type, prw_vk_result_name(r));
    if (!prw_vk_check(r, "gpu: vkAllocateMemory", e)) return false;
    void *mapped = NULL;
    if (gpu->mem_props.memoryTypes[type].propertyFlags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) {
        r = vkMapMemory(gpu->device, memory, 0, VK_WHOLE_SIZE, 0, &mapped);
        if (r != VK_SUCCESS) {
            vkFreeMemory(gpu->device, memory, NULL);
            return prw_vk_check(r, "gpu: vkMapMemory", e);
        }
    }
    /* Reuse a free slot so prw_alloc.block indices stay small and stable. */
    prw_mem *m = &gpu->mem;
    uint32_t idx = 0;
    while (idx < m->block_count && m->blocks[idx].memory) idx++;
    if (idx == m->block_count) {
        if (m->block_count == m->block_cap) {
            m->block_cap = m->block_cap ? m->block_cap * 2 : 16;
            m->blocks = prw_realloc(m->blocks, m->block_cap * sizeof *m->blocks);
        }
        memset(&m->blocks[m->block_count++], 0, sizeof *m->blocks);
    }
    prw_mem_block *b = &m->blocks[idx];
    b->memory = memory;
    b->size = size;
    b->type = type;
    b->linear = linear;
    b->dedicated = dedicated;
    b->mapped = mapped;
    b->free_cap = 8;
    b->free = prw_malloc(b->free_cap * sizeof *b->free);
    b->free[0] = (prw_mem_range){0, size};
    b->free_count = 1;
    m->reserved += size;
    m->live_blocks++;
    *out_index = idx;
    return true;
}

static VkDeviceSize align_up(VkDeviceSize v, VkDeviceSize a) { return a > 1 ? (v + a - 1) / a * a : v; }

/* First fit: the first free range that holds size bytes at an aligned offset. The alignment gap
 * before it stays free; the tail after it stays free. */
static bool block_take(prw_mem_block *b, VkDeviceSize size, VkDeviceSize alignment, VkDeviceSize *offset)
{
    for (uint32_t i = 0; i < b->free_count; i++) {
        prw_mem_range r = b->free[i];
        VkDeviceSize start = align_up(r.offset, alignment);
        if (start + size > r.offset + r.size) continue;
        VkDeviceSize head = start - r.offset, tail = r.offset + r.size - (start + size);
        if (head && tail) {
            if (b->free_count == b->free_cap) {
                b->free_cap *= 2;
                b->free = prw_realloc(b->free, b->free_cap * sizeof *b->free);
            }
            memmove(&b->free[i + 2], &b->free[i + 1], (b->free_count - i - 1) * sizeof *b->free);
            b->free[i] = (prw_mem_range){r.offset, head};
            b->free[i + 1] = (prw_mem_range){start + size, tail};
            b->free_count++;
        } else if (head) {
            b->free[i].size = head;
        } else if (tail) {
            b->free[i] = (prw_mem_range){start + size, tail};
        } else {
            memmove(&b->free[i], &b->free[i + 1], (b->free_count - i - 1) * sizeof *b->free);
            b->free_count--;
        }
        *offset = start;
        return true;
    }
    return false;
}

/* Returns a range to the sorted free list, merging with its neighbours. */
static void block_give(prw_mem_block *b, VkDeviceSize offset, VkDeviceSize size)
{
    uint32_t i = 0;
    while (i < b->free_count && b->free[i].offset < offset) i++;
    bool merge_prev = i > 0 && b->free[i - 1].offset + b->free[i - 1].size == offset;
    bool merge_next = i < b->free_count && offset + size == b->free[i].offset;
    if (merge_prev && merge_next) {
        b->free[i - 1].size += size + b->free[i].size;
        memmove(&b->free[i], &b->free[i + 1], (b->free_count - i - 1) * sizeof *b->free);
        b->free_count--;
    } else if (merge_prev) {
        b->free[i - 1].size += size;
    } else if (merge_next) {
        b->free[i].offset = offset;
        b->free[i].size += size;
    } else {
        if (b->free_count == b->free_cap) {
            b->free_cap *= 2;
            b->free = prw_realloc(b->free, b->free_cap * sizeof *b->free);
        }
        memmove(&b->free[i + 1], &b->free[i], (b->free_count - i) * sizeof *b->free);
        b->free[i] = (prw_mem_range){offset, size};
        b->free_count++;
    }
}

bool prw_mem_alloc(prw_gpu *gpu, const VkMemoryRequirements *req, prw_mem_kind kind, bool linear, prw_alloc *out,
                   prw_error *e)
{
    memset(out, 0, sizeof *out);
    uint32_t type = find_type(gpu, req->memoryTypeBits, kind);
    if (type == UINT32_MAX)
        return prw_fail(e, "gpu: no memory type for %s memory (allowed type bits 0x%x)", kind_name(kind),
                        req->memoryTypeBits);
    prw_mem *m = &gpu->mem;
    /* Do not let a small heap be swallowed by one 64 MiB block. */
    VkDeviceSize heap_size = gpu->mem_props.memoryHeaps[gpu->mem_props.memoryTypes[type].heapIndex].size;
    VkDeviceSize block_size = PRW_MIN(m->block_size, heap_size / 8);
    VkDeviceSize size = req->size ? req->size : 1;
    uint32_t idx = UINT32_MAX;
    VkDeviceSize offset = 0;
    if (size > block_size / 2) {
        if (!block_create(gpu, type, size, linear, true, &idx, e)) return false;
        block_take(&m->blocks[idx], size, 1, &offset);
    } else {
        for (uint32_t i = 0; i < m->block_count && idx == UINT32_MAX; i++) {
            prw_mem_block *b = &m->blocks[i];
            if (b->memory && !b->dedicated && b->type == type && b->linear == linear &&
                block_take(b, size, req->alignment, &offset))
                idx = i;
        }
        if (idx == UINT32_MAX) {
            if (!block_create(gpu, type, block_size, linear, false, &idx, e)) return false;
            block_take(&m->blocks[idx], size, req->alignment, &offset);
        }
    }
    prw_mem_block *b = &m->blocks[idx];
    b->used += size;
    b->allocs++;
    m->used += size;
    m->live_allocs++;
    if (m->used > m->peak) m->peak = m->used;
    out->memory = b->memory;
    out->offset = offset;
    out->size = size;
    out->block = idx;
    out->mapped = b->mapped ? (char *)b->mapped + offset : NULL;
    return true;
}

void prw_mem_free(prw_gpu *gpu, prw_alloc *a)
{
    if (!a || !a->memory) return;
    prw_mem *m = &gpu->mem;
    prw_mem_block *b = &m->blocks[a->block];
    block_give(b, a->offset, a->size);
    b->used -= a->size;
    b->allocs--;
    m->used -= a->size;
    m->live_allocs--;
    if (b->allocs == 0) {
        /* Keep at most one empty shared block per (type, tiling) so upload/readback staging does
         * not allocate and free 64 MiB on every call. */
        bool keep = !b->dedicated;
        for (uint32_t i = 0; i < m->block_count && keep; i++) {
            prw_mem_block *o = &m->blocks[i];
            if (o != b && o->memory && !o->dedicated && o->allocs == 0 && o->type == b->type && o->linear == b->linear)
                keep = false;
        }
        if (!keep) block_release(gpu, b);
    }
    memset(a, 0, sizeof *a);
}
