/* The BTF material's evaluation on the GPU (shaders/btf_eval.glsl over prw_btf_gpu_pack's words) equals
 * the C evaluation (prw_btf_material_eval, what the path tracer uses) at random texel positions, view
 * and light directions, for every codec (issue "BTF materials", must-show 3 for the whole evaluation:
 * direction triangles and weights, the light's cosine, the bilinear texel filter and the decode).  The
 * BTF: random values on 12 x 10 texels (not square: a swapped x / y fails), views on the Bonn 81 set,
 * lights on that set turned by 7 degrees (separate light table); two materials in one array (the second
 * one's offsets are not 0).  Bound: |GPU - C| <= 1e-5 x (|C| + the case's largest stored value). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "compute_case.h"
#include "prw_btf_codec.h"
#include "prw_btf_eval.h"
#include "prw_btf_gpu.h"
#include "prw_shaders.h"
#include "prw_test.h"

enum { N = 4096 };

static uint64_t st = 11;
static double rnd(void)
{
    st = st * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(st >> 11) * (1.0 / 9007199254740992.0);
}

static void random_btf(prw_btf *b)
{
    prw_error e;
    CHECK_OK(prw_btf_create(12, 10, 81, 81, b, &e), &e);
    prw_btf_dirs_ubo81(b->view_dirs);
    prw_btf_dirs_ubo81(b->light_dirs);
    for (uint32_t i = 0; i < 81; i++) b->light_dirs[2 * i + 1] += 7.0f;
    /* smooth in the directions plus per-texel noise, so the codecs keep a structure */
    for (uint32_t v = 0; v < 81; v++)
        for (uint32_t l = 0; l < 81; l++)
            for (uint32_t y = 0; y < b->height; y++)
                for (uint32_t x = 0; x < b->width; x++) {
                    float *px = b->rgb + prw_btf_at(b, v, l, x, y);
                    for (int c = 0; c < 3; c++)
                        px[c] = (float)(0.2 + 0.1 * c + 0.3 * rnd() + 0.2 * cos(0.1 * v + 0.05 * l + c));
                }
}

static void dir(double z_min, float out[4])
{
    double z = z_min + (1 - z_min) * rnd(), p = 2 * 3.14159265358979 * rnd(), r = sqrt(fmax(0, 1 - z * z));
    double s = 0.5 + rnd(); /* not unit: both sides normalise */
    out[0] = (float)(s * r * cos(p)), out[1] = (float)(s * r * sin(p)), out[2] = (float)(s * z), out[3] = 0;
}

static void test_eval_gpu_equals_cpu(void)
{
    prw_error e;
    prw_btf b;
    random_btf(&b);
    const prw_btf_codec codecs[4] = {PRW_BTF_CODEC_FMF, PRW_BTF_CODEC_CLUSTER, PRW_BTF_CODEC_PVF, PRW_BTF_CODEC_SPARSE};
    float *cases = prw_malloc(sizeof(float) * 12 * N), *gpu = prw_malloc(sizeof(float) * 4 * N);
    for (int ci = 0; ci < 4; ci++) {
        prw_btf_codec_params cp = {.codec = codecs[ci], .components = 4, .clusters = 6, .sparse_per_texel = 8, .seed = 1, .threads = 2};
        prw_btf_packed p0, p1;
        CHECK_OK(prw_btf_compress(&b, &cp, &p0, &e), &e);
        cp.components = 2, cp.seed = 3;
        CHECK_OK(prw_btf_compress(&b, &cp, &p1, &e), &e);
        prw_btf_material m0, m1;
        CHECK_OK(prw_btf_material_from_packed(&p0, "first", &m0, &e), &e);
        CHECK_OK(prw_btf_material_from_packed(&p1, "second", &m1, &e), &e);
        CHECK(!m1.shared);
        prw_btf_gpu_words words = {0};
        uint32_t off0, off1;
        CHECK_OK(prw_btf_gpu_pack(&m0, "first", &words, &off0, &e), &e);
        CHECK_OK(prw_btf_gpu_pack(&m1, "second", &words, &off1, &e), &e);
        CHECK(off1 > 0);
        for (int i = 0; i < N; i++) {
            float *c = cases + 12 * i;
            c[0] = (float)(-30 + 60 * rnd()), c[1] = (float)(-30 + 60 * rnd()), c[2] = c[3] = 0;
            if (i % 16 == 0) c[0] = (float)(int)c[0] + 0.5f; /* texel centres */
            dir(0.02, c + 4);
            dir(i % 8 == 0 ? -0.3 : 0.02, c + 8); /* some lights below the horizon: 0 */
        }
        compute_buffer bufs[3] = {{words.w, sizeof(uint32_t) * words.count, NULL}, {cases, sizeof(float) * 12 * N, NULL},
                                  {NULL, sizeof(float) * 4 * N, gpu}};
        uint32_t pc[2] = {N, off1};
        bool ok = compute_case_run(prw_shader_btf_eval_test_comp(), bufs, 3, NULL, pc, sizeof pc, (N + 63) / 64, &e);
        CHECK_MSG(ok, "%s", e.msg);
        double worst = 0, scale = 0, sum = 0;
        for (uint64_t i = 0; i < (uint64_t)b.views * b.lights * b.width * b.height * 3; i++) scale = fmax(scale, fabs(b.rgb[i]));
        for (int i = 0; ok && i < N; i++) {
            const float *c = cases + 12 * i;
            double wv[3] = {c[4], c[5], c[6]}, wl[3] = {c[8], c[9], c[10]};
            float cpu[3];
            prw_btf_material_eval(&m1, c[0], c[1], wv, wl, cpu);
            for (int k = 0; k < 3; k++) {
                CHECK(isfinite(gpu[4 * i + k]));
                double d = fabs((double)cpu[k] - gpu[4 * i + k]) / (fabs(cpu[k]) + scale);
                worst = fmax(worst, d);
                sum += fabs(cpu[k]);
            }
        }
        printf("codec %d: %d cases, mean value %.4f, worst |GPU - C| / (|C| + max stored %.3f) = %.3g\n", (int)codecs[ci], N,
               sum / (3.0 * N), scale, worst);
        CHECK_MSG(sum > 0.05 * 3 * N, "codec %d: values near 0 (mean %.3g): the comparison would say little", (int)codecs[ci],
                  sum / (3.0 * N));
        CHECK_MSG(worst <= 1e-5, "codec %d: worst %.3g", (int)codecs[ci], worst);
        free(words.w);
        prw_btf_material_free(&m0), prw_btf_material_free(&m1);
    }
    free(cases), free(gpu);
    prw_btf_free(&b);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {{"eval_gpu_equals_cpu", test_eval_gpu_equals_cpu}};
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
