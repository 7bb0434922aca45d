/* The shared BTF decode (materials/btf/prw_btf_decode.h) in a compute shader equals the C decode
 * (prw_btf_packed_value) at random texels, direction pairs and channels, for every codec (issue "BTF
 * materials", must-show 3): relative difference <= 1e-5 (values below 1e-4 compared absolutely at 1e-9).
 * The BTF is the synthetic flakes preset at 16 x 16 texels on 9 x 9 directions. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_btf_codec.h"
#include "prw_btf_synth.h"
#include "prw_gpu.h"
#include "prw_shaders.h"
#include "prw_test.h"

enum { NB = 10, N = 4096 };

/* halves padded to whole uints */
static size_t words(uint64_t halves) { return (size_t)((halves + 1) / 2 + 1); }

static bool run(const prw_btf_packed *p, const uint32_t *cases, float *out, prw_error *e)
{
    prw_gpu *gpu = NULL;
    prw_gpu_desc d = {.device_index = -1, .validation = true};
    if (!prw_gpu_create(&d, &gpu, e)) return false;
    uint64_t D = (uint64_t)p->views * p->lights * 3, T = (uint64_t)p->width * p->height, k = p->components;
    uint64_t nu = 0, nw = 0, nm = 0, nb = 0, ni = 0;
    if (p->codec == PRW_BTF_CODEC_FMF) nu = D * k, nw = T * k;
    else if (p->codec == PRW_BTF_CODEC_CLUSTER || p->codec == PRW_BTF_CODEC_SPARSE)
        nw = T * k, nm = p->clusters * D, nb = p->clusters * k * D, ni = T;
    else nw = p->views * T * k, nm = p->views * p->lights * 3, nb = p->views * k * p->lights * 3;
    const uint16_t *src[4] = {p->u, p->w, p->mean, p->basis};
    uint64_t cnt[4] = {nu, nw, nm, nb};
    prw_buffer buf[NB];
    memset(buf, 0, sizeof buf);
    VkDescriptorSetLayoutBinding b[NB];
    for (int i = 0; i < NB; i++) b[i] = (VkDescriptorSetLayoutBinding){(uint32_t)i, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, NULL};
    uint64_t M = p->codec == PRW_BTF_CODEC_SPARSE ? p->sparse_count : 0, ns = p->codec == PRW_BTF_CODEC_SPARSE ? T + 1 : 0;
    size_t sizes[NB] = {4 * words(nu), 4 * words(nw), 4 * words(nm), 4 * words(nb), 4 * (size_t)(ni + 1), 16 * (size_t)N, 4 * (size_t)N,
                        4 * (size_t)(ns + 1), 4 * words(M), 4 * words(3 * M)};
    VkDescriptorSetLayout dsl = VK_NULL_HANDLE;
    VkPipelineLayout pl = VK_NULL_HANDLE;
    VkPipeline pipe = VK_NULL_HANDLE;
    prw_desc_pool *pool = NULL;
    VkDescriptorSet set;
    VkCommandBuffer cmd;
    bool ok = true;
    for (int i = 0; ok && i < NB; i++)
        ok = prw_buffer_create(gpu, sizes[i], VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, i == 6 ? PRW_MEM_READBACK : PRW_MEM_UPLOAD,
                               &buf[i], e);
    ok = ok && prw_desc_layout_create(gpu, b, NB, &dsl, e) && prw_pipeline_layout_create(gpu, &dsl, 1, 24, &pl, e) &&
         prw_pipeline_compute(gpu, prw_shader_btf_decode_test_comp(), pl, &pipe, e) && prw_desc_pool_create(gpu, &pool, e) &&
         prw_desc_alloc(gpu, pool, dsl, &set, e);
    if (ok) {
        for (int i = 0; i < 4; i++) {
            memset(buf[i].mapped, 0, sizes[i]);
            if (cnt[i]) memcpy(buf[i].mapped, src[i], 2 * cnt[i]);
        }
        memset(buf[4].mapped, 0, sizes[4]);
        if (ni) memcpy(buf[4].mapped, p->index, 4 * ni);
        memcpy(buf[5].mapped, cases, 16 * (size_t)N);
        for (int i = 7; i < NB; i++) memset(buf[i].mapped, 0, sizes[i]);
        if (ns) memcpy(buf[7].mapped, p->sp_start, 4 * ns);
        if (M) memcpy(buf[8].mapped, p->sp_pair, 2 * M), memcpy(buf[9].mapped, p->sp_val, 6 * M);
        for (int i = 0; i < NB; i++) prw_desc_write_buffer(gpu, set, (uint32_t)i, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &buf[i], 0, VK_WHOLE_SIZE);
        ok = prw_cmd_begin(gpu, &cmd, e);
    }
    if (ok) {
        uint32_t pc[6] = {N, (uint32_t)p->codec, p->components, p->lights, p->views, (uint32_t)T};
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipe);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pl, 0, 1, &set, 0, NULL);
        vkCmdPushConstants(cmd, pl, VK_SHADER_STAGE_ALL, 0, sizeof pc, pc);
        vkCmdDispatch(cmd, (N + 63) / 64, 1, 1);
        VkMemoryBarrier2 mb = {VK_STRUCTURE_TYPE_MEMORY_BARRIER_2, NULL, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                               VK_ACCESS_2_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT};
        VkDependencyInfo di = {.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO, .memoryBarrierCount = 1, .pMemoryBarriers = &mb};
        vkCmdPipelineBarrier2(cmd, &di);
        ok = prw_cmd_submit_wait(gpu, cmd, e);
    }
    if (ok) memcpy(out, buf[6].mapped, sizeof(float) * N);
    if (pool) prw_desc_pool_destroy(gpu, pool);
    if (pipe) vkDestroyPipeline(prw_gpu_device(gpu), pipe, NULL);
    if (pl) vkDestroyPipelineLayout(prw_gpu_device(gpu), pl, NULL);
    if (dsl) vkDestroyDescriptorSetLayout(prw_gpu_device(gpu), dsl, NULL);
    for (int i = 0; i < NB; i++) prw_buffer_destroy(gpu, &buf[i]);
    prw_gpu_destroy(gpu);
    return ok;
}

static void test_gpu_equals_cpu(void)
{
    prw_error e;
    prw_btf b;
    prw_btf_synth_params sp = {.kind = PRW_BTF_SYNTH_FLAKES, .size = 16, .dirs = 9, .seed = 2, .threads = 2};
    CHECK_OK(prw_btf_synthesize(&sp, &b, &e), &e);
    const prw_btf_codec codecs[4] = {PRW_BTF_CODEC_FMF, PRW_BTF_CODEC_CLUSTER, PRW_BTF_CODEC_PVF, PRW_BTF_CODEC_SPARSE};
    uint32_t *cases = prw_malloc(16 * (size_t)N);
    float *gpu_v = prw_malloc(sizeof(float) * N);
    uint64_t st = 7;
    for (int ci = 0; ci < 4; ci++) {
        /* SPARSE: 8 of the 81 pairs per texel on average hold a residual entry, so cases hit and miss */
        prw_btf_codec_params cp = {.codec = codecs[ci], .components = ci == 3 ? 2 : 6, .clusters = 8, .sparse_per_texel = 8,
                                   .seed = 1, .threads = 2};
        prw_btf_packed p;
        CHECK_OK(prw_btf_compress(&b, &cp, &p, &e), &e);
        for (int i = 0; i < N; i++) {
            st = st * 6364136223846793005ull + 1442695040888963407ull;
            uint32_t r = (uint32_t)(st >> 33);
            cases[4 * i] = r % p.views, cases[4 * i + 1] = (r / 16) % p.lights, cases[4 * i + 2] = (r / 256) % (p.width * p.height),
            cases[4 * i + 3] = (r / 65536) % 3;
        }
        bool ok = run(&p, cases, gpu_v, &e);
        CHECK_MSG(ok, "%s", e.msg);
        double worst = 0;
        int hits = 0;
        for (int i = 0; ok && i < N; i++) {
            uint32_t t = cases[4 * i + 2];
            if (p.codec == PRW_BTF_CODEC_SPARSE)
                for (uint32_t j = p.sp_start[t]; j < p.sp_start[t + 1]; j++) hits += p.sp_pair[j] == cases[4 * i] * p.lights + cases[4 * i + 1];
            float cpu = prw_btf_packed_value(&p, cases[4 * i], cases[4 * i + 1], t % p.width, t / p.width, cases[4 * i + 3]);
            double diff = fabs((double)cpu - gpu_v[i]);
            worst = fmax(worst, fabs(cpu) > 1e-4 ? diff / fabs(cpu) : diff * 1e-5 / 1e-9);
        }
        printf("codec %d: %d values (%d on a residual entry), worst relative difference GPU vs CPU %.3g\n", (int)codecs[ci], N,
               hits, worst);
        if (p.codec == PRW_BTF_CODEC_SPARSE) CHECK_MSG(hits > 100, "sparse: only %d cases on a residual entry", hits);
        CHECK_MSG(worst <= 1e-5, "codec %d: worst %.3g", (int)codecs[ci], worst);
        prw_btf_packed_free(&p);
    }
    free(cases), free(gpu_v);
    prw_btf_free(&b);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {{"gpu_equals_cpu", test_gpu_equals_cpu}};
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
