/* The synthetic BTF generator (engine/bake/prw_btf_synth.h), measured by the path tracer:
 *  - flat_base: the flakes preset's flat coated base, wherever no flake is within 2 texels, equals
 *               the material model's closed form f(v, l) cos(theta_l) (prw_bsdf_eval) for every
 *               measured direction pair (>= 95 % of the values to 1e-5; the rest carry light a
 *               flake reflects onto the base, within 3 %) — the measurement's rays, light, units
 *               and frame;
 *               exactly 2 % of the texels hold a flake (seen head-on under a head-on light);
 *  - threads:   1 and 2 threads give the same bits;
 *  - varying:   the presets' |A - Abar| / |A| on 16 directions (must-show 0 holds it for 81 x 81:
 *               fabric >= 0.25, flakes >= 0.1; printed here, asserted with margin). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_btf_codec.h"
#include "prw_btf_synth.h"
#include "prw_bsdf.h"
#include "prw_test.h"

static bool synth(prw_btf_synth_kind k, uint32_t size, uint32_t dirs, int threads, prw_btf *out)
{
    prw_btf_synth_params p = {.kind = k, .size = size, .rays = 1, .spp = 2, .dirs = dirs, .seed = 5, .threads = threads};
    prw_error e;
    if (prw_btf_synthesize(&p, out, &e)) return true;
    fprintf(stderr, "synthesize: %s\n", e.msg);
    return false;
}

static void test_flat_base(void)
{
    const uint32_t S = 20, D = 16;
    prw_btf b;
    CHECK(synth(PRW_BTF_SYNTH_FLAKES, S, D, 2, &b));
    if (!b.rgb) return;
    /* the base material of the preset (prw_btf_synth.h): dark blue, roughness 0.3, coat GGX alpha 0.05 */
    prw_bsdf base = {.base = {0.02f, 0.05f, 0.20f}, .metallic = 0, .roughness = 0.3f, .specular = 1,
                     .clearcoat = 1, .clearcoat_roughness = (float)sqrt(0.05)};
    double up[3] = {0, 0, 1}, f0[3];
    prw_bsdf_eval(&base, up, up, f0);
    /* flake texels: head-on view and light show them different from the base */
    bool flake[S * S];
    int nflake = 0;
    for (uint32_t t = 0; t < S * S; t++) {
        const float *p = b.rgb + prw_btf_at(&b, 0, 0, t % S, t / S);
        flake[t] = fabs(p[2] - f0[2]) > 1e-4 * f0[2];
        nflake += flake[t];
    }
    CHECK_MSG(nflake == (int)lround(0.02 * S * S), "%d flake texels of %u (2 %% is %ld)", nflake, S * S, lround(0.02 * S * S));
    double worst = 0;
    int checked = 0, exact = 0;
    for (uint32_t v = 0; v < D; v++)
        for (uint32_t l = 0; l < D; l++) {
            double wo[3], wi[3], f[3];
            prw_btf_dir_vector(b.view_dirs[2 * v], b.view_dirs[2 * v + 1], wo);
            prw_btf_dir_vector(b.light_dirs[2 * l], b.light_dirs[2 * l + 1], wi);
            prw_bsdf_eval(&base, wo, wi, f);
            for (uint32_t y = 0; y < S; y++)
                for (uint32_t x = 0; x < S; x++) {
                    bool near = false; /* a flake within 2 texels (the tile repeats) */
                    for (int dy = -2; dy <= 2; dy++)
                        for (int dx = -2; dx <= 2; dx++)
                            near |= flake[((y + S + (uint32_t)dy) % S) * S + (x + S + (uint32_t)dx) % S];
                    if (near) continue;
                    const float *p = b.rgb + prw_btf_at(&b, v, l, x, y);
                    for (int c = 0; c < 3; c++) {
                        double want = f[c] * wi[2];
                        double rel = fabs(p[c] - want) / want;
                        worst = fmax(worst, rel);
                        exact += rel < 1e-5;
                    }
                    checked += 3;
                }
        }
    /* exact where only direct light reaches the base; light a flake reflects onto the base (an
     * interreflection, several texels away at grazing angles) adds a little elsewhere */
    printf("flat base: %d values against f(v, l) cos(theta_l): %.2f %% within 1e-5 relative, worst %.2g "
           "(light reflected by flakes)\n", checked, 100.0 * exact / checked, worst);
    CHECK(checked > 1000);
    CHECK_MSG(exact >= 0.95 * checked, "only %d of %d values exact", exact, checked);
    CHECK_MSG(worst < 0.03, "worst relative error %.3g", worst);
    prw_btf_free(&b);
}

static void test_threads(void)
{
    prw_btf a, b;
    CHECK(synth(PRW_BTF_SYNTH_LEATHER, 6, 4, 1, &a) && synth(PRW_BTF_SYNTH_LEATHER, 6, 4, 2, &b));
    if (a.rgb && b.rgb) CHECK(memcmp(a.rgb, b.rgb, sizeof(float) * 3 * 6 * 6 * 16) == 0);
    prw_btf_free(&a), prw_btf_free(&b);
}

static void test_varying(void)
{
    const uint32_t D = prw_test_light() ? 4 : 16;
    for (int k = 0; k < PRW_BTF_SYNTH_COUNT; k++) {
        prw_btf b;
        if (!synth((prw_btf_synth_kind)k, 16, D, 2, &b)) {
            CHECK(false);
            continue;
        }
        double f = prw_btf_varying_fraction(&b);
        printf("%-8s |A - Abar| / |A| = %.3f (16 x 16 texels, %u x %u directions)\n", prw_btf_synth_name((prw_btf_synth_kind)k), f, D, D);
        if (k == PRW_BTF_SYNTH_FABRIC) CHECK_MSG(f >= 0.25, "fabric %.3f", f);
        if (k == PRW_BTF_SYNTH_FLAKES) CHECK_MSG(f >= 0.1, "flakes %.3f", f);
        for (size_t i = 0; i < (size_t)16 * 16 * D * D * 3; i++)
            if (!isfinite(b.rgb[i]) || b.rgb[i] < 0) {
                CHECK_MSG(false, "%s: value %zu is %g", prw_btf_synth_name((prw_btf_synth_kind)k), i, b.rgb[i]);
                break;
            }
        prw_btf_free(&b);
    }
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"flat_base", test_flat_base},
        {"threads", test_threads},
        {"varying", test_varying},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
