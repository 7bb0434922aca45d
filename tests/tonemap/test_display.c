/* Display profiles: PQ against SMPTE ST 2084 (independent long-double evaluation + published values),
 * round trips of every EOTF and of the display model, primaries matrices, the JSON files against the
 * built-in tuples, and loader error messages. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_display.h"
#include "prw_test.h"

#ifndef PRW_SOURCE_DIR
#error "PRW_SOURCE_DIR must be defined"
#endif

/* ST 2084 written out independently, in long double, with the constants as rationals */
static long double pq_ref_inverse(long double cd)
{
    long double m1 = 2610.0L / 4096.0L / 4.0L, m2 = 2523.0L / 4096.0L * 128.0L;
    long double c1 = 3424.0L / 4096.0L, c2 = 2413.0L / 4096.0L * 32.0L, c3 = 2392.0L / 4096.0L * 32.0L;
    long double y = cd / 10000.0L, p = powl(y, m1);
    return powl((c1 + c2 * p) / (1.0L + c3 * p), m2);
}
static long double pq_ref_eotf(long double e)
{
    long double m1 = 2610.0L / 4096.0L / 4.0L, m2 = 2523.0L / 4096.0L * 128.0L;
    long double c1 = 3424.0L / 4096.0L, c2 = 2413.0L / 4096.0L * 32.0L, c3 = 2392.0L / 4096.0L * 32.0L;
    long double p = powl(e, 1.0L / m2), n = p - c1;
    if (n < 0) n = 0;
    return 10000.0L * powl(n / (c2 - c3 * p), 1.0L / m1);
}

static void test_pq(void)
{
    /* constants exactly as in the issue */
    CHECK(PRW_PQ_M1 == 2610.0 / 16384.0 && PRW_PQ_M2 == 2523.0 / 32.0 && PRW_PQ_C1 == 3424.0 / 4096.0 &&
          PRW_PQ_C2 == 2413.0 / 128.0 && PRW_PQ_C3 == 2392.0 / 128.0);
    CHECK(fabs(PRW_PQ_C1 - (PRW_PQ_C3 - PRW_PQ_C2 + 1.0)) < 1e-15); /* c1 = c3 - c2 + 1 */
    double worst = 0, worst_rt = 0;
    for (int i = 0; i <= 4000; i++) {
        double e = i / 4000.0;
        worst = fmax(worst, fabs(prw_pq_eotf(e) / 10000.0 - (double)(pq_ref_eotf(e) / 10000.0L)));
        double cd = pow(10.0, -3.0 + 7.0 * i / 4000.0); /* 1e-3 .. 1e4 cd/m^2 */
        worst = fmax(worst, fabs(prw_pq_inverse(cd) - (double)pq_ref_inverse(cd)));
        double back = prw_pq_eotf(prw_pq_inverse(cd));
        worst_rt = fmax(worst_rt, fabs(back - cd) / cd);
    }
    printf("PQ: max |ours - ST 2084| = %.3g (normalised), round trip max relative error %.3g\n", worst, worst_rt);
    CHECK(worst <= 1e-6);
    CHECK(worst_rt <= 1e-4);
    /* published code values (ITU-R BT.2100 / BT.2408): 100 cd/m^2 -> 0.5081, 203 -> 0.5807 (58 %),
     * 1000 -> 0.7518, 10000 -> 1 */
    CHECK_NEAR(prw_pq_inverse(100), 0.5081, 1e-4);
    CHECK_NEAR(prw_pq_inverse(203), 0.5807, 1e-4);
    CHECK_NEAR(prw_pq_inverse(1000), 0.7518, 1e-4);
    CHECK_NEAR(prw_pq_inverse(10000), 1.0, 1e-12);
    CHECK_NEAR(prw_pq_eotf(1.0), 10000.0, 1e-9);
    CHECK(prw_pq_eotf(0.0) == 0.0);
}

static void test_srgb(void)
{
    double worst = 0;
    for (int i = 0; i <= 10000; i++) {
        double x = i / 10000.0;
        worst = fmax(worst, fabs(prw_srgb_decode(prw_srgb_encode(x)) - x));
    }
    CHECK(worst < 1e-12);
    CHECK_NEAR(prw_srgb_encode(0.0031308), 0.0031308 * 12.92, 1e-12);
    CHECK_NEAR(prw_srgb_encode(0.5), 0.735356983, 1e-8);
}

static void test_model_round_trip(void)
{
    for (const char *const *n = prw_display_builtin_names(); *n; n++) {
        prw_display d;
        CHECK(prw_display_builtin(*n, &d));
        prw_error e;
        CHECK_OK(prw_display_validate(&d, d.name, &e), &e);
        double lo = prw_display_min(&d), hi = prw_display_max(&d), worst = 0;
        for (int i = 0; i <= 2000; i++) {
            double l = lo * pow(hi / fmax(lo, 1e-6), i / 2000.0);
            if (lo <= 0) l = hi * pow(1e-5, 1.0 - i / 2000.0);
            double v = prw_display_signal(&d, l);
            CHECK(v >= 0 && v <= 1);
            worst = fmax(worst, fabs(prw_display_luminance(&d, v) - l) / l);
        }
        printf("%-12s L_min %.4f L_max %.1f reflection %.4f, model round trip max rel %.2g\n", d.name, lo, hi,
               prw_display_reflection(&d), worst);
        CHECK_MSG(worst < 1e-9, "%s: %.3g", d.name, worst);
        /* out-of-range targets clamp to the range */
        CHECK_NEAR(prw_display_luminance(&d, prw_display_signal(&d, 1e9)), hi, 1e-9 * hi);
        CHECK_NEAR(prw_display_luminance(&d, prw_display_signal(&d, 0)), fmax(lo, 0), 1e-9);
        CHECK(isfinite(prw_display_signal(&d, NAN)));
    }
    /* the display model itself, default LCD: L_d(1) = peak + (k/pi) E, L_d(0.5) by the formula */
    prw_display d;
    prw_display_builtin("default-lcd", &d);
    double refl = 0.01 / 3.14159265358979323846 * 60;
    CHECK_NEAR(prw_display_reflection(&d), refl, 1e-12);
    CHECK_NEAR(prw_display_luminance(&d, 0.5), (200 - 0.8) * pow(0.5, 2.2) + 0.8 + refl, 1e-9);
    /* BT.1886 with the textbook numbers (Lw 100, Lb 0.1, gamma 2.4): L(0) = Lb, L(1) = Lw */
    prw_display b = {"bt", PRW_EOTF_BT1886, PRW_PRIMARIES_REC709, 2.4, 100, 0.1, 0, 0, 80, 0, 8, false};
    CHECK_NEAR(prw_display_luminance(&b, 0), 0.1, 1e-9);
    CHECK_NEAR(prw_display_luminance(&b, 1), 100, 1e-9);
}

static void test_primaries(void)
{
    double m[9];
    prw_primaries_to_xyz(PRW_PRIMARIES_REC709, m);
    /* IEC 61966-2-1 sRGB -> XYZ (4 decimals) */
    const double srgb[9] = {0.4124, 0.3576, 0.1805, 0.2126, 0.7152, 0.0722, 0.0193, 0.1192, 0.9505};
    for (int i = 0; i < 9; i++) CHECK_NEAR(m[i], srgb[i], 1.5e-4);
    prw_display d;
    prw_display_builtin("hdr10-1000", &d);
    prw_display_matrix(&d, m);
    /* ITU-R BT.2087 Rec.709 -> Rec.2020 (4 decimals) */
    const double to2020[9] = {0.6274, 0.3293, 0.0433, 0.0691, 0.9195, 0.0114, 0.0164, 0.0880, 0.8956};
    for (int i = 0; i < 9; i++) CHECK_NEAR(m[i], to2020[i], 1.5e-4);
    for (int p = 0; p < 3; p++) {
        d.primaries = (prw_primaries)p;
        prw_display_matrix(&d, m);
        for (int r = 0; r < 3; r++) CHECK_NEAR(m[3 * r] + m[3 * r + 1] + m[3 * r + 2], 1.0, 1e-12); /* white stays */
    }
}

static void test_profile_files(void)
{
    const char *names[] = {"srgb", "office-lcd", "default-lcd", "bright-lcd", "hdr10-1000", "hmd-lcd"};
    for (size_t i = 0; i < PRW_ARRAY_LEN(names); i++) {
        char path[1024];
        snprintf(path, sizeof path, "%s/assets/displays/%s.json", PRW_SOURCE_DIR, names[i]);
        prw_display f, b;
        prw_error e;
        CHECK_OK(prw_display_load(path, &f, &e), &e);
        CHECK(prw_display_builtin(names[i], &b));
        CHECK_MSG(memcmp(&f, &b, sizeof f) == 0 || (strcmp(f.name, b.name) == 0 && f.eotf == b.eotf &&
                                                     f.primaries == b.primaries && f.gamma == b.gamma &&
                                                     f.peak == b.peak && f.black == b.black &&
                                                     f.reflectivity == b.reflectivity && f.ambient == b.ambient &&
                                                     fabs(f.ref_white - b.ref_white) < 1e-12 && f.ppd == b.ppd &&
                                                     f.bits == b.bits && f.hmd == b.hmd),
                  "%s: file and built-in differ", names[i]);
    }
    /* the tuples (gamma, peak, black, k, E_amb) */
    struct { const char *n; double g, p, b, k, E; } t[] = {{"office-lcd", 2.2, 100, 0.8, 0.01, 400},
                                                           {"default-lcd", 2.2, 200, 0.8, 0.01, 60},
                                                           {"bright-lcd", 2.6, 500, 0.5, 0.01, 10}};
    for (size_t i = 0; i < 3; i++) {
        prw_display d;
        prw_display_builtin(t[i].n, &d);
        CHECK(d.gamma == t[i].g && d.peak == t[i].p && d.black == t[i].b && d.reflectivity == t[i].k &&
              d.ambient == t[i].E && d.eotf == PRW_EOTF_GAMMA);
        CHECK(d.ref_white / d.peak >= 0.6 && d.ref_white / d.peak <= 0.9);
    }
    prw_display h;
    prw_display_builtin("hdr10-1000", &h);
    CHECK(h.eotf == PRW_EOTF_PQ && h.peak == 1000 && h.ref_white == 203 && h.primaries == PRW_PRIMARIES_REC2020);
    prw_display_builtin("hmd-lcd", &h);
    CHECK(h.hmd);
}

static void expect_error(const char *text, const char *needle)
{
    prw_display d;
    prw_error e = {{0}};
    bool ok = prw_display_parse(text, strlen(text), "t.json", &d, &e);
    CHECK_MSG(!ok && strstr(e.msg, needle), "expected '%s', got %s", needle, ok ? "success" : e.msg);
}

static void test_errors(void)
{
    const char *good = "{\"prw_display\":1,\"name\":\"x\",\"eotf\":\"gamma\",\"gamma\":2.2,\"peak\":100,\"black\":0.5,"
                       "\"reflectivity\":0.01,\"ambient\":100,\"reference_white_fraction\":0.8}";
    prw_display d;
    prw_error e;
    CHECK_OK(prw_display_parse(good, strlen(good), "t.json", &d, &e), &e);
    CHECK(d.bits == 8 && d.primaries == PRW_PRIMARIES_REC709 && fabs(d.ref_white - 80) < 1e-12);
    expect_error("{\n  \"prw_display\": 1,\n  \"name\" \"x\"\n}", "t.json:3:10: JSON syntax error");
    expect_error("{\"prw_display\":1,\"name\":\"x\",\"eotf\":\"gamma\",\"gamma\":2.2,\"peak\":100,\"black\":0.5,"
                 "\"reflectivity\":0.01,\"ambient\":100,\"reference_white_fraction\":0.8,\"colour\":1}",
                 "unknown key 'colour'");
    expect_error("{\"prw_display\":1,\"name\":\"x\",\"eotf\":\"hlg\",\"peak\":100,\"black\":0.5,"
                 "\"reflectivity\":0.01,\"ambient\":100,\"reference_white_fraction\":0.8}",
                 "t.json:eotf: must be one of srgb, gamma, bt1886, pq");
    expect_error("{\"prw_display\":1,\"name\":\"x\",\"eotf\":\"gamma\",\"gamma\":2.2,\"peak\":-3,\"black\":0.5,"
                 "\"reflectivity\":0.01,\"ambient\":100,\"reference_white_fraction\":0.8}",
                 "t.json:peak: must be a finite number");
    expect_error("{\"prw_display\":1,\"name\":\"x\",\"eotf\":\"gamma\",\"gamma\":2.2,\"peak\":100,\"black\":0.5,"
                 "\"reflectivity\":0.01,\"ambient\":100}",
                 "exactly one of reference_white_fraction and reference_white");
    expect_error("{\"prw_display\":1,\"name\":\"x\",\"eotf\":\"gamma\",\"peak\":100,\"black\":0.5,"
                 "\"reflectivity\":0.01,\"ambient\":100,\"reference_white_fraction\":0.8}",
                 "t.json:gamma: missing");
    expect_error("{\"prw_display\":2}", "t.json:prw_display: unsupported version");
    expect_error("[1]", "top level must be a JSON object");
    expect_error("{\"prw_display\":1,\"name\":\"x\",\"eotf\":\"pq\",\"peak\":100,\"black\":60,"
                 "\"reflectivity\":0.01,\"ambient\":100,\"reference_white\":80}",
                 "leaves no range below peak");
    CHECK(!prw_display_resolve("no-such-display", &d, &e) && strstr(e.msg, "default-lcd"));
    CHECK(prw_display_resolve("hdr10-1000", &d, &e) && d.eotf == PRW_EOTF_PQ);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"pq", test_pq},
        {"srgb", test_srgb},
        {"model_round_trip", test_model_round_trip},
        {"primaries", test_primaries},
        {"profile_files", test_profile_files},
        {"errors", test_errors},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
