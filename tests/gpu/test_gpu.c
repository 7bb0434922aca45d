/* test_gpu — device, validation, memory, compute, timestamps, pipeline cache, timeouts. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gpu_test_util.h"
#include "prw_shaders.h"

static void test_create_destroy(void)
{
    prw_error e;
    prw_gpu *gpu;
    CHECK_OK(test_gpu_open(&gpu, &e), &e);
    CHECK(strlen(prw_gpu_device_name(gpu)) > 0);
    CHECK(strlen(prw_gpu_driver_info(gpu)) > 0);
    printf("  device: %s, driver: %s\n", prw_gpu_device_name(gpu), prw_gpu_driver_info(gpu));
    CHECK(prw_gpu_properties(gpu)->apiVersion >= VK_API_VERSION_1_3);
    CHECK(prw_gpu_device(gpu) != VK_NULL_HANDLE && prw_gpu_queue(gpu) != VK_NULL_HANDLE);
    CHECK(prw_gpu_pipeline_cache(gpu) != VK_NULL_HANDLE);
    for (int k = 0; k < PRW_SAMPLER_COUNT; k++) CHECK(prw_gpu_sampler(gpu, (prw_sampler_kind)k) != VK_NULL_HANDLE);
    const prw_gpu_features *f = prw_gpu_features_enabled(gpu);
    printf("  multiview %d, fillModeNonSolid %d, independentBlend %d, float64 %d\n", f->multiview,
           f->fill_mode_non_solid, f->independent_blend, f->shader_float64);
    TEST_GPU_CLOSE(gpu);
}

static void test_list_devices(void)
{
    prw_error e;
    char buf[2048];
    CHECK_OK(prw_gpu_list_devices(buf, sizeof buf, &e), &e);
    printf("  %s\n", buf);
    CHECK(strncmp(buf, "0: ", 3) == 0);
}

static void test_device_select(void)
{
    prw_error e;
    prw_gpu *gpu = NULL;
    char list[2048];
    CHECK_OK(prw_gpu_list_devices(list, sizeof list, &e), &e);
    char first[64] = {0};
    sscanf(list, "0: %8[^ (]", first); /* a prefix of device 0's name */

    setenv("PRW_DEVICE", "no-such-device-xyz", 1);
    prw_gpu_desc d = {.device_index = -1, .validation = true};
    CHECK(!prw_gpu_create(&d, &gpu, &e));
    CHECK_MSG(strstr(e.msg, "no-such-device-xyz") && strstr(e.msg, "available") && strstr(e.msg, first), "%s",
              e.msg);
    setenv("PRW_DEVICE", "0", 1);
    CHECK_OK(prw_gpu_create(&d, &gpu, &e), &e);
    TEST_GPU_CLOSE(gpu);
    unsetenv("PRW_DEVICE");

    d.device_index = 99;
    CHECK(!prw_gpu_create(&d, &gpu, &e));
    CHECK_MSG(strstr(e.msg, "99") && strstr(e.msg, "available"), "%s", e.msg);
    d.device_index = -1;
    d.device_name = first;
    CHECK_OK(prw_gpu_create(&d, &gpu, &e), &e);
    CHECK(strstr(prw_gpu_device_name(gpu), first) != NULL);
    TEST_GPU_CLOSE(gpu);
}

/* Records one invalid command: a line width > 1 without the wideLines feature. */
static void invalid_call(prw_gpu *gpu)
{
    prw_error e;
    VkCommandBuffer cmd;
    CHECK_OK(prw_cmd_begin(gpu, &cmd, &e), &e);
    vkCmdSetLineWidth(cmd, 2.0f);
    CHECK_OK(prw_cmd_submit_wait(gpu, cmd, &e), &e);
}

static void test_validation_counts_errors(void)
{
    prw_error e;
    prw_gpu *gpu;
    CHECK_OK(test_gpu_open(&gpu, &e), &e);
    uint32_t total0 = prw_gpu_validation_total();
    printf("  (one deliberate validation error follows)\n");
    fflush(stdout);
    invalid_call(gpu);
    uint32_t n = prw_gpu_validation_count(gpu);
    CHECK_MSG(n > 0, "the messenger did not count a deliberate error");
    CHECK(prw_gpu_validation_total() == total0 + n);
    prw_gpu_destroy(gpu);
    CHECK_MSG(prw_gpu_validation_total() == total0 + n, "destroy after the error reported more");

    /* The same error, suppressed by id, is not counted. */
    char path[600];
    snprintf(path, sizeof path, "%s/suppress.txt", prw_test_tmpdir());
    const char *text = "# test\n\nVUID-vkCmdSetLineWidth-lineWidth-00788  deliberate error of this test\n";
    CHECK_OK(prw_write_file_atomic(path, text, strlen(text), &e), &e);
    prw_gpu_desc d = {.device_index = -1, .validation = true, .suppress_file = path};
    CHECK_OK(prw_gpu_create(&d, &gpu, &e), &e);
    invalid_call(gpu);
    TEST_GPU_CLOSE(gpu);

    /* Every suppression needs a reason. */
    const char *bad = "VUID-vkCmdSetLineWidth-lineWidth-00788\n";
    CHECK_OK(prw_write_file_atomic(path, bad, strlen(bad), &e), &e);
    CHECK(!prw_gpu_create(&d, &gpu, &e));
    CHECK_MSG(strstr(e.msg, "no reason"), "%s", e.msg);
    d.suppress_file = "/nonexistent/suppress.txt";
    CHECK(!prw_gpu_create(&d, &gpu, &e));
    CHECK_MSG(strstr(e.msg, "suppress"), "%s", e.msg);
}

static void test_validation_reports_leaks(void)
{
    prw_error e;
    prw_gpu *gpu;
    CHECK_OK(test_gpu_open(&gpu, &e), &e);
    VkSamplerCreateInfo ci = {.sType = VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO, .maxAnisotropy = 1.0f};
    VkSampler leaked;
    CHECK(vkCreateSampler(prw_gpu_device(gpu), &ci, NULL, &leaked) == VK_SUCCESS);
    uint32_t total0 = prw_gpu_validation_total();
    printf("  (one deliberate leak report follows)\n");
    fflush(stdout);
    prw_gpu_destroy(gpu);
    CHECK_MSG(prw_gpu_validation_total() > total0, "a leaked VkSampler was not reported at destroy");
}

/* With the layer search path pointing nowhere, asking for validation must fail clearly. */
static void test_validation_layer_missing(void)
{
    prw_error e;
    prw_gpu *gpu = NULL;
    const char *old = getenv("VK_LAYER_PATH");
    char *saved = old ? prw_strdup(old) : NULL;
    setenv("VK_LAYER_PATH", "/nonexistent-prw-layers", 1);
    prw_gpu_desc d = {.device_index = -1, .validation = true};
    bool ok = prw_gpu_create(&d, &gpu, &e);
    if (saved) setenv("VK_LAYER_PATH", saved, 1);
    else unsetenv("VK_LAYER_PATH");
    free(saved);
    CHECK(!ok);
    if (ok) prw_gpu_destroy(gpu);
    else CHECK_MSG(strstr(e.msg, "VK_LAYER_KHRONOS_validation") && strstr(e.msg, "not installed"), "%s", e.msg);
}

static void test_vk_check(void)
{
    prw_error e;
    CHECK(prw_vk_check(VK_SUCCESS, "x", &e));
    CHECK(!prw_vk_check(VK_ERROR_DEVICE_LOST, "gpu: vkFoo", &e));
    CHECK_MSG(strstr(e.msg, "gpu: vkFoo") && strstr(e.msg, "VK_ERROR_DEVICE_LOST") && strstr(e.msg, "device lost"),
              "%s", e.msg);
    CHECK(!prw_vk_check(VK_ERROR_OUT_OF_DEVICE_MEMORY, "y", &e));
    CHECK_MSG(strstr(e.msg, "out of device memory"), "%s", e.msg);
}

static void test_suballocator(void)
{
    prw_error e;
    prw_gpu *gpu;
    CHECK_OK(test_gpu_open(&gpu, &e), &e);
    enum { N = 300 };
    static prw_buffer bufs[N];
    prw_mem_stats s0, s;
    prw_gpu_mem_stats(gpu, &s0);
    uint64_t sum = 0;
    VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT;
    VkDeviceSize align = prw_gpu_properties(gpu)->limits.minStorageBufferOffsetAlignment;
    for (int i = 0; i < N; i++) {
        VkDeviceSize size = 1 + (VkDeviceSize)(i * 7919 % 20011);
        CHECK_OK(prw_buffer_create(gpu, size, usage, i % 3 == 0 ? PRW_MEM_GPU : PRW_MEM_UPLOAD, &bufs[i], &e), &e);
        VkMemoryRequirements req;
        vkGetBufferMemoryRequirements(prw_gpu_device(gpu), bufs[i].buffer, &req);
        CHECK(bufs[i].alloc.offset % req.alignment == 0);
        CHECK(bufs[i].alloc.offset % align == 0);
        CHECK(bufs[i].alloc.size >= size);
        CHECK((bufs[i].mapped != NULL) == (i % 3 != 0));
        sum += bufs[i].alloc.size;
        if (bufs[i].mapped) memset(bufs[i].mapped, i & 0xff, size);
    }
    /* Pairwise non-overlap within the same VkDeviceMemory. */
    int overlaps = 0;
    for (int i = 0; i < N; i++)
        for (int j = i + 1; j < N; j++) {
            const prw_alloc *a = &bufs[i].alloc, *b = &bufs[j].alloc;
            if (a->memory == b->memory && a->offset < b->offset + b->size && b->offset < a->offset + a->size)
                overlaps++;
        }
    CHECK(overlaps == 0);
    /* Patterns written through the mappings survived every neighbour's writes. */
    for (int i = 0; i < N; i++) {
        if (!bufs[i].mapped) continue;
        const unsigned char *p = bufs[i].mapped;
        for (VkDeviceSize k = 0; k < bufs[i].size; k++)
            if (p[k] != (i & 0xff)) {
                CHECK_MSG(false, "buffer %d byte %llu clobbered", i, (unsigned long long)k);
                break;
            }
    }
    prw_gpu_mem_stats(gpu, &s);
    CHECK(s.used_bytes == s0.used_bytes + sum);
    CHECK(s.alloc_count == s0.alloc_count + N);
    CHECK(s.peak_bytes >= s.used_bytes);
    CHECK(s.reserved_bytes >= s.used_bytes);
    CHECK(s.block_count >= 1);
    uint64_t peak = s.peak_bytes;
    uint32_t blocks = s.block_count;

    /* Free every other one, then refill the holes: no new block may be needed. */
    for (int i = 0; i < N; i += 2) prw_buffer_destroy(gpu, &bufs[i]);
    prw_gpu_mem_stats(gpu, &s);
    CHECK(s.used_bytes < sum + s0.used_bytes);
    CHECK(s.peak_bytes == peak);
    for (int i = 0; i < N; i += 2) {
        VkDeviceSize size = 1 + (VkDeviceSize)(i * 7919 % 20011);
        CHECK_OK(prw_buffer_create(gpu, size, usage, i % 3 == 0 ? PRW_MEM_GPU : PRW_MEM_UPLOAD, &bufs[i], &e), &e);
    }
    prw_gpu_mem_stats(gpu, &s);
    CHECK(s.block_count == blocks);

    /* A buffer larger than a block gets its own (dedicated) block. */
    prw_buffer big;
    CHECK_OK(prw_buffer_create(gpu, (VkDeviceSize)100 << 20, usage, PRW_MEM_GPU, &big, &e), &e);
    prw_gpu_mem_stats(gpu, &s);
    CHECK(s.block_count == blocks + 1);
    CHECK(s.peak_bytes >= ((uint64_t)100 << 20));
    prw_buffer_destroy(gpu, &big);
    prw_gpu_mem_stats(gpu, &s);
    CHECK(s.block_count == blocks);

    for (int i = 0; i < N; i++) prw_buffer_destroy(gpu, &bufs[i]);
    prw_gpu_mem_stats(gpu, &s);
    CHECK(s.used_bytes == s0.used_bytes);
    CHECK(s.alloc_count == s0.alloc_count);

    /* Out of memory: more than the heap holds is a clear error, not a driver crash. */
    VkPhysicalDeviceMemoryProperties mp;
    vkGetPhysicalDeviceMemoryProperties(prw_gpu_physical(gpu), &mp);
    VkMemoryRequirements req = {.size = mp.memoryHeaps[0].size * 2, .alignment = 256, .memoryTypeBits = ~0u};
    prw_alloc a;
    CHECK(!prw_mem_alloc(gpu, &req, PRW_MEM_GPU, true, &a, &e));
    CHECK_MSG(strstr(e.msg, "out of device memory"), "%s", e.msg);
    TEST_GPU_CLOSE(gpu);
}

/* Random alloc/free on the raw allocator: live ranges never overlap, offsets are aligned, and
 * freeing everything merges the free lists back so the empty blocks are released. */
static void test_suballocator_random(void)
{
    prw_error e;
    prw_gpu *gpu;
    CHECK_OK(test_gpu_open(&gpu, &e), &e);
    enum { SLOTS = 256, OPS = 4000 };
    static prw_alloc live[SLOTS];
    memset(live, 0, sizeof live);
    uint32_t rng = 12345;
    int bad_align = 0, overlaps = 0;
    for (int op = 0; op < OPS; op++) {
        rng = rng * 1664525u + 1013904223u;
        int i = (int)((rng >> 8) % SLOTS);
        if (live[i].memory) {
            prw_mem_free(gpu, &live[i]);
            continue;
        }
        rng = rng * 1664525u + 1013904223u;
        VkMemoryRequirements req = {.size = 1 + (rng >> 8) % 1500000, .alignment = (VkDeviceSize)1 << ((rng >> 4) % 12),
                                    .memoryTypeBits = ~0u};
        bool linear = (rng >> 20) & 1;
        CHECK_OK(prw_mem_alloc(gpu, &req, PRW_MEM_UPLOAD, linear, &live[i], &e), &e);
        bad_align += live[i].offset % req.alignment != 0;
        for (int j = 0; j < SLOTS; j++) {
            const prw_alloc *a = &live[i], *b = &live[j];
            if (j != i && b->memory == a->memory && a->offset < b->offset + b->size && b->offset < a->offset + a->size)
                overlaps++;
        }
    }
    CHECK(bad_align == 0);
    CHECK(overlaps == 0);
    prw_mem_stats s;
    prw_gpu_mem_stats(gpu, &s);
    printf("  peak %.1f MiB, %u blocks at the end\n", s.peak_bytes / 1048576.0, s.block_count);
    CHECK(s.block_count >= 3); /* the sizes force several blocks per tiling */
    for (int i = 0; i < SLOTS; i++) prw_mem_free(gpu, &live[i]);
    prw_gpu_mem_stats(gpu, &s);
    CHECK(s.used_bytes == 0 && s.alloc_count == 0);
    CHECK_MSG(s.block_count <= 2, "%u blocks left after freeing everything", s.block_count); /* one per tiling */
    CHECK(s.peak_bytes > 0);
    TEST_GPU_CLOSE(gpu);
}

/* fill.comp through pipe with set bound (layout pl): out[i] = i * i + add for i < n, copied into rb. */
static bool fill_dispatch(prw_gpu *gpu, VkPipeline pipe, VkPipelineLayout pl, VkDescriptorSet set, const prw_buffer *out,
                          const prw_buffer *rb, uint32_t n, uint32_t add, prw_error *e)
{
    VkCommandBuffer cmd;
    if (!prw_cmd_begin(gpu, &cmd, e)) return false;
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipe);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pl, 0, 1, &set, 0, NULL);
    uint32_t push[2] = {n, add};
    vkCmdPushConstants(cmd, pl, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof push, push);
    vkCmdDispatch(cmd, (n + 63) / 64, 1, 1);
    VkMemoryBarrier2 mb[2] = {
        {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER_2,
         .srcStageMask = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
         .srcAccessMask = VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
         .dstStageMask = VK_PIPELINE_STAGE_2_COPY_BIT,
         .dstAccessMask = VK_ACCESS_2_TRANSFER_READ_BIT},
        {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER_2,
         .srcStageMask = VK_PIPELINE_STAGE_2_COPY_BIT,
         .srcAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT,
         .dstStageMask = VK_PIPELINE_STAGE_2_HOST_BIT,
         .dstAccessMask = VK_ACCESS_2_HOST_READ_BIT},
    };
    VkDependencyInfo dep = {.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO, .memoryBarrierCount = 1,
                            .pMemoryBarriers = &mb[0]};
    vkCmdPipelineBarrier2(cmd, &dep);
    VkBufferCopy region = {0, 0, (VkDeviceSize)n * 4};
    vkCmdCopyBuffer(cmd, out->buffer, rb->buffer, 1, &region);
    dep.pMemoryBarriers = &mb[1];
    vkCmdPipelineBarrier2(cmd, &dep);
    return prw_cmd_submit_wait(gpu, cmd, e);
}

/* Dispatches fill.comp over a GPU buffer, copies it to a readback buffer, checks every value. */
static void test_compute_buffer(void)
{
    prw_error e;
    prw_gpu *gpu;
    CHECK_OK(test_gpu_open(&gpu, &e), &e);
    VkDevice dev = prw_gpu_device(gpu);
    const uint32_t n = 1000;
    prw_buffer out, rb;
    CHECK_OK(prw_buffer_create(gpu, n * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, PRW_MEM_GPU, &out, &e), &e);
    CHECK_OK(prw_buffer_create(gpu, n * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT, PRW_MEM_READBACK, &rb, &e), &e);
    VkDescriptorSetLayoutBinding b = {0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, NULL};
    VkDescriptorSetLayout dsl;
    VkPipelineLayout pl;
    VkPipeline pipe;
    prw_desc_pool *pool;
    VkDescriptorSet set;
    CHECK_OK(prw_desc_layout_create(gpu, &b, 1, &dsl, &e), &e);
    CHECK_OK(prw_pipeline_layout_create_stages(gpu, &dsl, 1, 8, VK_SHADER_STAGE_COMPUTE_BIT, &pl, &e), &e);
    CHECK_OK(prw_pipeline_compute(gpu, prw_shader_fill_comp(), pl, &pipe, &e), &e);
    CHECK_OK(prw_desc_pool_create(gpu, &pool, &e), &e);
    CHECK_OK(prw_desc_alloc(gpu, pool, dsl, &set, &e), &e);
    prw_desc_write_buffer(gpu, set, 0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &out, 0, 0);
    CHECK_OK(fill_dispatch(gpu, pipe, pl, set, &out, &rb, n, 7, &e), &e);
    /* the upload check below: a copy out -> rb, then the host reads */
    VkMemoryBarrier2 to_host = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER_2,
                                .srcStageMask = VK_PIPELINE_STAGE_2_COPY_BIT,
                                .srcAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT,
                                .dstStageMask = VK_PIPELINE_STAGE_2_HOST_BIT,
                                .dstAccessMask = VK_ACCESS_2_HOST_READ_BIT};
    VkDependencyInfo dep = {.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO, .memoryBarrierCount = 1,
                            .pMemoryBarriers = &to_host};
    VkBufferCopy region = {0, 0, n * 4};
    VkCommandBuffer cmd;
    const uint32_t *v = rb.mapped;
    int bad = 0;
    for (uint32_t i = 0; i < n; i++) bad += v[i] != i * i + 7;
    CHECK_MSG(bad == 0, "%d wrong values (v[5] = %u)", bad, v[5]);

    /* prw_buffer_upload into GPU memory goes through staging; read it back the same way. */
    uint32_t data[4] = {11, 22, 33, 44};
    CHECK_OK(prw_buffer_upload(gpu, &out, 8, data, sizeof data, &e), &e);
    CHECK_OK(prw_cmd_begin(gpu, &cmd, &e), &e);
    vkCmdCopyBuffer(cmd, out.buffer, rb.buffer, 1, &region);
    vkCmdPipelineBarrier2(cmd, &dep);
    CHECK_OK(prw_cmd_submit_wait(gpu, cmd, &e), &e);
    CHECK(v[1] == 1 + 7 && v[2] == 11 && v[5] == 44 && v[6] == 36 + 7);
    CHECK(!prw_buffer_upload(gpu, &out, n * 4 - 4, data, sizeof data, &e));

    prw_desc_pool_destroy(gpu, pool);
    prw_pipeline_release(gpu, pipe);
    vkDestroyPipelineLayout(dev, pl, NULL);
    vkDestroyDescriptorSetLayout(dev, dsl, NULL);
    prw_buffer_destroy(gpu, &out);
    prw_buffer_destroy(gpu, &rb);
    TEST_GPU_CLOSE(gpu);
}

/* Many sets from one growing pool: more than one VkDescriptorPool holds, then reset and reuse. */
static void test_desc_pool_growth(void)
{
    prw_error e;
    prw_gpu *gpu;
    CHECK_OK(test_gpu_open(&gpu, &e), &e);
    VkDescriptorSetLayoutBinding b[2] = {
        {0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 8, VK_SHADER_STAGE_FRAGMENT_BIT, NULL},
        {1, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, VK_SHADER_STAGE_ALL, NULL},
    };
    VkDescriptorSetLayoutBinding huge = {0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1000, VK_SHADER_STAGE_COMPUTE_BIT,
                                         NULL};
    VkDescriptorSetLayout dsl, dsl_huge;
    prw_desc_pool *pool;
    CHECK_OK(prw_desc_layout_create(gpu, b, 2, &dsl, &e), &e);
    CHECK_OK(prw_desc_layout_create(gpu, &huge, 1, &dsl_huge, &e), &e);
    CHECK_OK(prw_desc_pool_create(gpu, &pool, &e), &e);
    for (int round = 0; round < 2; round++) {
        for (int i = 0; i < 700; i++) {
            VkDescriptorSet s;
            CHECK_OK(prw_desc_alloc(gpu, pool, dsl, &s, &e), &e);
        }
        VkDescriptorSet s;
        CHECK_OK(prw_desc_alloc(gpu, pool, dsl_huge, &s, &e), &e);
        prw_desc_pool_reset(gpu, pool);
    }
    prw_desc_pool_destroy(gpu, pool);
    vkDestroyDescriptorSetLayout(prw_gpu_device(gpu), dsl, NULL);
    vkDestroyDescriptorSetLayout(prw_gpu_device(gpu), dsl_huge, NULL);
    TEST_GPU_CLOSE(gpu);
}

static void test_timestamps(void)
{
    prw_error e;
    prw_gpu *gpu;
    CHECK_OK(test_gpu_open(&gpu, &e), &e);
    prw_timer *t;
    CHECK_OK(prw_timer_create(gpu, 4, &t, &e), &e);
    prw_buffer buf;
    CHECK_OK(prw_buffer_create(gpu, 16 << 20, 0, PRW_MEM_GPU, &buf, &e), &e);
    for (int frame = 0; frame < 2; frame++) {
        VkCommandBuffer cmd;
        CHECK_OK(prw_cmd_begin(gpu, &cmd, &e), &e);
        prw_timer_reset(cmd, t);
        uint32_t a = prw_timer_begin(cmd, t, "fill");
        vkCmdFillBuffer(cmd, buf.buffer, 0, VK_WHOLE_SIZE, 0x3f800000u);
        prw_timer_end(cmd, t, a);
        uint32_t b = prw_timer_begin(cmd, t, "empty");
        prw_timer_end(cmd, t, b);
        CHECK_OK(prw_cmd_submit_wait(gpu, cmd, &e), &e);
        uint32_t count;
        const char *const *names;
        const double *ms;
        CHECK_OK(prw_timer_read(gpu, t, &count, &names, &ms, &e), &e);
        CHECK(count == 2);
        CHECK(strcmp(names[0], "fill") == 0 && strcmp(names[1], "empty") == 0);
        for (uint32_t i = 0; i < count; i++) CHECK_MSG(isfinite(ms[i]) && ms[i] >= 0 && ms[i] < 60e3, "%g", ms[i]);
        printf("  frame %d: fill 16 MiB %.3f ms, empty %.3f ms\n", frame, ms[0], ms[1]);
    }
    prw_buffer_destroy(gpu, &buf);
    prw_timer_destroy(gpu, t);
    TEST_GPU_CLOSE(gpu);
}

/* A saved cache starts with the VkPipelineCacheHeaderVersionOne of this device (lavapipe stores
 * nothing else: its caches are exactly the 32-byte header). */
static bool cache_file_valid(const char *path, const VkPhysicalDeviceProperties *p)
{
    char *data;
    size_t size;
    prw_error e;
    if (!prw_read_file(path, &data, &size, &e)) return false;
    uint32_t h[4] = {0};
    if (size >= 32) memcpy(h, data, sizeof h);
    bool ok = size >= 32 && h[0] >= 32 && h[1] == VK_PIPELINE_CACHE_HEADER_VERSION_ONE && h[2] == p->vendorID &&
              h[3] == p->deviceID && memcmp(data + 16, p->pipelineCacheUUID, VK_UUID_SIZE) == 0;
    free(data);
    return ok;
}

static void test_pipeline_cache(void)
{
    prw_error e;
    char dir[600], file[900];
    snprintf(dir, sizeof dir, "%s/cache/nested", prw_test_tmpdir());
    prw_gpu_desc d = {.device_index = -1, .validation = true, .cache_dir = dir};
    for (int run = 0; run < 3; run++) {
        prw_gpu *gpu;
        CHECK_OK(prw_gpu_create(&d, &gpu, &e), &e);
        VkPhysicalDeviceProperties props = *prw_gpu_properties(gpu), *p = &props;
        snprintf(file, sizeof file, "%s/pipeline-%04x-%04x-%08x.bin", dir, p->vendorID, p->deviceID,
                 p->driverVersion);
        VkDescriptorSetLayoutBinding b = {0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, NULL};
        VkDescriptorSetLayout dsl;
        VkPipelineLayout pl;
        VkPipeline pipe;
        CHECK_OK(prw_desc_layout_create(gpu, &b, 1, &dsl, &e), &e);
        CHECK_OK(prw_pipeline_layout_create(gpu, &dsl, 1, 8, &pl, &e), &e);
        double t0 = prw_now();
        CHECK_OK(prw_pipeline_compute(gpu, prw_shader_fill_comp(), pl, &pipe, &e), &e);
        printf("  run %d: pipeline in %.1f ms\n", run, (prw_now() - t0) * 1e3);
        prw_pipeline_release(gpu, pipe);
        vkDestroyPipelineLayout(prw_gpu_device(gpu), pl, NULL);
        vkDestroyDescriptorSetLayout(prw_gpu_device(gpu), dsl, NULL);
        TEST_GPU_CLOSE(gpu);
        CHECK_MSG(cache_file_valid(file, p), "%s not written", file);
        if (run == 1) { /* a damaged file is ignored (warning), not an error */
            const char junk[64] = "this is not a pipeline cache";
            CHECK_OK(prw_write_file_atomic(file, junk, sizeof junk, &e), &e);
        }
    }
}

/* fill.comp through pipe (made with any layout equal to pl's): v[i] = i * i + add for i < n. */
static int fill_wrong(prw_gpu *gpu, VkPipeline pipe, VkPipelineLayout pl, VkDescriptorSetLayout dsl, uint32_t n,
                      uint32_t add, prw_error *e)
{
    prw_buffer out = {0}, rb = {0};
    prw_desc_pool *pool = NULL;
    VkDescriptorSet set;
    int bad = -1;
    if (!prw_buffer_create(gpu, n * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                           PRW_MEM_GPU, &out, e) ||
        !prw_buffer_create(gpu, n * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT, PRW_MEM_READBACK, &rb, e) ||
        !prw_desc_pool_create(gpu, &pool, e) || !prw_desc_alloc(gpu, pool, dsl, &set, e))
        goto done;
    prw_desc_write_buffer(gpu, set, 0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &out, 0, 0);
    if (!fill_dispatch(gpu, pipe, pl, set, &out, &rb, n, add, e)) goto done;
    const uint32_t *v = rb.mapped;
    bad = 0;
    for (uint32_t i = 0; i < n; i++) bad += v[i] != i * i + add;
done:
    if (pool) prw_desc_pool_destroy(gpu, pool);
    prw_buffer_destroy(gpu, &out);
    prw_buffer_destroy(gpu, &rb);
    return bad;
}

/* Shared pipelines (prw_gpu.h): a pipeline requested again with an equal description and a layout of
 * equal content made separately is the same pipeline, and it still computes right after the layout it
 * was made with is destroyed; a layout of other content (push range) gets its own pipeline; with
 * PRW_PIPELINE_MEMO=0 every request compiles. */
static void test_pipeline_memo(void)
{
    prw_error e;
    prw_gpu *gpu;
    CHECK_OK(test_gpu_open(&gpu, &e), &e);
    VkDevice dev = prw_gpu_device(gpu);
    VkDescriptorSetLayoutBinding b = {0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, NULL};
    VkDescriptorSetLayout dsl1, dsl2, dsl3;
    VkPipelineLayout pl1, pl2, pl3;
    VkPipeline a, c, d;
    CHECK_OK(prw_desc_layout_create(gpu, &b, 1, &dsl1, &e), &e);
    CHECK_OK(prw_pipeline_layout_create_stages(gpu, &dsl1, 1, 8, VK_SHADER_STAGE_COMPUTE_BIT, &pl1, &e), &e);
    CHECK_OK(prw_pipeline_compute(gpu, prw_shader_fill_comp(), pl1, &a, &e), &e);
    uint32_t n0;
    uint64_t h0;
    prw_pipeline_memo_stats(gpu, &n0, &h0);
    /* "another renderer": its own layouts of equal content */
    CHECK_OK(prw_desc_layout_create(gpu, &b, 1, &dsl2, &e), &e);
    CHECK_OK(prw_pipeline_layout_create_stages(gpu, &dsl2, 1, 8, VK_SHADER_STAGE_COMPUTE_BIT, &pl2, &e), &e);
    CHECK(pl2 != pl1 && dsl2 != dsl1);
    prw_pipeline_release(gpu, a);
    vkDestroyPipelineLayout(dev, pl1, NULL);
    vkDestroyDescriptorSetLayout(dev, dsl1, NULL);
    VkPipeline a2;
    CHECK_OK(prw_pipeline_compute(gpu, prw_shader_fill_comp(), pl2, &a2, &e), &e);
    uint32_t n1;
    uint64_t h1;
    prw_pipeline_memo_stats(gpu, &n1, &h1);
    CHECK_MSG(a2 == a && n1 == n0 && h1 == h0 + 1, "not shared: same handle %d, pipelines %u -> %u, hits %llu -> %llu",
              a2 == a, n0, n1, (unsigned long long)h0, (unsigned long long)h1);
    int bad = fill_wrong(gpu, a2, pl2, dsl2, 1000, 5, &e);
    CHECK_MSG(bad == 0, "shared pipeline, its first layout destroyed: %d wrong values (%s)", bad, bad < 0 ? e.msg : "");
    /* other content: a 16-byte push range */
    CHECK_OK(prw_desc_layout_create(gpu, &b, 1, &dsl3, &e), &e);
    CHECK_OK(prw_pipeline_layout_create_stages(gpu, &dsl3, 1, 16, VK_SHADER_STAGE_COMPUTE_BIT, &pl3, &e), &e);
    CHECK_OK(prw_pipeline_compute(gpu, prw_shader_fill_comp(), pl3, &c, &e), &e);
    CHECK(c != a2);
    CHECK(fill_wrong(gpu, c, pl3, dsl3, 100, 9, &e) == 0);
    prw_pipeline_release(gpu, c);
    prw_pipeline_release(gpu, a2);
    vkDestroyPipelineLayout(dev, pl3, NULL);
    vkDestroyDescriptorSetLayout(dev, dsl3, NULL);
    vkDestroyPipelineLayout(dev, pl2, NULL);
    vkDestroyDescriptorSetLayout(dev, dsl2, NULL);
    TEST_GPU_CLOSE(gpu);

    /* off: each request compiles its own pipeline */
    setenv("PRW_PIPELINE_MEMO", "0", 1);
    CHECK_OK(test_gpu_open(&gpu, &e), &e);
    CHECK_OK(prw_desc_layout_create(gpu, &b, 1, &dsl1, &e), &e);
    CHECK_OK(prw_pipeline_layout_create_stages(gpu, &dsl1, 1, 8, VK_SHADER_STAGE_COMPUTE_BIT, &pl1, &e), &e);
    CHECK_OK(prw_pipeline_compute(gpu, prw_shader_fill_comp(), pl1, &a, &e), &e);
    CHECK_OK(prw_pipeline_compute(gpu, prw_shader_fill_comp(), pl1, &d, &e), &e);
    CHECK(a != d);
    prw_pipeline_release(gpu, a);
    prw_pipeline_release(gpu, d);
    vkDestroyPipelineLayout(prw_gpu_device(gpu), pl1, NULL);
    vkDestroyDescriptorSetLayout(prw_gpu_device(gpu), dsl1, NULL);
    TEST_GPU_CLOSE(gpu);
    unsetenv("PRW_PIPELINE_MEMO");
}

/* A submit that waits on an event nobody sets must time out with a clear error; setting the event
 * afterwards lets the work finish and everything is released cleanly. */
static void test_gpu_timeout(void)
{
    prw_error e;
    prw_gpu *gpu;
    setenv("PRW_GPU_TIMEOUT_S", "0.3", 1);
    bool ok = test_gpu_open(&gpu, &e);
    unsetenv("PRW_GPU_TIMEOUT_S");
    CHECK_OK(ok, &e);
    VkDevice dev = prw_gpu_device(gpu);
    VkEventCreateInfo eci = {.sType = VK_STRUCTURE_TYPE_EVENT_CREATE_INFO};
    VkEvent ev;
    CHECK(vkCreateEvent(dev, &eci, NULL, &ev) == VK_SUCCESS);
    VkCommandBuffer cmd;
    CHECK_OK(prw_cmd_begin(gpu, &cmd, &e), &e);
    VkMemoryBarrier2 mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER_2,
                           .srcStageMask = VK_PIPELINE_STAGE_2_HOST_BIT,
                           .srcAccessMask = VK_ACCESS_2_HOST_WRITE_BIT,
                           .dstStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                           .dstAccessMask = VK_ACCESS_2_MEMORY_READ_BIT};
    VkDependencyInfo dep = {.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO, .memoryBarrierCount = 1,
                            .pMemoryBarriers = &mb};
    vkCmdWaitEvents2(cmd, 1, &ev, &dep);
    double t0 = prw_now();
    CHECK(!prw_cmd_submit_wait(gpu, cmd, &e));
    double dt = prw_now() - t0;
    CHECK_MSG(strstr(e.msg, "GPU timeout"), "%s", e.msg);
    CHECK_MSG(dt > 0.25 && dt < 5.0, "waited %.2f s", dt);
    printf("  %s (after %.2f s)\n", e.msg, dt);
    CHECK(vkSetEvent(dev, ev) == VK_SUCCESS);
    CHECK_OK(prw_gpu_wait_idle(gpu, &e), &e);
    vkDestroyEvent(dev, ev, NULL);
    TEST_GPU_CLOSE(gpu);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"create_destroy", test_create_destroy},
        {"list_devices", test_list_devices},
        {"device_select", test_device_select},
        {"validation_counts_errors", test_validation_counts_errors},
        {"validation_reports_leaks", test_validation_reports_leaks},
        {"validation_layer_missing", test_validation_layer_missing},
        {"vk_check", test_vk_check},
        {"suballocator", test_suballocator},
        {"suballocator_random", test_suballocator_random},
        {"compute_buffer", test_compute_buffer},
        {"pipeline_memo", test_pipeline_memo},
        {"desc_pool_growth", test_desc_pool_growth},
        {"timestamps", test_timestamps},
        {"pipeline_cache", test_pipeline_cache},
        {"gpu_timeout", test_gpu_timeout},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
