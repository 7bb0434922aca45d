/* prw_stats — pure statistics for benchmarks: order statistics of frame times, lows, a seeded
 * bootstrap of a median ratio, and the Pareto front of (time, error) points.
 *
 * Promises:
 *  - No I/O, no global state, no allocation visible to the caller (internal scratch is freed).
 *  - Percentiles use linear interpolation between order statistics (numpy's default, "type 7"):
 *    for sorted x[0..n), p in [0, 100]: h = (n - 1) p / 100, result x[floor h] + (h - floor h)
 *    (x[floor h + 1] - x[floor h]).  The median is the 50th percentile.
 *  - Lows: the "1 % low" of frame times is the MEAN of the slowest ceil(n * 1 %) frame times
 *    (at least one frame), in the same unit as the input (ms); likewise the "0.1 % low".  Larger
 *    is worse.  With fewer than 100 (1000) frames both lows are the single slowest frame.
 *  - Bootstrap: percentile interval of the ratio median(b) / median(a) over `resamples` resamples
 *    drawn with a SplitMix64 generator from `seed`; paired (the same indices for a and b) when
 *    the caller says the samples are pairs (interleaved A/B frames), else independent.  The same
 *    inputs and seed give bit-identical results on every machine.
 *  - Pareto front: minimise both coordinates; a point is on the front when no other point is
 *    <= in both and < in at least one.  Equal points are all on the front.
 */
#ifndef PRW_STATS_H
#define PRW_STATS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Sorts x in place, ascending (NaNs are not allowed). */
void prw_stats_sort(double *x, size_t n);
/* Percentile p in [0, 100] of sorted x (n >= 1); NaN when n == 0. */
double prw_stats_percentile_sorted(const double *sorted, size_t n, double p);
/* Median of unsorted x (copied internally); NaN when n == 0. */
double prw_stats_median(const double *x, size_t n);
/* Mean of the largest ceil(n * fraction) values of sorted x (at least one); NaN when n == 0. */
double prw_stats_low_sorted(const double *sorted, size_t n, double fraction);

typedef struct prw_stats_summary {
    size_t n;
    double mean, min, max;
    double p50, p95, p99;
    double low_1pct, low_01pct; /* see the header comment: mean of the slowest 1 % / 0.1 % */
} prw_stats_summary;

/* Summary of unsorted x (copied internally).  n == 0 gives n = 0 and NaN figures. */
void prw_stats_summarize(const double *x, size_t n, prw_stats_summary *out);

/* SplitMix64: state advances by the golden gamma; returns the next 64-bit output. */
uint64_t prw_stats_rng_next(uint64_t *state);
/* Uniform integer in [0, n) (n >= 1), by rejection (no modulo bias). */
uint64_t prw_stats_rng_below(uint64_t *state, uint64_t n);

typedef struct prw_stats_ratio {
    double ratio;   /* the statistic on the inputs (see the function that fills it) */
    double lo, hi;  /* 2.5th and 97.5th percentiles of the bootstrap distribution */
    int resamples;
} prw_stats_ratio;

/* Bootstrap 95 % interval of median(b) / median(a).  paired requires na == nb.  Returns false when
 * na or nb is 0, resamples < 1, paired with na != nb, or a median of a is 0. */
bool prw_stats_bootstrap_median_ratio(const double *a, size_t na, const double *b, size_t nb, bool paired,
                                      int resamples, uint64_t seed, prw_stats_ratio *out);

/* Bootstrap 95 % interval of the median of the per-pair ratios b[i] / a[i] (n pairs, resampled as
 * pairs).  For interleaved A/B timing this is the robust figure: a pair's two frames see the same
 * scene content and nearly the same machine load, so both cancel in its ratio.  out->ratio is the
 * median of the n ratios.  Returns false when n is 0, resamples < 1 or some a[i] <= 0. */
bool prw_stats_bootstrap_pair_ratio(const double *a, const double *b, size_t n, int resamples, uint64_t seed,
                                    prw_stats_ratio *out);

/* Marks on_front[i] for the Pareto-optimal points (x, y minimised).  Points with a NaN coordinate
 * are never on the front.  Returns the number of points on the front. */
size_t prw_stats_pareto(const double *x, const double *y, size_t n, bool *on_front);

#ifdef __cplusplus
}
#endif
#endif
