/* gpu_internal.h — the prw_gpu struct and helpers shared by the gpu_*.c files (not a public header).
 *
 * The gpu is single-threaded by design: one thread records, submits and allocates.  Only the
 * validation counters are atomic, because the layer may call the messenger from any thread.
 */
#ifndef PRW_GPU_INTERNAL_H
#define PRW_GPU_INTERNAL_H

#include <stdatomic.h>

#include "prw_gpu.h"

/* One free range inside a memory block. */
typedef struct prw_mem_range {
    VkDeviceSize offset, size;
} prw_mem_range;

typedef struct prw_mem_block {
    VkDeviceMemory memory; /* VK_NULL_HANDLE: slot unused */
    VkDeviceSize size, used;
    uint32_t type;
    uint32_t allocs;
    bool linear, dedicated;
    void *mapped;
    prw_mem_range *free; /* sorted by offset, never adjacent (merged on free) */
    uint32_t free_count, free_cap;
} prw_mem_block;

typedef struct prw_mem {
    prw_mem_block *blocks;
    uint32_t block_count, block_cap;
    VkDeviceSize block_size;
    uint64_t used, peak, reserved;
    uint32_t live_blocks, live_allocs;
} prw_mem;

/* What prw_desc_layout_create() learned about a layout, so pools can count descriptors themselves
 * (lavapipe never reports VK_ERROR_OUT_OF_POOL_MEMORY, so relying on the driver is not enough). */
#define PRW_DESC_TYPES 11 /* VK_DESCRIPTOR_TYPE_SAMPLER .. VK_DESCRIPTOR_TYPE_INPUT_ATTACHMENT */
typedef struct prw_hash128 {
    uint64_t a, b;
} prw_hash128;

typedef struct prw_desc_layout_info {
    VkDescriptorSetLayout layout;
    uint32_t counts[PRW_DESC_TYPES];
    prw_hash128 sig; /* of its bindings: the content a pipeline's compatibility depends on */
} prw_desc_layout_info;

/* gpu_pipeline_memo.c: a pipeline layout's content signature; a shared pipeline */
typedef struct prw_playout_sig {
    VkPipelineLayout layout;
    prw_hash128 sig;
} prw_playout_sig;

typedef struct prw_pipe_memo_entry {
    prw_hash128 key;
    VkPipeline pipe;
    uint32_t refs; /* holders; 0 keeps it for the next one */
} prw_pipe_memo_entry;

/* A command buffer whose fence wait timed out: it may still be executing, so it is freed only once
 * the queue is known to be idle. */
typedef struct prw_orphan {
    VkCommandBuffer cmd;
    VkFence fence;
} prw_orphan;

struct prw_gpu {
    VkInstance instance;
    VkDebugUtilsMessengerEXT messenger;
    VkPhysicalDevice physical;
    VkDevice device;
    VkQueue queue;
    uint32_t queue_family;
    uint32_t timestamp_valid_bits;
    VkPhysicalDeviceProperties props;
    VkPhysicalDeviceMemoryProperties mem_props;
    prw_gpu_features features;
    char driver_info[VK_MAX_DRIVER_INFO_SIZE + VK_MAX_DRIVER_NAME_SIZE + 8];
    bool present;

    /* validation */
    bool validation;
    atomic_uint validation_count;
    char **suppress;
    uint32_t suppress_count;

    /* pipeline cache */
    VkPipelineCache pipeline_cache;
    char *cache_dir;  /* NULL: not persisted */
    char *cache_path;

    /* commands */
    VkCommandPool cmd_pool;
    double timeout_s;
    prw_orphan *orphans;
    uint32_t orphan_count;

    VkSampler samplers[PRW_SAMPLER_COUNT];
    prw_desc_layout_info *layouts;
    uint32_t layout_count;

    /* shared pipelines (gpu_pipeline_memo.c) */
    int memo_state; /* 0 unknown, 1 on, 2 off (PRW_PIPELINE_MEMO=0) */
    prw_pipe_memo_entry *memo;
    uint32_t memo_count, memo_cap;
    uint64_t memo_hits;
    prw_playout_sig *playouts;
    uint32_t playout_count, playout_cap;
    prw_mem mem;
};

/* gpu_pipeline_memo.c */
void prw_hash128_init(prw_hash128 *h);
void prw_hash128_add(prw_hash128 *h, const void *data, size_t n);
bool prw_pipe_memo_enabled(prw_gpu *gpu);
void prw_playout_note(prw_gpu *gpu, VkPipelineLayout layout, const prw_hash128 *sig);
void prw_playout_hash(prw_gpu *gpu, VkPipelineLayout layout, prw_hash128 *h); /* adds its signature to h */
bool prw_pipe_memo_find(prw_gpu *gpu, const prw_hash128 *key, VkPipeline *out);
void prw_pipe_memo_add(prw_gpu *gpu, const prw_hash128 *key, VkPipeline pipe);
void prw_pipe_memo_shutdown(prw_gpu *gpu);

/* gpu_validation.c */
bool prw_validation_load_suppressions(prw_gpu *gpu, const char *path, prw_error *e);
void prw_validation_messenger_info(prw_gpu *gpu, VkDebugUtilsMessengerCreateInfoEXT *info);
void prw_validation_free(prw_gpu *gpu);

/* gpu_memory.c */
void prw_mem_init(prw_gpu *gpu);
void prw_mem_shutdown(prw_gpu *gpu);

/* gpu_pipeline_cache.c */
bool prw_pipeline_cache_init(prw_gpu *gpu, const char *cache_dir, prw_error *e);
void prw_pipeline_cache_shutdown(prw_gpu *gpu);

/* gpu_sampler.c */
bool prw_samplers_init(prw_gpu *gpu, prw_error *e);
void prw_samplers_shutdown(prw_gpu *gpu);

/* gpu_desc.c */
void prw_desc_shutdown(prw_gpu *gpu);

/* gpu_cmd.c */
bool prw_cmd_init(prw_gpu *gpu, prw_error *e);
void prw_cmd_shutdown(prw_gpu *gpu);
/* Waits for a fence with the gpu's timeout; names the wait in the error. */
bool prw_fence_wait(prw_gpu *gpu, VkFence fence, const char *what, prw_error *e);
const char *prw_vk_result_name(VkResult r);

/* gpu_image.c */
uint32_t prw_format_texel_bytes(VkFormat f, uint32_t *block_w, uint32_t *block_h);
VkImageAspectFlags prw_format_aspect(VkFormat f);

/* gpu_swapchain.c: instance extensions GLFW needs for a surface (NULL + error when GLFW cannot). */
const char **prw_swapchain_instance_extensions(uint32_t *count, prw_error *e);

#endif
