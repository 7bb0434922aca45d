/* The shared material header (materials/prw_brdf.h) evaluated by a compute shader equals the C
 * evaluation on 10^4 random configurations (relative difference <= 1e-5; values below 1e-6 /sr
 * compared absolutely at 1e-11): the base model, and the coated model (clear coat) with its own
 * coat normal. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_brdf.h"
#include "compute_case.h"
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

typedef struct coat_case {
    float NoV, NoL, NoH, VoH, NcV, NcL, NcH, base, metallic, roughness, specular, clearcoat, rc;
} coat_case;

/* A coated configuration: random n, v, l as above and a coat normal up to ~40 degrees off n (a coat
 * normal map), so the coat's cosines differ from the base's (and may be negative). */
static coat_case random_coat_case(void)
{
    float th_v = acosf(rnd()), th_l = acosf(rnd()), ph = 6.2831853f * rnd();
    float v[3] = {sinf(th_v), 0, cosf(th_v)};
    float l[3] = {sinf(th_l) * cosf(ph), sinf(th_l) * sinf(ph), cosf(th_l)};
    float h[3] = {v[0] + l[0], v[1] + l[1], v[2] + l[2]};
    float hl = sqrtf(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
    for (int i = 0; i < 3; i++) h[i] /= hl > 0 ? hl : 1;
    float tc = rnd() < 0.3f ? 0.0f : 0.7f * rnd(), pc = 6.2831853f * rnd();
    float nc[3] = {sinf(tc) * cosf(pc), sinf(tc) * sinf(pc), cosf(tc)};
    coat_case c = {v[2], l[2], h[2], v[0] * h[0] + v[1] * h[1] + v[2] * h[2],
                   nc[0] * v[0] + nc[1] * v[1] + nc[2] * v[2], nc[0] * l[0] + nc[1] * l[1] + nc[2] * l[2],
                   nc[0] * h[0] + nc[1] * h[1] + nc[2] * h[2], rnd(), rnd() < 0.3f ? 1.0f : rnd(), rnd(),
                   rnd() < 0.2f ? 0.0f : rnd(), rnd() < 0.2f ? 1.0f : rnd(), rnd() < 0.1f ? 0.0f : rnd()};
    return c;
}

/* Runs `shader` over n cases of `stride` bytes into n floats. */
static bool run_cases(prw_spirv shader, const void *cases, size_t stride, int n, float *results, prw_error *e)
{
    uint32_t count = (uint32_t)n;
    compute_buffer b[2] = {{cases, (size_t)n * stride, NULL}, {NULL, (size_t)n * sizeof(float), results}};
    return compute_case_run(shader, b, 2, NULL, &count, sizeof count, (count + 63) / 64, e);
}

/* relative difference, values below 1e-6 /sr compared absolutely at 1e-11 */
static double rel_diff(float cpu, float gpu)
{
    double diff = fabs((double)cpu - (double)gpu);
    return fabs(cpu) > 1e-6 ? diff / fabs(cpu) : diff * 1e-5 / 1e-11;
}

static void test_gpu_equals_cpu(void)
{
    enum { N = 10000 };
    prw_error e;
    brdf_case *cases = prw_malloc(N * sizeof *cases);
    float *gpu_v = prw_malloc(N * sizeof(float));
    for (int i = 0; i < N; i++) cases[i] = random_case();
    bool ok = run_cases(prw_shader_brdf_test_comp(), cases, sizeof *cases, N, gpu_v, &e);
    CHECK_MSG(ok, "%s", e.msg);
    if (ok) {
        double worst = 0;
        int bad = 0, worst_i = 0;
        for (int i = 0; i < N; i++) {
            const brdf_case *c = &cases[i];
            float cpu = prw_brdf_channel(c->NoV, c->NoL, c->NoH, c->VoH, c->base, c->metallic, c->roughness, c->specular);
            double rel = rel_diff(cpu, gpu_v[i]);
            if (!isfinite(gpu_v[i]) || !(rel <= 1e-5)) bad++;
            if (rel > worst) worst = rel, worst_i = i;
        }
        printf("brdf gpu vs cpu: %d cases, worst relative %.3g (case %d), %d beyond 1e-5\n", N, worst, worst_i, bad);
        CHECK(bad == 0);
    }
    free(cases);
    free(gpu_v);
    CHECK(prw_gpu_validation_total() == 0); /* includes leak reports made at destroy */
}

/* The coated model (second GGX lobe of KHR_materials_clearcoat), the same way. */
static void test_coat_gpu_equals_cpu(void)
{
    enum { N = 10000 };
    prw_error e;
    coat_case *cases = prw_malloc(N * sizeof *cases);
    float *gpu_v = prw_malloc(N * sizeof(float));
    for (int i = 0; i < N; i++) cases[i] = random_coat_case();
    bool ok = run_cases(prw_shader_brdf_coat_test_comp(), cases, sizeof *cases, N, gpu_v, &e);
    CHECK_MSG(ok, "%s", e.msg);
    if (ok) {
        double worst = 0;
        int bad = 0, worst_i = 0, coated = 0;
        for (int i = 0; i < N; i++) {
            const coat_case *c = &cases[i];
            float cpu = prw_brdf_coated_channel(c->NoV, c->NoL, c->NoH, c->VoH, c->NcV, c->NcL, c->NcH, c->base,
                                                c->metallic, c->roughness, c->specular, c->clearcoat, c->rc);
            coated += c->clearcoat > 0 && c->NcV > 0 && c->NcL > 0;
            double rel = rel_diff(cpu, gpu_v[i]);
            if (!isfinite(gpu_v[i]) || !(rel <= 1e-5)) bad++;
            if (rel > worst) worst = rel, worst_i = i;
        }
        printf("coated brdf gpu vs cpu: %d cases (%d with the coat lobe active), worst relative %.3g (case %d), %d "
               "beyond 1e-5\n",
               N, coated, worst, worst_i, bad);
        CHECK(bad == 0);
        CHECK(coated > N / 2);
    }
    free(cases);
    free(gpu_v);
    CHECK(prw_gpu_validation_total() == 0);
}

static const prw_test_case cases_[] = {{"brdf_gpu_equals_cpu", test_gpu_equals_cpu},
                                       {"coat_gpu_equals_cpu", test_coat_gpu_equals_cpu}};

int main(int argc, char **argv)
{
    prw_threads_set(2);
    return prw_test_main(argc, argv, cases_, 2);
}
