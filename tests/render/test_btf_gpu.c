/* The shared BTF decode (materials/btf/prw_btf_decode.h) in a compute shader equals the C decode
 * (prw_btf_packed_value) at random texels, direction pairs and channels, for every codec (issue "BTF
 * materials", must-show 3): relative difference <= 1e-5 (values below 1e-4 compared absolutely at 1e-9).
 * The BTF is the synthetic flakes preset at 16 x 16 texels on 9 x 9 directions. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_btf_codec.h"
#include "prw_btf_synth.h"
#include "compute_case.h"
#include "prw_shaders.h"
#include "prw_test.h"

enum { NB = 10, N = 4096 };

/* halves padded to whole uints */
static size_t words(uint64_t halves) { return (size_t)((halves + 1) / 2 + 1); }

static bool run(const prw_btf_packed *p, const uint32_t *cases, float *out, prw_error *e)
{
    uint64_t D = (uint64_t)p->views * p->lights * 3, T = (uint64_t)p->width * p->height, k = p->components;
    uint64_t nu = 0, nw = 0, nm = 0, nb = 0, ni = 0;
    if (p->codec == PRW_BTF_CODEC_FMF) nu = D * k, nw = T * k;
    else if (p->codec == PRW_BTF_CODEC_CLUSTER || p->codec == PRW_BTF_CODEC_SPARSE)
        nw = T * k, nm = p->clusters * D, nb = p->clusters * k * D, ni = T;
    else nw = p->views * T * k, nm = p->views * p->lights * 3, nb = p->views * k * p->lights * 3;
    uint64_t M = p->codec == PRW_BTF_CODEC_SPARSE ? p->sparse_count : 0, ns = p->codec == PRW_BTF_CODEC_SPARSE ? T + 1 : 0;
    size_t sizes[NB] = {4 * words(nu), 4 * words(nw), 4 * words(nm), 4 * words(nb), 4 * (size_t)(ni + 1), 16 * (size_t)N, 4 * (size_t)N,
                        4 * (size_t)(ns + 1), 4 * words(M), 4 * words(3 * M)};
    /* the stored arrays, zero-padded to whole uints (two halves per uint in the shader) */
    const void *src[NB] = {p->u, p->w, p->mean, p->basis, p->index, cases, NULL, p->sp_start, p->sp_pair, p->sp_val};
    size_t used[NB] = {2 * nu, 2 * nw, 2 * nm, 2 * nb, 4 * ni, 16 * (size_t)N, 0, 4 * ns, 2 * M, 6 * M};
    void *host[NB];
    compute_buffer b[NB];
    for (int i = 0; i < NB; i++) {
        host[i] = prw_calloc(sizes[i], 1);
        if (used[i]) memcpy(host[i], src[i], used[i]);
        b[i] = (compute_buffer){host[i], sizes[i], i == 6 ? out : NULL};
    }
    uint32_t pc[6] = {N, (uint32_t)p->codec, p->components, p->lights, p->views, (uint32_t)T};
    bool ok = compute_case_run(prw_shader_btf_decode_test_comp(), b, NB, NULL, pc, sizeof pc, (N + 63) / 64, e);
    for (int i = 0; i < NB; i++) free(host[i]);
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
