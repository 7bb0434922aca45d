/* prw_gpu — the Vulkan 1.3 backend: it knows the GPU, nothing about scenes.
 *
 * Promises:
 *  - One prw_gpu per process: instance, one physical device (chosen by --device / PRW_DEVICE, index
 *    or name substring), one graphics+compute queue, a pipeline cache persisted in a cache directory,
 *    dynamic rendering and synchronization2 enabled (core 1.3).
 *  - Validation: when desc.validation or PRW_VALIDATION=1, VK_LAYER_KHRONOS_validation is enabled with a
 *    debug messenger that counts WARNING and ERROR messages of the validation and performance types.
 *    Messages whose VUID / message-id name is listed in the suppression file (desc.suppress_file or
 *    PRW_VALIDATION_SUPPRESS; lines "VUID  reason", '#' comments) are not counted.  Counted messages are
 *    logged at error level.  Tests fail when prw_gpu_validation_count() != 0.  PRW_VALIDATION_SYNC=1
 *    additionally enables the layer's synchronization (hazard) validation.
 *  - Threading: a prw_gpu is used from one thread at a time (recording, submits, allocation).
 *  - Memory: every buffer and image is suballocated from large VkDeviceMemory blocks per memory type;
 *    prw_gpu_mem_stats() reports the allocator's own accounting.
 *  - Waits never hang: every fence wait has a timeout; timeout, VK_ERROR_DEVICE_LOST and out-of-memory
 *    become a clear prw_error.
 *  - Layout tracking: prw_gpu_image remembers its current layout; prw_cmd_transition() emits a
 *    synchronization2 barrier to a new layout with stage/access masks derived from the two layouts.
 *  - Raw Vulkan handles are exposed: the renderer records vkCmd* itself.
 */
#ifndef PRW_GPU_H
#define PRW_GPU_H

#include <vulkan/vulkan.h>

#include "prw_core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct prw_gpu prw_gpu;

typedef struct prw_gpu_desc {
    int device_index;        /* -1: PRW_DEVICE env (index or name substring), else the first device */
    const char *device_name; /* substring match on deviceName; overrides device_index when set */
    bool validation;         /* also enabled by PRW_VALIDATION=1 */
    const char *suppress_file;
    bool present;            /* enable surface/swapchain extensions (GLFW must be initialised) */
    const char *cache_dir;   /* NULL: PRW_CACHE_DIR, else $XDG_CACHE_HOME/prw, else $HOME/.cache/prw */
} prw_gpu_desc;

bool prw_gpu_create(const prw_gpu_desc *desc, prw_gpu **out, prw_error *e);
void prw_gpu_destroy(prw_gpu *gpu); /* saves the pipeline cache */

uint32_t prw_gpu_validation_count(const prw_gpu *gpu);
/* Process-wide count of counted validation messages, including those emitted while a gpu is being
 * destroyed (object leaks are reported by the layer at vkDestroyDevice, after the gpu is gone). */
uint32_t prw_gpu_validation_total(void);
const char *prw_gpu_device_name(const prw_gpu *gpu);
const char *prw_gpu_driver_info(const prw_gpu *gpu); /* e.g. "Mesa 22.3.6 (LLVM 15.0.6)" */
/* Lists devices as "index: name (driver)" lines into buf. */
bool prw_gpu_list_devices(char *buf, size_t cap, prw_error *e);

/* Optional features, enabled at create when the device supports them. */
typedef struct prw_gpu_features {
    bool multiview, fill_mode_non_solid, independent_blend, shader_float64, shader_draw_parameters, clip_distance;
} prw_gpu_features;
const prw_gpu_features *prw_gpu_features_enabled(const prw_gpu *gpu);

VkInstance prw_gpu_instance(const prw_gpu *gpu);
VkPhysicalDevice prw_gpu_physical(const prw_gpu *gpu);
VkDevice prw_gpu_device(const prw_gpu *gpu);
VkQueue prw_gpu_queue(const prw_gpu *gpu);
uint32_t prw_gpu_queue_family(const prw_gpu *gpu);
VkPipelineCache prw_gpu_pipeline_cache(const prw_gpu *gpu);
const VkPhysicalDeviceProperties *prw_gpu_properties(const prw_gpu *gpu);
/* Turns a VkResult into an error message naming the call; returns false unless r == VK_SUCCESS. */
bool prw_vk_check(VkResult r, const char *what, prw_error *e);

/* ---- memory ---- */
typedef enum prw_mem_kind {
    PRW_MEM_GPU = 0,   /* device local */
    PRW_MEM_UPLOAD,    /* host visible + coherent, written by the CPU */
    PRW_MEM_READBACK,  /* host visible (+ cached when available), read by the CPU */
} prw_mem_kind;

typedef struct prw_alloc {
    VkDeviceMemory memory;
    VkDeviceSize offset, size;
    uint32_t block; /* allocator-internal */
    void *mapped;   /* host pointer at offset, or NULL */
} prw_alloc;

typedef struct prw_mem_stats {
    uint64_t used_bytes;     /* live suballocations */
    uint64_t peak_bytes;     /* maximum of used_bytes */
    uint64_t reserved_bytes; /* VkDeviceMemory blocks */
    uint32_t block_count, alloc_count;
} prw_mem_stats;

void prw_gpu_mem_stats(const prw_gpu *gpu, prw_mem_stats *out);
/* Raw suballocation (buffers and images use these).  linear: buffers / linear-tiling images;
 * optimal-tiling images live in separate blocks so bufferImageGranularity never matters.
 * Allocations larger than a block get a dedicated VkDeviceMemory. */
bool prw_mem_alloc(prw_gpu *gpu, const VkMemoryRequirements *req, prw_mem_kind kind, bool linear, prw_alloc *out,
                   prw_error *e);
void prw_mem_free(prw_gpu *gpu, prw_alloc *a);

/* ---- buffers ---- */
typedef struct prw_buffer {
    VkBuffer buffer;
    VkDeviceSize size;
    prw_alloc alloc;
    void *mapped; /* non-NULL for UPLOAD/READBACK */
} prw_buffer;

/* TRANSFER_SRC|DST usage is always added.  mapped is set for UPLOAD/READBACK only (host-coherent). */
bool prw_buffer_create(prw_gpu *gpu, VkDeviceSize size, VkBufferUsageFlags usage, prw_mem_kind kind,
                       prw_buffer *out, prw_error *e);
void prw_buffer_destroy(prw_gpu *gpu, prw_buffer *b);
/* Copies data into b at offset (through a staging buffer and a waited submit if b is GPU memory). */
bool prw_buffer_upload(prw_gpu *gpu, prw_buffer *b, VkDeviceSize offset, const void *data, VkDeviceSize size,
                       prw_error *e);

/* ---- images ---- */
typedef struct prw_image_desc {
    uint32_t width, height;
    uint32_t layers;             /* 0 -> 1 */
    uint32_t mips;               /* 0 -> 1 */
    VkFormat format;
    VkSampleCountFlagBits samples; /* 0 -> 1 */
    VkImageUsageFlags usage;
    VkImageViewType view_type;   /* 0 -> 2D (or 2D_ARRAY when layers > 1) */
    bool cube;                   /* cube-compatible (layers must be 6*n) */
} prw_image_desc;

typedef struct prw_gpu_image {
    VkImage image;
    VkImageView view;       /* all layers and mips (depth/stencil formats: depth aspect only) */
    VkImageView *layer_views; /* one 2D view per layer (mip 0), for rendering into layers */
    prw_alloc alloc;
    VkFormat format;
    VkImageAspectFlags aspect;
    uint32_t width, height, layers, mips;
    VkSampleCountFlagBits samples;
    VkImageLayout layout;   /* current layout, tracked by prw_cmd_transition */
    VkImageUsageFlags usage;
} prw_gpu_image;

bool prw_image_create(prw_gpu *gpu, const prw_image_desc *desc, prw_gpu_image *out, prw_error *e);
void prw_image_destroy(prw_gpu *gpu, prw_gpu_image *img);
/* Uploads tightly packed mip-0 pixels of layer `layer`; when mips > 1, generates the chain by blits.
 * Needs TRANSFER_DST usage (+ TRANSFER_SRC for mips).  Leaves the image in SHADER_READ_ONLY_OPTIMAL
 * (images without SAMPLED/INPUT_ATTACHMENT usage: TRANSFER_SRC_OPTIMAL, else TRANSFER_DST_OPTIMAL). */
bool prw_image_upload(prw_gpu *gpu, prw_gpu_image *img, uint32_t layer, const void *pixels, size_t bytes,
                      prw_error *e);
/* Reads mip 0 / layer 0 of a single-sample colour image of format R16G16B16A16_SFLOAT, R32G32B32A32_SFLOAT
 * or R8G8B8A8_(UNORM|SRGB) into float RGBA (8-bit values are returned as stored / 255). */
bool prw_image_readback(prw_gpu *gpu, prw_gpu_image *img, float *rgba, prw_error *e);

/* Reads mip 0 / layer 0 of a single-sample D32_SFLOAT image (depth aspect) or an R32_UINT / R32_SFLOAT
 * colour image into width*height 32-bit values (floats; R32_UINT values stored as their uint bits). */
bool prw_image_readback_r32(prw_gpu *gpu, prw_gpu_image *img, void *out, prw_error *e);

void prw_cmd_transition(VkCommandBuffer cmd, prw_gpu_image *img, VkImageLayout new_layout);
/* The stages and accesses an image in `layout` may be used with (what prw_cmd_transition assumes). */
void prw_layout_access(VkImageLayout layout, VkImageAspectFlags aspect, VkPipelineStageFlags2 *stages,
                       VkAccessFlags2 *reads, VkAccessFlags2 *writes);

/* ---- samplers ---- */
typedef enum prw_sampler_kind {
    PRW_SAMPLER_LINEAR_REPEAT = 0, /* trilinear, anisotropy off (lavapipe has none) */
    PRW_SAMPLER_LINEAR_CLAMP,
    PRW_SAMPLER_NEAREST_CLAMP,
    PRW_SAMPLER_SHADOW,            /* compare GREATER_OR_EQUAL (reversed Z), linear PCF, clamp to border 0 */
    PRW_SAMPLER_SHADOW_DEPTH,      /* the shadow atlas's depths for gathers: nearest, no compare, border 0 */
    PRW_SAMPLER_COUNT
} prw_sampler_kind;

VkSampler prw_gpu_sampler(prw_gpu *gpu, prw_sampler_kind kind); /* owned by gpu */

/* ---- descriptors (no bindless) ---- */
bool prw_desc_layout_create(prw_gpu *gpu, const VkDescriptorSetLayoutBinding *bindings, uint32_t count,
                            VkDescriptorSetLayout *out, prw_error *e);

/* A growing descriptor pool; reset whenever its sets are no longer in use. */
typedef struct prw_desc_pool prw_desc_pool;
bool prw_desc_pool_create(prw_gpu *gpu, prw_desc_pool **out, prw_error *e);
void prw_desc_pool_destroy(prw_gpu *gpu, prw_desc_pool *pool);
void prw_desc_pool_reset(prw_gpu *gpu, prw_desc_pool *pool);
bool prw_desc_alloc(prw_gpu *gpu, prw_desc_pool *pool, VkDescriptorSetLayout layout, VkDescriptorSet *out,
                    prw_error *e);
/* Writers for the common cases (range 0 = VK_WHOLE_SIZE).  prw_desc_alloc only accepts layouts made
 * by prw_desc_layout_create (it counts descriptors per pool itself). */
void prw_desc_write_buffer(prw_gpu *gpu, VkDescriptorSet set, uint32_t binding, VkDescriptorType type,
                           const prw_buffer *b, VkDeviceSize offset, VkDeviceSize range);
void prw_desc_write_image(prw_gpu *gpu, VkDescriptorSet set, uint32_t binding, uint32_t array_element,
                          VkDescriptorType type, VkImageView view, VkSampler sampler, VkImageLayout layout);

/* ---- pipelines ---- */
typedef struct prw_spirv {
    const uint32_t *code;
    size_t size; /* bytes */
} prw_spirv;

/* Push constants are one range [0, push_constant_bytes) with stageFlags VK_SHADER_STAGE_ALL, so
 * vkCmdPushConstants must be called with VK_SHADER_STAGE_ALL too (the layer requires the push's
 * stageFlags to cover every stage of the range). */
bool prw_pipeline_layout_create(prw_gpu *gpu, const VkDescriptorSetLayout *sets, uint32_t set_count,
                                uint32_t push_constant_bytes, VkPipelineLayout *out, prw_error *e);
/* Same with an explicit stage set for the push-constant range (0 = VK_SHADER_STAGE_ALL); push with
 * exactly these stages. */
bool prw_pipeline_layout_create_stages(prw_gpu *gpu, const VkDescriptorSetLayout *sets, uint32_t set_count,
                                       uint32_t push_constant_bytes, VkShaderStageFlags push_stages,
                                       VkPipelineLayout *out, prw_error *e);

#define PRW_GPU_MAX_FS_SPEC 12 /* specialisation constants of one fragment shader */

typedef struct prw_graphics_desc {
    prw_spirv vs, fs;        /* fs.code may be NULL (depth-only) */
    uint32_t fs_spec[PRW_GPU_MAX_FS_SPEC]; /* the fragment shader's specialisation constants: constant_id i = fs_spec[i] */
    uint32_t fs_spec_count;  /* (32-bit int or bool each), 0 = none */
    VkPipelineLayout layout;
    const VkVertexInputBindingDescription *vertex_bindings;
    uint32_t vertex_binding_count;
    const VkVertexInputAttributeDescription *vertex_attrs;
    uint32_t vertex_attr_count;
    VkPrimitiveTopology topology; /* 0 = TRIANGLE_LIST */
    VkFormat color_formats[4];
    uint32_t color_count;
    VkFormat depth_format;        /* VK_FORMAT_UNDEFINED: no depth */
    VkSampleCountFlagBits samples; /* 0 -> 1 */
    VkCullModeFlags cull;         /* 0 = none */
    VkFrontFace front_face;       /* 0 = COUNTER_CLOCKWISE */
    bool depth_test, depth_write;
    VkCompareOp depth_compare;    /* 0 (NEVER) means GREATER_OR_EQUAL: reversed Z */
    bool depth_bias;              /* dynamic depth bias enabled */
    bool blend_additive;          /* ONE + ONE on all colour attachments */
    bool blend_over;              /* attachment 0: rgb = src.a src + (1 - src.a) dst, alpha kept; the other
                                     attachments are not written (surfaces blended over the image) */
    bool no_color_write;          /* colour write mask 0 (e.g. a depth pre-pass into a colour target) */
    bool stencil_test;            /* needs a depth format with stencil */
    VkStencilOpState stencil;     /* front and back (with stencil_test) */
    uint32_t view_mask;           /* multiview; 0 = off */
} prw_graphics_desc;

/* Pipelines are shared within the process: for a description equal to an earlier one (same SPIR-V
 * bytes, constants and state, and a pipeline layout of equal content: the same set-layout bindings
 * and push range) these return the pipeline made then instead of compiling it again.  The gpu owns
 * every pipeline they return: give it back with prw_pipeline_release, never vkDestroyPipeline; shared
 * ones live until prw_gpu_destroy.  PRW_PIPELINE_MEMO=0 in the environment turns sharing off (each
 * call compiles, release destroys).  Viewport and scissor are dynamic state. */
bool prw_pipeline_graphics(prw_gpu *gpu, const prw_graphics_desc *desc, VkPipeline *out, prw_error *e);
bool prw_pipeline_compute(prw_gpu *gpu, prw_spirv cs, VkPipelineLayout layout, VkPipeline *out, prw_error *e);
/* The same with specialisation constants: constant_id i = spec[i] (32-bit int or bool each, at most 8). */
bool prw_pipeline_compute_spec(prw_gpu *gpu, prw_spirv cs, VkPipelineLayout layout, const uint32_t *spec,
                               uint32_t spec_count, VkPipeline *out, prw_error *e);

void prw_pipeline_release(prw_gpu *gpu, VkPipeline pipe); /* VK_NULL_HANDLE: nothing */
/* Shared pipelines made so far, and how many requests they answered without compiling. */
void prw_pipeline_memo_stats(const prw_gpu *gpu, uint32_t *pipelines, uint64_t *hits);

/* Pipelines by key (a byte string of at most PRW_PIPELINE_KEY_MAX bytes; zero padding is part of the
 * key, so keys should be memset before they are filled).  The table holds its pipelines (released
 * with prw_pipeline_release when removed or destroyed). */
#define PRW_PIPELINE_KEY_MAX 64
typedef struct prw_pipeline_table prw_pipeline_table;
bool prw_pipeline_table_create(prw_gpu *gpu, prw_pipeline_table **out, prw_error *e);
void prw_pipeline_table_destroy(prw_pipeline_table *t);
VkPipeline prw_pipeline_table_find(const prw_pipeline_table *t, const void *key, size_t size);
/* Takes ownership of pipe (destroyed on failure too). */
bool prw_pipeline_table_add(prw_pipeline_table *t, const void *key, size_t size, VkPipeline pipe, prw_error *e);
/* Destroys the pipelines whose key matches. */
void prw_pipeline_table_remove(prw_pipeline_table *t, bool (*match)(const void *key, size_t size, void *user),
                               void *user);
uint32_t prw_pipeline_table_count(const prw_pipeline_table *t);

/* ---- commands ---- */
/* Begins a one-time primary command buffer from the gpu's pool. */
bool prw_cmd_begin(prw_gpu *gpu, VkCommandBuffer *out, prw_error *e);
/* Ends, submits, waits (with timeout) and frees it. */
bool prw_cmd_submit_wait(prw_gpu *gpu, VkCommandBuffer cmd, prw_error *e);
/* Waits for the queue to drain (timeout -> error). */
bool prw_gpu_wait_idle(prw_gpu *gpu, prw_error *e);

/* Sets a full-target viewport (y down, depth 0..1) and scissor. */
void prw_cmd_viewport(VkCommandBuffer cmd, uint32_t width, uint32_t height);

/* ---- timestamps ---- */
typedef struct prw_timer prw_timer;
bool prw_timer_create(prw_gpu *gpu, uint32_t max_scopes, prw_timer **out, prw_error *e);
void prw_timer_destroy(prw_gpu *gpu, prw_timer *t);
void prw_timer_reset(VkCommandBuffer cmd, prw_timer *t); /* record before any begin in that frame */
/* Returns the scope index; name is copied. */
uint32_t prw_timer_begin(VkCommandBuffer cmd, prw_timer *t, const char *name);
void prw_timer_end(VkCommandBuffer cmd, prw_timer *t, uint32_t scope);
/* After the submit has completed: scope count, names and milliseconds. */
bool prw_timer_read(prw_gpu *gpu, prw_timer *t, uint32_t *count, const char *const **names, const double **ms,
                    prw_error *e);

#ifdef __cplusplus
}
#endif
#endif
