/* The shared material header (materials/prw_brdf.h) evaluated by a compute shader equals the C
 * evaluation on 10^4 random configurations (relative difference <= 1e-5; values below 1e-6 /sr
 * compared absolutely at 1e-11). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_brdf.h"
#include "prw_shaders.h"
#include "prw_test.h"

typedef struct brdf_case {
    float NoV, NoL, NoH, VoH, base, metallic, roughness, specular;
} brdf_case;

static uint64_t rng_state = 0x9E3779B97F4A7C15ull;
static float rnd(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (float)((rng_state >> 40) * (1.0 / 16777216.0));
}

/* A geometrically consistent configuration: random unit n, v, l on the upper hemisphere. */
static brdf_case random_case(void)
{
    float th_v = acosf(rnd()), th_l = acosf(rnd()), ph = 6.2831853f * rnd();
    float v[3] = {sinf(th_v), 0, cosf(th_v)};
    float l[3] = {sinf(th_l) * cosf(ph), sinf(th_l) * sinf(ph), cosf(th_l)};
    float h[3] = {v[0] + l[0], v[1] + l[1], v[2] + l[2]};
    float hl = sqrtf(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
    for (int i = 0; i < 3; i++) h[i] /= hl > 0 ? hl : 1;
    brdf_case c = {v[2], l[2], h[2], v[0] * h[0] + v[1] * h[1] + v[2] * h[2], rnd(), rnd() < 0.3f ? 1.0f : rnd(),
                   rnd(), rnd() < 0.2f ? 0.0f : rnd()};
    return c;
}

static void test_gpu_equals_cpu(void)
{
    enum { N = 10000 };
    prw_error e;
    prw_gpu *gpu = NULL;
    prw_gpu_desc d = {.device_index = -1, .validation = true};
    CHECK_OK(prw_gpu_create(&d, &gpu, &e), &e);
    prw_buffer in = {0}, out = {0};
    VkDescriptorSetLayout dsl = VK_NULL_HANDLE;
    VkPipelineLayout pl = VK_NULL_HANDLE;
    VkPipeline pipe = VK_NULL_HANDLE;
    prw_desc_pool *pool = NULL;
    brdf_case *cases = prw_malloc(N * sizeof *cases);
    for (int i = 0; i < N; i++) cases[i] = random_case();
    VkDescriptorSetLayoutBinding b[2] = {
        {0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, NULL},
        {1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, NULL},
    };
    VkDescriptorSet set;
    VkCommandBuffer cmd;
    bool ok = prw_buffer_create(gpu, N * sizeof *cases, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, PRW_MEM_UPLOAD, &in, &e) &&
              prw_buffer_create(gpu, N * sizeof(float), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, PRW_MEM_READBACK, &out,
                                &e) &&
              prw_desc_layout_create(gpu, b, 2, &dsl, &e) && prw_pipeline_layout_create(gpu, &dsl, 1, 4, &pl, &e) &&
              prw_pipeline_compute(gpu, prw_shader_brdf_test_comp(), pl, &pipe, &e) &&
              prw_desc_pool_create(gpu, &pool, &e) && prw_desc_alloc(gpu, pool, dsl, &set, &e);
    if (ok) {
        memcpy(in.mapped, cases, N * sizeof *cases);
        prw_desc_write_buffer(gpu, set, 0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &in, 0, VK_WHOLE_SIZE);
        prw_desc_write_buffer(gpu, set, 1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &out, 0, VK_WHOLE_SIZE);
        ok = prw_cmd_begin(gpu, &cmd, &e);
    }
    if (ok) {
        uint32_t count = N;
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipe);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pl, 0, 1, &set, 0, NULL);
        vkCmdPushConstants(cmd, pl, VK_SHADER_STAGE_ALL, 0, 4, &count);
        vkCmdDispatch(cmd, (N + 63) / 64, 1, 1);
        VkMemoryBarrier2 mb = {VK_STRUCTURE_TYPE_MEMORY_BARRIER_2, NULL, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                               VK_ACCESS_2_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT};
        VkDependencyInfo di = {.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO, .memoryBarrierCount = 1,
                               .pMemoryBarriers = &mb};
        vkCmdPipelineBarrier2(cmd, &di);
        ok = prw_cmd_submit_wait(gpu, cmd, &e);
    }
    CHECK_MSG(ok, "%s", e.msg);
    if (ok) {
        const float *gpu_v = out.mapped;
        double worst = 0;
        int bad = 0, worst_i = 0;
        for (int i = 0; i < N; i++) {
            const brdf_case *c = &cases[i];
            float cpu = prw_brdf_channel(c->NoV, c->NoL, c->NoH, c->VoH, c->base, c->metallic, c->roughness, c->specular);
            double diff = fabs((double)cpu - (double)gpu_v[i]);
            double rel = fabs(cpu) > 1e-6 ? diff / fabs(cpu) : diff * 1e-5 / 1e-11;
            if (!isfinite(gpu_v[i]) || !(rel <= 1e-5)) bad++;
            if (rel > worst) worst = rel, worst_i = i;
        }
        printf("brdf gpu vs cpu: %d cases, worst relative %.3g (case %d), %d beyond 1e-5\n", N, worst, worst_i, bad);
        CHECK(bad == 0);
    }
    free(cases);
    if (pool) prw_desc_pool_destroy(gpu, pool);
    if (pipe) vkDestroyPipeline(prw_gpu_device(gpu), pipe, NULL);
    if (pl) vkDestroyPipelineLayout(prw_gpu_device(gpu), pl, NULL);
    if (dsl) vkDestroyDescriptorSetLayout(prw_gpu_device(gpu), dsl, NULL);
    prw_buffer_destroy(gpu, &in);
    prw_buffer_destroy(gpu, &out);
    prw_gpu_destroy(gpu);
    CHECK(prw_gpu_validation_total() == 0); /* includes leak reports made at destroy */
}

static const prw_test_case cases_[] = {{"brdf_gpu_equals_cpu", test_gpu_equals_cpu}};

int main(int argc, char **argv)
{
    prw_threads_set(2);
    return prw_test_main(argc, argv, cases_, 1);
}
