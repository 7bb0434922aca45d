/* stats — order statistics, lows, bootstrap of a median ratio, Pareto front (prw_stats.h). */
#include "prw_stats.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_core.h"

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

void prw_stats_sort(double *x, size_t n)
{
    if (n > 1) qsort(x, n, sizeof *x, cmp_double);
}

double prw_stats_percentile_sorted(const double *sorted, size_t n, double p)
{
    if (n == 0) return NAN;
    if (p <= 0) return sorted[0];
    if (p >= 100) return sorted[n - 1];
    double h = (double)(n - 1) * p / 100.0;
    size_t i = (size_t)floor(h);
    if (i + 1 >= n) return sorted[n - 1];
    double f = h - (double)i;
    return sorted[i] + f * (sorted[i + 1] - sorted[i]);
}

double prw_stats_median(const double *x, size_t n)
{
    if (n == 0) return NAN;
    double *c = prw_malloc(n * sizeof *c);
    memcpy(c, x, n * sizeof *c);
    prw_stats_sort(c, n);
    double m = prw_stats_percentile_sorted(c, n, 50.0);
    free(c);
    return m;
}

double prw_stats_low_sorted(const double *sorted, size_t n, double fraction)
{
    if (n == 0) return NAN;
    size_t k = (size_t)ceil((double)n * fraction - 1e-9);
    if (k < 1) k = 1;
    if (k > n) k = n;
    double sum = 0;
    for (size_t i = n - k; i < n; i++) sum += sorted[i];
    return sum / (double)k;
}

void prw_stats_summarize(const double *x, size_t n, prw_stats_summary *out)
{
    memset(out, 0, sizeof *out);
    out->n = n;
    if (n == 0) {
        out->mean = out->min = out->max = out->p50 = out->p95 = out->p99 = NAN;
        out->low_1pct = out->low_01pct = NAN;
        return;
    }
    double *c = prw_malloc(n * sizeof *c);
    memcpy(c, x, n * sizeof *c);
    prw_stats_sort(c, n);
    double sum = 0;
    for (size_t i = 0; i < n; i++) sum += c[i];
    out->mean = sum / (double)n;
    out->min = c[0];
    out->max = c[n - 1];
    out->p50 = prw_stats_percentile_sorted(c, n, 50);
    out->p95 = prw_stats_percentile_sorted(c, n, 95);
    out->p99 = prw_stats_percentile_sorted(c, n, 99);
    out->low_1pct = prw_stats_low_sorted(c, n, 0.01);
    out->low_01pct = prw_stats_low_sorted(c, n, 0.001);
    free(c);
}

uint64_t prw_stats_rng_next(uint64_t *state)
{
    uint64_t z = (*state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

uint64_t prw_stats_rng_below(uint64_t *state, uint64_t n)
{
    if (n <= 1) return 0;
    uint64_t limit = UINT64_MAX - UINT64_MAX % n; /* accept [0, limit): a multiple of n */
    for (;;) {
        uint64_t r = prw_stats_rng_next(state);
        if (r < limit) return r % n;
    }
}

bool prw_stats_bootstrap_median_ratio(const double *a, size_t na, const double *b, size_t nb, bool paired,
                                      int resamples, uint64_t seed, prw_stats_ratio *out)
{
    memset(out, 0, sizeof *out);
    if (na == 0 || nb == 0 || resamples < 1 || (paired && na != nb)) return false;
    double ma = prw_stats_median(a, na), mb = prw_stats_median(b, nb);
    if (ma == 0) return false;
    out->ratio = mb / ma;
    out->resamples = resamples;
    double *ra = prw_malloc(na * sizeof *ra), *rb = prw_malloc(nb * sizeof *rb);
    double *ratios = prw_malloc((size_t)resamples * sizeof *ratios);
    uint64_t st = seed;
    int kept = 0;
    for (int r = 0; r < resamples; r++) {
        for (size_t i = 0; i < na; i++) {
            uint64_t j = prw_stats_rng_below(&st, na);
            ra[i] = a[j];
            if (paired) rb[i] = b[j];
        }
        if (!paired)
            for (size_t i = 0; i < nb; i++) rb[i] = b[prw_stats_rng_below(&st, nb)];
        prw_stats_sort(ra, na);
        prw_stats_sort(rb, nb);
        double da = prw_stats_percentile_sorted(ra, na, 50);
        if (da == 0) continue; /* a resample of all-zero times has no ratio */
        ratios[kept++] = prw_stats_percentile_sorted(rb, nb, 50) / da;
    }
    prw_stats_sort(ratios, (size_t)kept);
    out->lo = prw_stats_percentile_sorted(ratios, (size_t)kept, 2.5);
    out->hi = prw_stats_percentile_sorted(ratios, (size_t)kept, 97.5);
    free(ra);
    free(rb);
    free(ratios);
    return kept > 0;
}

bool prw_stats_bootstrap_pair_ratio(const double *a, const double *b, size_t n, int resamples, uint64_t seed,
                                    prw_stats_ratio *out)
{
    memset(out, 0, sizeof *out);
    if (n == 0 || resamples < 1) return false;
    for (size_t i = 0; i < n; i++)
        if (!(a[i] > 0)) return false;
    double *q = prw_malloc(n * sizeof *q), *rs = prw_malloc(n * sizeof *rs);
    double *meds = prw_malloc((size_t)resamples * sizeof *meds);
    for (size_t i = 0; i < n; i++) q[i] = b[i] / a[i];
    out->ratio = prw_stats_median(q, n);
    out->resamples = resamples;
    uint64_t st = seed;
    for (int r = 0; r < resamples; r++) {
        for (size_t i = 0; i < n; i++) rs[i] = q[prw_stats_rng_below(&st, n)];
        prw_stats_sort(rs, n);
        meds[r] = prw_stats_percentile_sorted(rs, n, 50);
    }
    prw_stats_sort(meds, (size_t)resamples);
    out->lo = prw_stats_percentile_sorted(meds, (size_t)resamples, 2.5);
    out->hi = prw_stats_percentile_sorted(meds, (size_t)resamples, 97.5);
    free(q);
    free(rs);
    free(meds);
    return true;
}

size_t prw_stats_pareto(const double *x, const double *y, size_t n, bool *on_front)
{
    size_t count = 0;
    for (size_t i = 0; i < n; i++) {
        bool ok = !isnan(x[i]) && !isnan(y[i]);
        for (size_t j = 0; ok && j < n; j++) {
            if (j == i || isnan(x[j]) || isnan(y[j])) continue;
            bool le = x[j] <= x[i] && y[j] <= y[i];
            bool lt = x[j] < x[i] || y[j] < y[i];
            if (le && lt) ok = false; /* j dominates i */
        }
        on_front[i] = ok;
        count += ok;
    }
    return count;
}
