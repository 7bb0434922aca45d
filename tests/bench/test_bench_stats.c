/* prw_stats: percentiles, lows, bootstrap of a median ratio, Pareto front — against hand-computed
 * cases. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_stats.h"
#include "prw_test.h"

static void t_percentiles(void)
{
    const double x[4] = {1, 2, 3, 4};
    CHECK_NEAR(prw_stats_percentile_sorted(x, 4, 0), 1, 0);
    CHECK_NEAR(prw_stats_percentile_sorted(x, 4, 25), 1.75, 1e-15); /* h = 0.75 */
    CHECK_NEAR(prw_stats_percentile_sorted(x, 4, 50), 2.5, 1e-15);  /* h = 1.5 */
    CHECK_NEAR(prw_stats_percentile_sorted(x, 4, 95), 3.85, 1e-15); /* h = 2.85 */
    CHECK_NEAR(prw_stats_percentile_sorted(x, 4, 100), 4, 0);
    const double one = 7;
    CHECK_NEAR(prw_stats_percentile_sorted(&one, 1, 99), 7, 0);
    CHECK(isnan(prw_stats_percentile_sorted(x, 0, 50)));
    const double odd[3] = {5, 1, 3};
    CHECK_NEAR(prw_stats_median(odd, 3), 3, 0);
    const double even[4] = {10, 40, 20, 30};
    CHECK_NEAR(prw_stats_median(even, 4), 25, 0);
    CHECK(even[0] == 10 && even[1] == 40); /* the input is not reordered */
}

static void t_lows(void)
{
    double x[1000];
    for (int i = 0; i < 1000; i++) x[i] = i + 1;
    /* 1000 frames: 1 % = the 10 slowest (991..1000, mean 995.5); 0.1 % = the slowest one */
    CHECK_NEAR(prw_stats_low_sorted(x, 1000, 0.01), 995.5, 1e-12);
    CHECK_NEAR(prw_stats_low_sorted(x, 1000, 0.001), 1000, 0);
    /* 200 frames: 1 % = 2 frames (199, 200); 0.1 % = ceil(0.2) = 1 frame */
    CHECK_NEAR(prw_stats_low_sorted(x, 200, 0.01), 199.5, 1e-12);
    CHECK_NEAR(prw_stats_low_sorted(x, 200, 0.001), 200, 0);
    /* 150 frames: ceil(1.5) = 2 */
    CHECK_NEAR(prw_stats_low_sorted(x, 150, 0.01), 149.5, 1e-12);
    /* fewer than 100 frames: the single slowest */
    CHECK_NEAR(prw_stats_low_sorted(x, 60, 0.01), 60, 0);
    prw_stats_summary s;
    const double y[4] = {4, 1, 3, 2};
    prw_stats_summarize(y, 4, &s);
    CHECK(s.n == 4);
    CHECK_NEAR(s.mean, 2.5, 0);
    CHECK_NEAR(s.min, 1, 0);
    CHECK_NEAR(s.max, 4, 0);
    CHECK_NEAR(s.p50, 2.5, 1e-15);
    CHECK_NEAR(s.p99, 3.97, 1e-12); /* h = 2.97 */
    CHECK_NEAR(s.low_1pct, 4, 0);
    CHECK_NEAR(s.low_01pct, 4, 0);
    prw_stats_summarize(y, 0, &s);
    CHECK(s.n == 0 && isnan(s.p50) && isnan(s.low_1pct));
}

static void t_rng(void)
{
    uint64_t a = 42, b = 42;
    for (int i = 0; i < 100; i++) CHECK(prw_stats_rng_next(&a) == prw_stats_rng_next(&b));
    int hist[3] = {0, 0, 0};
    for (int i = 0; i < 30000; i++) {
        uint64_t v = prw_stats_rng_below(&a, 3);
        CHECK(v < 3);
        if (v < 3) hist[v]++;
    }
    for (int k = 0; k < 3; k++) CHECK_MSG(abs(hist[k] - 10000) < 500, "bin %d: %d", k, hist[k]);
    CHECK(prw_stats_rng_below(&a, 1) == 0);
}

static void t_bootstrap_constant(void)
{
    double a[31], b[31];
    for (int i = 0; i < 31; i++) a[i] = 10, b[i] = 12;
    prw_stats_ratio r;
    CHECK(prw_stats_bootstrap_median_ratio(a, 31, b, 31, true, 2000, 1, &r));
    CHECK_NEAR(r.ratio, 1.2, 1e-15);
    CHECK_NEAR(r.lo, 1.2, 1e-15);
    CHECK_NEAR(r.hi, 1.2, 1e-15);
    CHECK(r.resamples == 2000);
}

/* a = {1,1,1}, b = {1,2,2}: median(b)/median(a) = 2.  A resample of b has median 1 when at least two
 * of its three draws are the 1: probability 3 (1/3)^2 (2/3) + (1/3)^3 = 7/27 (26 %), else 2; so the
 * 2.5th and 97.5th percentiles of the bootstrap ratio are 1 and 2. */
static void t_bootstrap_hand(void)
{
    const double a[3] = {1, 1, 1}, b[3] = {1, 2, 2};
    prw_stats_ratio r;
    CHECK(prw_stats_bootstrap_median_ratio(a, 3, b, 3, false, 4000, 7, &r));
    CHECK_NEAR(r.ratio, 2, 0);
    CHECK_NEAR(r.lo, 1, 0);
    CHECK_NEAR(r.hi, 2, 0);
}

/* Paired samples with b_i = 1.2 a_i: every paired resample has ratio 1.2 (the median commutes with
 * scaling), while unpaired resampling of the same data gives a wide interval. */
static void t_bootstrap_paired(void)
{
    double a[40], b[40];
    uint64_t st = 3;
    for (int i = 0; i < 40; i++) {
        a[i] = 50 + 100 * (double)(prw_stats_rng_next(&st) >> 11) / 9007199254740992.0;
        b[i] = 1.2 * a[i];
    }
    prw_stats_ratio p, u, p2;
    CHECK(prw_stats_bootstrap_median_ratio(a, 40, b, 40, true, 3000, 11, &p));
    CHECK(prw_stats_bootstrap_median_ratio(a, 40, b, 40, false, 3000, 11, &u));
    CHECK(prw_stats_bootstrap_median_ratio(a, 40, b, 40, true, 3000, 11, &p2));
    CHECK_NEAR(p.ratio, 1.2, 1e-12);
    CHECK_NEAR(p.lo, 1.2, 1e-12);
    CHECK_NEAR(p.hi, 1.2, 1e-12);
    CHECK(u.hi - u.lo > 0.1);
    CHECK(memcmp(&p, &p2, sizeof p) == 0); /* same seed: bit-identical */
    CHECK(!prw_stats_bootstrap_median_ratio(a, 40, b, 39, true, 10, 1, &p));
    CHECK(!prw_stats_bootstrap_median_ratio(a, 0, b, 40, false, 10, 1, &p));
    CHECK(!prw_stats_bootstrap_median_ratio(a, 40, b, 40, false, 0, 1, &p));
}

/* Median of per-pair ratios.  Hand case: ratios {1, 2, 2}, median 2; a resample's median is 1 with
 * probability 7/27 (as above), so the percentile interval is [1, 2].  Path case: frame costs vary 4x
 * along a path and a load burst slows both frames of some pairs 3x; the pair ratios stay 1.2 (x 1 +-1 %
 * noise), so the figure is 1.2 within the noise while median(b)/median(a) of the same data is not
 * guaranteed to be. */
static void t_bootstrap_pair_ratio(void)
{
    const double a3[3] = {1, 1, 1}, b3[3] = {1, 2, 2};
    prw_stats_ratio r;
    CHECK(prw_stats_bootstrap_pair_ratio(a3, b3, 3, 4000, 7, &r));
    CHECK_NEAR(r.ratio, 2, 0);
    CHECK_NEAR(r.lo, 1, 0);
    CHECK_NEAR(r.hi, 2, 0);

    double a[60], b[60];
    uint64_t st = 5;
    for (int i = 0; i < 60; i++) {
        double cost = 1000 + 3000 * (double)(i % 20) / 19.0;  /* the path: 1..4 s */
        double burst = (i % 7 == 3) ? 3.0 : 1.0;               /* load burst hits the pair */
        double u = (double)(prw_stats_rng_next(&st) >> 11) / 9007199254740992.0;
        a[i] = cost * burst;
        b[i] = 1.2 * cost * burst * (1 + 0.02 * (u - 0.5));
    }
    CHECK(prw_stats_bootstrap_pair_ratio(a, b, 60, 4000, 1, &r));
    CHECK_NEAR(r.ratio, 1.2, 0.012);
    CHECK(r.lo <= r.ratio && r.ratio <= r.hi);
    CHECK(r.lo > 1.2 * 0.99 && r.hi < 1.2 * 1.01);
    b[10] = 0;
    CHECK(prw_stats_bootstrap_pair_ratio(a, b, 60, 10, 1, &r)); /* b = 0 is a ratio of 0, allowed */
    a[10] = 0;
    CHECK(!prw_stats_bootstrap_pair_ratio(a, b, 60, 10, 1, &r));
    CHECK(!prw_stats_bootstrap_pair_ratio(a, b, 0, 10, 1, &r));
    CHECK(!prw_stats_bootstrap_pair_ratio(a3, b3, 3, 0, 1, &r));
}

/* Noisy frame times: A ~ 100 ms, B ~ 120 ms with 5 % noise; the interval contains 1.2 and is narrow. */
static void t_bootstrap_noisy(void)
{
    double a[60], b[60];
    uint64_t st = 99;
    for (int i = 0; i < 60; i++) {
        double u1 = (double)(prw_stats_rng_next(&st) >> 11) / 9007199254740992.0;
        double u2 = (double)(prw_stats_rng_next(&st) >> 11) / 9007199254740992.0;
        a[i] = 100 * (1 + 0.05 * (u1 - 0.5) * 2);
        b[i] = 120 * (1 + 0.05 * (u2 - 0.5) * 2);
    }
    prw_stats_ratio r;
    CHECK(prw_stats_bootstrap_median_ratio(a, 60, b, 60, true, 4000, 1, &r));
    CHECK_MSG(r.lo <= 1.2 && r.hi >= 1.2, "[%g, %g]", r.lo, r.hi);
    CHECK_MSG(r.hi - r.lo < 0.08, "[%g, %g]", r.lo, r.hi);
    CHECK(r.lo <= r.ratio && r.ratio <= r.hi);
}

static void t_pareto(void)
{
    /* index:           0  1  2  3  4  5    6    7   8 */
    const double x[9] = {1, 2, 3, 4, 2, 5, NAN, 0.5, 1};
    const double y[9] = {5, 3, 4, 1, 3, 5, 0, 10, 6};
    const bool expect[9] = {true, true, false, true, true, false, false, true, false};
    bool front[9];
    size_t n = prw_stats_pareto(x, y, 9, front);
    CHECK(n == 5);
    for (int i = 0; i < 9; i++) CHECK_MSG(front[i] == expect[i], "point %d", i);
    /* all equal: all on the front */
    const double ex[3] = {2, 2, 2}, ey[3] = {1, 1, 1};
    CHECK(prw_stats_pareto(ex, ey, 3, front) == 3);
    /* a chain dominated one by one: only the best */
    const double cx[4] = {4, 3, 2, 1}, cy[4] = {4, 3, 2, 1};
    CHECK(prw_stats_pareto(cx, cy, 4, front) == 1 && front[3] && !front[0]);
    CHECK(prw_stats_pareto(cx, cy, 0, front) == 0);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"percentiles", t_percentiles},
        {"lows", t_lows},
        {"rng", t_rng},
        {"bootstrap_constant", t_bootstrap_constant},
        {"bootstrap_hand", t_bootstrap_hand},
        {"bootstrap_paired", t_bootstrap_paired},
        {"bootstrap_noisy", t_bootstrap_noisy},
        {"bootstrap_pair_ratio", t_bootstrap_pair_ratio},
        {"pareto", t_pareto},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
