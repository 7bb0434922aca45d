/* The rect lights' single-scattering specular by linearly transformed cosines (shaders/ltc.glsl) evaluated
 * by a compute shader equals its C twin (materials/prw_ltc.c) on 10^4 random configurations (a rect light
 * in front of a receiver, random normal and view, random material):
 *  - the table lookup (ltc_lookup: the sampler's bilinear filter) to 1e-5 (|c| + the texel's largest channel);
 *  - rect_specular_ltc per RGB channel to |gpu - cpu| <= 1e-4 (|cpu| + s), s = the result with every
 *    polygon edge's term taken absolutely (prw_ltc_rect_ggx_scale times the Fresnel factor): float
 *    rounding of the GPU's atan / sqrt is relative to the terms, which cancel for a light far off the lobe.
 * The table is uploaded as the renderer does (a 2-layer RGBA32F array image, linear filtering, clamp to edge). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_ltc.h"
#include "prw_test_shaders.h"
#include "prw_test.h"

enum { FLOATS = 24, OUTS = 11 };

static uint64_t rng_state = 0x2545F4914F6CDD1Dull;
static float rnd(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (float)((rng_state >> 40) * (1.0 / 16777216.0));
}

static void rnd_dir(float d[3])
{
    for (;;) {
        for (int i = 0; i < 3; i++) d[i] = 2 * rnd() - 1;
        float l = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        if (l > 1e-4f && l < 1) {
            for (int i = 0; i < 3; i++) d[i] /= sqrtf(l);
            return;
        }
    }
}

/* p, n, v, c, du, dv, base, metallic, roughness, specular */
static void random_case(float *f)
{
    float dir[3], n[3], v[3];
    do rnd_dir(dir);
    while (dir[2] < 0.05f);
    float dist = 0.3f + 5 * rnd();
    rnd_dir(n);
    if (n[0] * dir[0] + n[1] * dir[1] + n[2] * dir[2] > 0.2f)
        for (int i = 0; i < 3; i++) n[i] = -n[i];
    do rnd_dir(v);
    while (v[0] * n[0] + v[1] * n[1] + v[2] * n[2] <= 0.0f);
    if (rnd() < 0.05f) memcpy(v, n, sizeof v); /* the frame's fallback */
    float off[3] = {4 * rnd() - 2, 4 * rnd() - 2, 4 * rnd() - 2}; /* any common origin */
    for (int i = 0; i < 3; i++) {
        f[i] = dir[i] * dist + off[i];
        f[3 + i] = n[i];
        f[6 + i] = v[i];
        f[9 + i] = off[i];
        f[18 + i] = rnd();
    }
    float lu = 0.1f + 1.4f * rnd(), lv = 0.1f + 1.4f * rnd();
    f[12] = lu, f[13] = 0, f[14] = 0;
    f[15] = 0, f[16] = lv, f[17] = 0;
    f[21] = rnd() < 0.3f ? 1.0f : rnd() < 0.3f ? 0.0f : rnd();
    f[22] = rnd() < 0.1f ? 0.0f : rnd();
    f[23] = rnd() < 0.2f ? 1.0f : rnd();
}

static bool run_cases(const float *cases, int n, float *results, prw_error *e)
{
    prw_gpu *gpu = NULL;
    prw_gpu_desc d = {.device_index = -1, .validation = true};
    if (!prw_gpu_create(&d, &gpu, e)) return false;
    prw_buffer in = {0}, out = {0};
    prw_gpu_image table = {0};
    VkDescriptorSetLayout dsl = VK_NULL_HANDLE;
    VkPipelineLayout pl = VK_NULL_HANDLE;
    VkPipeline pipe = VK_NULL_HANDLE;
    prw_desc_pool *pool = NULL;
    VkDescriptorSetLayoutBinding b[3] = {
        {0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, NULL},
        {1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, NULL},
        {2, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_COMPUTE_BIT, NULL},
    };
    prw_image_desc td = {.width = PRW_LTC_N, .height = PRW_LTC_N, .layers = 2, .format = VK_FORMAT_R32G32B32A32_SFLOAT,
                         .usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                         .view_type = VK_IMAGE_VIEW_TYPE_2D_ARRAY};
    size_t layer = (size_t)PRW_LTC_N * PRW_LTC_N * 4;
    VkDescriptorSet set;
    VkCommandBuffer cmd;
    bool ok = prw_buffer_create(gpu, (size_t)n * FLOATS * sizeof(float), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                PRW_MEM_UPLOAD, &in, e) &&
              prw_buffer_create(gpu, (size_t)n * OUTS * sizeof(float), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                PRW_MEM_READBACK, &out, e) &&
              prw_image_create(gpu, &td, &table, e) &&
              prw_image_upload(gpu, &table, 0, prw_ltc_table_texels(), layer * sizeof(float), e) &&
              prw_image_upload(gpu, &table, 1, prw_ltc_table_texels() + layer, layer * sizeof(float), e) &&
              prw_desc_layout_create(gpu, b, 3, &dsl, e) && prw_pipeline_layout_create(gpu, &dsl, 1, 4, &pl, e) &&
              prw_pipeline_compute(gpu, prw_shader_ltc_test_comp(), pl, &pipe, e) &&
              prw_desc_pool_create(gpu, &pool, e) && prw_desc_alloc(gpu, pool, dsl, &set, e);
    if (ok) {
        memcpy(in.mapped, cases, (size_t)n * FLOATS * sizeof(float));
        prw_desc_write_buffer(gpu, set, 0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &in, 0, VK_WHOLE_SIZE);
        prw_desc_write_buffer(gpu, set, 1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &out, 0, VK_WHOLE_SIZE);
        prw_desc_write_image(gpu, set, 2, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, table.view,
                             prw_gpu_sampler(gpu, PRW_SAMPLER_LINEAR_CLAMP), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
        ok = prw_cmd_begin(gpu, &cmd, e);
    }
    if (ok) {
        uint32_t count = (uint32_t)n;
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipe);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pl, 0, 1, &set, 0, NULL);
        vkCmdPushConstants(cmd, pl, VK_SHADER_STAGE_ALL, 0, 4, &count);
        vkCmdDispatch(cmd, (count + 63) / 64, 1, 1);
        VkMemoryBarrier2 mb = {VK_STRUCTURE_TYPE_MEMORY_BARRIER_2, NULL, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                               VK_ACCESS_2_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT};
        VkDependencyInfo di = {.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO, .memoryBarrierCount = 1,
                               .pMemoryBarriers = &mb};
        vkCmdPipelineBarrier2(cmd, &di);
        ok = prw_cmd_submit_wait(gpu, cmd, e);
    }
    if (ok) memcpy(results, out.mapped, (size_t)n * OUTS * sizeof(float));
    if (pool) prw_desc_pool_destroy(gpu, pool);
    if (pipe) vkDestroyPipeline(prw_gpu_device(gpu), pipe, NULL);
    if (pl) vkDestroyPipelineLayout(prw_gpu_device(gpu), pl, NULL);
    if (dsl) vkDestroyDescriptorSetLayout(prw_gpu_device(gpu), dsl, NULL);
    prw_image_destroy(gpu, &table);
    prw_buffer_destroy(gpu, &in);
    prw_buffer_destroy(gpu, &out);
    prw_gpu_destroy(gpu);
    return ok;
}

static void test_ltc_gpu_equals_c(void)
{
    enum { N = 10000 };
    prw_error e;
    float *cases = prw_malloc((size_t)N * FLOATS * sizeof(float));
    float *gpu_v = prw_malloc((size_t)N * OUTS * sizeof(float));
    for (int i = 0; i < N; i++) random_case(cases + (size_t)i * FLOATS);
    bool ok = run_cases(cases, N, gpu_v, &e);
    CHECK_MSG(ok, "%s", e.msg);
    if (ok) {
        double worst = 0, worst_t = 0;
        int bad = 0, bad_t = 0, worst_i = 0, lit = 0;
        for (int i = 0; i < N; i++) {
            const float *f = cases + (size_t)i * FLOATS, *g = gpu_v + (size_t)i * OUTS;
            float cpu[3], m[4], fr[4];
            prw_ltc_rect_specular(f, f + 3, f + 6, f + 9, f + 12, f + 15, f + 18, f[21], f[22], f[23], cpu);
            float one[3] = {1, 1, 1}, unit[3];
            prw_ltc_rect_specular(f, f + 3, f + 6, f + 9, f + 12, f + 15, one, f[21], f[22], f[23], unit);
            float I = prw_ltc_rect_ggx(f, f + 3, f + 6, f + 9, f + 12, f + 15, f[22], fr);
            float S = prw_ltc_rect_ggx_scale(f, f + 3, f + 6, f + 9, f + 12, f + 15, f[22]);
            /* the Fresnel factor is at most that of a white metal's (1) or the dielectric's (<= 1) */
            double s = I > 0 ? (double)S * fmax(unit[0], fmax(unit[1], unit[2])) / I : (double)S * fr[0];
            lit += cpu[0] + cpu[1] + cpu[2] > 1e-4f;
            for (int k = 0; k < 3; k++) {
                double diff = fabs((double)g[k] - cpu[k]);
                double rel = diff / (1e-4 * (fabs(cpu[k]) + s) + 1e-12);
                if (!isfinite(g[k]) || !(rel <= 1)) bad++;
                if (rel > worst) worst = rel, worst_i = i;
            }
            prw_ltc_lookup(f[22], f[18], m, fr);
            double big[2] = {0, 0}; /* per layer, the texel's largest channel */
            for (int k = 0; k < 4; k++) big[0] = fmax(big[0], fabs(m[k])), big[1] = fmax(big[1], fabs(fr[k]));
            for (int k = 0; k < 8; k++) {
                float c = k < 4 ? m[k] : fr[k - 4];
                double rel = fabs((double)g[3 + k] - c) / (1e-5 * (fabs(c) + big[k / 4]) + 1e-12);
                if (!isfinite(g[3 + k]) || !(rel <= 1)) bad_t++;
                if (rel > worst_t) worst_t = rel;
            }
        }
        printf("ltc gpu vs c twin: %d cases (%d lit); lookup: worst |diff| / 1e-5 (|c| + max) %.3g, %d beyond; "
               "specular: worst |diff| / 1e-4 (|c| + s) %.3g (case %d), %d channels beyond\n",
               N, lit, worst_t, bad_t, worst, worst_i, bad);
        CHECK(bad == 0);
        CHECK(bad_t == 0);
        CHECK(lit > N / 2);
    }
    free(cases);
    free(gpu_v);
    CHECK(prw_gpu_validation_total() == 0);
}

static const prw_test_case cases_[] = {{"ltc_gpu_equals_c", test_ltc_gpu_equals_c}};

int main(int argc, char **argv)
{
    prw_threads_set(2);
    return prw_test_main(argc, argv, cases_, 1);
}
