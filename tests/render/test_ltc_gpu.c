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

#include "compute_case.h"
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
    uint32_t count = (uint32_t)n;
    compute_buffer b[2] = {{cases, (size_t)n * FLOATS * sizeof(float), NULL},
                           {NULL, (size_t)n * OUTS * sizeof(float), results}};
    compute_texture t = {prw_ltc_table_texels(), PRW_LTC_N, PRW_LTC_N, 2};
    return compute_case_run(prw_shader_ltc_test_comp(), b, 2, &t, &count, sizeof count, (count + 63) / 64, e);
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
