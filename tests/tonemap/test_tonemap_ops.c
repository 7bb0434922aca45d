/* The C reference operators (must-show 2 (a)-(c) and 4 of issue 6; (d) is in test_display.c):
 * per display profile, in absolute displayed luminance through the profile's EOTF and display model. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_test.h"
#include "tm_scenes.h"

static const char *const k_profiles[] = {"office-lcd", "default-lcd", "bright-lcd", "hdr10-1000", "hmd-lcd", "srgb"};
#define NPROF 5 /* the five; "srgb" (the provisional tone map's ideal display) is extra */

static void prep(const char *prof, prw_tm_op op, double exposure, prw_display *d, prw_tm_params *p)
{
    prw_display_builtin(prof, d);
    prw_tonemap_settings s = {.op = op};
    prw_tm_prepare(&s, d, exposure, p);
}

/* (a): no pixel above peak; fraction at peak: displayed luminance within 1e-4 of the display's range
 * below peak, (L - L_min) / (L_max - L_min) >= 1 - 1e-4 (clipped or indistinguishable from clipped) */
static void test_peak(void)
{
    const prw_tm_op ops[] = {PRW_TM_REINHARD, PRW_TM_NEUTRAL, PRW_TM_ADAPTIVE, PRW_TM_EXPOSURE, PRW_TM_ABSOLUTE};
    const double drs[] = {2, 4, 6};
    for (int pi = 0; pi < NPROF; pi++)
        for (size_t oi = 0; oi < PRW_ARRAY_LEN(ops); oi++) {
            double worst_over = 0, at_peak = 0;
            long total = 0;
            for (size_t si = 0; si < PRW_ARRAY_LEN(drs); si++) {
                prw_image hdr, out;
                double exposure = tm_scene_field(&hdr, 128, 96, drs[si], (unsigned)si + 1);
                prw_display d;
                prw_tm_params p;
                prep(k_profiles[pi], ops[oi], exposure, &d, &p);
                prw_error e;
                CHECK_OK(prw_tm_apply(&p, NULL, &hdr, &out, NULL, &e), &e);
                double lmin = prw_display_min(&d), lmax = prw_display_max(&d);
                for (int k = 0; k < 128 * 96; k++) {
                    double y = tm_displayed_lum(&d, out.rgba + 4 * k);
                    worst_over = fmax(worst_over, (y - d.peak) / d.peak);
                    if ((y - lmin) / (lmax - lmin) >= 1 - 1e-4) at_peak++;
                    total++;
                }
                prw_image_free(&hdr);
                prw_image_free(&out);
            }
            printf("%-12s %-9s max over peak %+.2e (relative), at peak %.3f %%\n", k_profiles[pi],
                   prw_tm_op_name(ops[oi]), worst_over, 100.0 * at_peak / total);
            /* the signal is float: its rounding (~6e-8 relative) may show as a few 1e-8 of peak */
            CHECK_MSG(worst_over <= 1e-6, "%s %s: %.3g above peak", k_profiles[pi], prw_tm_op_name(ops[oi]),
                      worst_over);
            /* the compressive operators must not pile pixels at peak; exposure+clamp and absolute clip by design */
            if (ops[oi] != PRW_TM_EXPOSURE && ops[oi] != PRW_TM_ABSOLUTE)
                CHECK_MSG(at_peak / total < 0.005, "%s %s: %.3f %% at peak", k_profiles[pi], prw_tm_op_name(ops[oi]),
                          100.0 * at_peak / total);
        }
}

/* (b): the scene's reference white (relative x = 1: L = 1 / exposure) shown at the profile's reference white */
static void test_reference_white(void)
{
    const prw_tm_op ops[] = {PRW_TM_EXPOSURE, PRW_TM_NEUTRAL, PRW_TM_ADAPTIVE, PRW_TM_ABSOLUTE};
    for (int pi = 0; pi < NPROF; pi++)
        for (size_t oi = 0; oi < PRW_ARRAY_LEN(ops); oi++) {
            prw_display d;
            prw_display_builtin(k_profiles[pi], &d);
            /* absolute: scene white is shown as is, so only meaningful at a scene white of W itself */
            double exposure = ops[oi] == PRW_TM_ABSOLUTE ? 1.0 / d.ref_white : 1.0 / 3000.0;
            prw_tm_params p;
            prep(k_profiles[pi], ops[oi], exposure, &d, &p);
            /* a scene with white and a range of other values (frame statistics matter for adaptive) */
            prw_image hdr, out;
            tm_scene_field(&hdr, 64, 64, 5, 3);
            for (int q = 0; q < 3; q++) hdr.rgba[q] = (float)(1.0 / exposure);
            prw_error e;
            CHECK_OK(prw_tm_apply(&p, NULL, &hdr, &out, NULL, &e), &e);
            double y = tm_displayed_lum(&d, out.rgba);
            printf("%-12s %-9s reference white -> %.2f cd/m^2 (%.3f of peak; profile: %.2f)\n", k_profiles[pi],
                   prw_tm_op_name(ops[oi]), y, y / d.peak, d.ref_white);
            if (d.eotf == PRW_EOTF_PQ) CHECK_MSG(fabs(y - 203.0) <= 4.0, "%s: %.2f", prw_tm_op_name(ops[oi]), y);
            else {
                CHECK(y / d.peak >= 0.6 && y / d.peak <= 0.9);
                CHECK_MSG(fabs(y - d.ref_white) <= 0.01 * d.ref_white, "%s %s: %.3f vs %.3f", k_profiles[pi],
                          prw_tm_op_name(ops[oi]), y, d.ref_white);
            }
            prw_image_free(&hdr);
            prw_image_free(&out);
        }
}

/* (c): global operators are monotonic on grey and coloured luminance ramps over 12 decades */
static void test_monotonic(void)
{
    const int n = 6000;
    prw_image ramp, out;
    prw_error e;
    const double chroma[3][3] = {{1, 1, 1}, {1.6, 0.8, 0.5}, {0.3, 0.6, 2.5}};
    for (int ci = 0; ci < 3; ci++) {
        prw_image_alloc(&ramp, n, 1, &e);
        double cy = 0.2126 * chroma[ci][0] + 0.7152 * chroma[ci][1] + 0.0722 * chroma[ci][2];
        for (int i = 0; i < n; i++) {
            double Y = pow(10.0, -4.0 + 12.0 * i / (n - 1.0));
            for (int q = 0; q < 3; q++) ramp.rgba[4 * i + q] = (float)(Y * chroma[ci][q] / cy);
            ramp.rgba[4 * i + 3] = 1;
        }
        for (int pi = 0; pi < NPROF + 1; pi++)
            for (int op = 0; op < PRW_TM_OP_COUNT; op++) {
                prw_display d;
                prw_tm_params p;
                prep(k_profiles[pi], (prw_tm_op)op, 1.0 / 500.0, &d, &p);
                CHECK_OK(prw_tm_apply(&p, NULL, &ramp, &out, NULL, &e), &e);
                double prev = -1, worst_drop = 0;
                for (int i = 0; i < n; i++) {
                    double y = tm_displayed_lum(&d, out.rgba + 4 * i);
                    if (prev >= 0) worst_drop = fmax(worst_drop, (prev - y) / d.peak);
                    prev = y;
                }
                /* float output: allow one float ulp of signal, nothing more */
                CHECK_MSG(worst_drop <= 1e-6, "%s %s chroma %d: luminance drops by %.3g of peak", k_profiles[pi],
                          prw_tm_op_name((prw_tm_op)op), ci, worst_drop);
                prw_image_free(&out);
            }
        prw_image_free(&ramp);
    }
}

/* 4: extremes never give NaN/Inf, and the signal stays in [0, 1] */
static void test_extremes(void)
{
    for (int x = 0; x < TM_EXT_COUNT; x++) {
        prw_image hdr;
        tm_scene_extreme(&hdr, 48, 40, x);
        for (int pi = 0; pi < NPROF + 1; pi++)
            for (int op = 0; op < PRW_TM_OP_COUNT; op++)
                for (int ov = 0; ov < 2; ov++) {
                    prw_display d;
                    prw_display_builtin(k_profiles[pi], &d);
                    prw_tonemap_settings s = {.op = (prw_tm_op)op, .overlay = ov};
                    prw_tm_params p;
                    prw_tm_prepare(&s, &d, 1.0 / 100.0, &p);
                    prw_image out;
                    prw_tm_report rep;
                    prw_error e;
                    CHECK_OK(prw_tm_apply(&p, NULL, &hdr, &out, &rep, &e), &e);
                    int bad = 0;
                    for (int k = 0; k < 48 * 40 * 4; k++) bad += !(out.rgba[k] >= 0.0f && out.rgba[k] <= 1.0f);
                    CHECK_MSG(bad == 0, "%s, %s, %s: %d bad values", tm_scene_extreme_name(x), k_profiles[pi],
                              prw_tm_op_name((prw_tm_op)op), bad);
                    prw_image_free(&out);
                }
        prw_image_free(&hdr);
    }
}

/* PBR Neutral against its published formula, evaluated by hand for a few colours */
static void test_pbr_neutral(void)
{
    struct { double in[3], out[3]; } t[] = {
        /* below the compression start: only the toe offset (x >= 0.08: 0.04) */
        {{0.5, 0.5, 0.5}, {0.46, 0.46, 0.46}},
        /* toe: x = 0.05 -> offset x - 6.25 x^2 = 0.034375 */
        {{0.05, 0.2, 0.3}, {0.015625, 0.165625, 0.265625}},
        /* grey 1: peak 0.96, new peak 1 - 0.24^2 / (0.96 + 0.24 - 0.76) = 0.86909..., no hue to desaturate */
        {{1, 1, 1}, {1 - 0.0576 / 0.44, 1 - 0.0576 / 0.44, 1 - 0.0576 / 0.44}},
        /* (2, 0.5, 0.1): offset 0.04, peak 1.96, new peak 0.96, g = 1 - 1/1.15 */
        {{2, 0.5, 0.1},
         {0.96, 0.46 * 0.96 / 1.96 / 1.15 + 0.96 * (1 - 1 / 1.15), 0.06 * 0.96 / 1.96 / 1.15 + 0.96 * (1 - 1 / 1.15)}},
    };
    for (size_t i = 0; i < PRW_ARRAY_LEN(t); i++) {
        double o[3];
        prw_tm_pbr_neutral(t[i].in, o);
        for (int c = 0; c < 3; c++) CHECK_NEAR(o[c], t[i].out[c], 1e-12);
    }
}

/* absolute mode: in-range pixels shown at their own cd/m^2; the report counts what is out of range */
static void test_absolute(void)
{
    prw_display d;
    prw_tm_params p;
    prep("hdr10-1000", PRW_TM_ABSOLUTE, 1.0 / 300.0, &d, &p);
    prw_image hdr, out;
    prw_error e;
    prw_image_alloc(&hdr, 4, 1, &e);
    const float px[4][3] = {{0.001f, 0.001f, 0.001f}, {203, 203, 203}, {5000, 5000, 5000}, {0, 50, 0}};
    for (int k = 0; k < 4; k++)
        for (int q = 0; q < 4; q++) hdr.rgba[4 * k + q] = q < 3 ? px[k][q] : 1;
    prw_tm_report rep;
    CHECK_OK(prw_tm_apply(&p, NULL, &hdr, &out, &rep, &e), &e);
    CHECK_NEAR(tm_displayed_lum(&d, out.rgba + 4), 203.0, 203.0 * 1e-6);
    CHECK_NEAR(tm_displayed_lum(&d, out.rgba + 8), 1000.0, 1e-3);
    CHECK_NEAR(tm_displayed_lum(&d, out.rgba + 0), prw_display_min(&d), 1e-6);
    /* pure Rec.709 green at 50 cd/m^2 is inside Rec.2020: shown at its luminance (the rounded weight
     * 0.7152 of DESIGN.md §5 differs from the chromaticity-derived 0.71517 by 4e-5) */
    CHECK_NEAR(tm_displayed_lum(&d, out.rgba + 12), 50.0 * 0.7152, 50.0 * 0.7152 * 1e-4);
    printf("absolute on hdr10: below %llu, above %llu, out of gamut %llu of %llu\n",
           (unsigned long long)rep.below_black, (unsigned long long)rep.above_peak,
           (unsigned long long)rep.out_of_gamut, (unsigned long long)rep.pixels);
    CHECK(rep.below_black == 1 && rep.above_peak == 1 && rep.out_of_gamut == 0 && rep.pixels == 4);
    prw_image_free(&out);
    /* on an sRGB-primaries display a saturated Rec.709 colour is in gamut, a dark one is not
     * representable above black + reflection without desaturation */
    prep("office-lcd", PRW_TM_ABSOLUTE, 1.0, &d, &p);
    CHECK_OK(prw_tm_apply(&p, NULL, &hdr, &out, &rep, &e), &e);
    CHECK(rep.above_peak == 2 && rep.below_black == 1);
    prw_image_free(&out);
    prw_image_free(&hdr);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"pbr_neutral", test_pbr_neutral}, {"peak", test_peak},           {"reference_white", test_reference_white},
        {"monotonic", test_monotonic},     {"extremes", test_extremes}, {"absolute", test_absolute},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
