/* bench_ab — A/B mode (DESIGN.md §5 "Timing"): configurations A and B on two renderers in one process,
 * interleaved frame by frame, timestamps off.  Pair i renders path frame (i mod frames) with both, in
 * the order A,B on even pairs and B,A on odd ones (so neither always runs second); at least 30 pairs,
 * or one pass over the path when it is longer.  Each renderer first renders --warmup untimed frames.
 * The figure is the median over pairs of B/A (frame times = wall time of prw_renderer_render), with a
 * 95 % interval from a bootstrap over pairs (4000 resamples, seed 1): a pair's frames show the same
 * path frame under nearly the same machine load, so both cancel in its ratio, which the ratio of the
 * two medians does not guarantee on a path whose frame cost varies.  median(A) and median(B) are
 * printed beside it.  Writes ab.csv
 * (pair, frame, a_ms, b_ms) and ab.json in --out; no references are rendered in this mode.
 * After the timing (untimed): B's image against A's at up to AB_IMAGE_FRAMES path frames spread over the
 * sampled ones, LDR-FLIP (metric tone map at the scene camera's EV100, 67 ppd) as the mean over the
 * image and over the pixels where the two differ (what a knob such as mirror_scale or reflection_skip
 * changes: the reflectors' pixels), both renderers being deterministic (no noise to subtract); and in
 * how many of those frames each configuration ran the reflection passes (mirror, mirror_add).
 *
 * The known-slowdown check (`--vs extra_gpu_work=F`, A without extra work): before timing, the
 * replay fraction of B's extra pass (pass_extra_work.c) is calibrated so that the pass takes F x A's
 * GPU frame time (sum of A's pass times), measured with GPU timestamps on CALIB_FRAMES path frames
 * in separate timestamped renderers; CALIB_ROUNDS rounds of proportional correction, the last
 * measured share printed.  The A/B figure, from wall-clock frame times with timestamps off, should
 * then read 1 + F (less the small CPU share of a frame).
 */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_internal.h"

#define AB_MIN_PAIRS 30
#define AB_RESAMPLES 4000
#define AB_SEED 1
#define CALIB_FRAMES 8
#define CALIB_ROUNDS 3
#define AB_IMAGE_FRAMES 4

static double sum_gpu(const prw_frame_stats *st, const char *only)
{
    double t = 0;
    for (uint32_t i = 0; i < st->pass_count; i++)
        if (!st->passes[i].skipped && st->passes[i].gpu_ms > 0 && (!only || strcmp(st->passes[i].name, only) == 0))
            t += st->passes[i].gpu_ms;
    return t;
}

/* See the top: returns the calibrated replay fraction in *fraction and the last measured share. */
static bool calibrate_extra(bench_ctx *c, prw_gpu *gpu, const prw_render_desc *da, const prw_render_desc *db,
                            double *fraction, double *share, prw_error *e)
{
    prw_render_desc ta = *da, tb = *db;
    ta.timestamps = tb.timestamps = true;
    prw_renderer *ra = NULL, *rb = NULL;
    double target = db->quality.extra_gpu_work;
    *fraction = target;
    *share = 0;
    bool ok = prw_renderer_create(gpu, c->scene, &ta, &ra, e) && prw_renderer_create(gpu, c->scene, &tb, &rb, e);
    prw_view v;
    if (ok) ok = bench_frame_view(c, c->frames[0], &v, e) && prw_renderer_render(ra, &v, 1, NULL, e) &&
                 prw_renderer_render(rb, &v, 1, NULL, e); /* warm-up */
    for (int round = 0; ok && round < CALIB_ROUNDS; round++) {
        ok = prw_renderer_set_extra_work(rb, *fraction, e);
        double sa = 0, sx = 0;
        for (uint32_t k = 0; ok && k < CALIB_FRAMES; k++) {
            prw_frame_stats st;
            ok = bench_frame_view(c, c->frames[(size_t)k * c->nframes / CALIB_FRAMES], &v, e) &&
                 prw_renderer_render(ra, &v, 1, &st, e);
            if (ok) sa += sum_gpu(&st, NULL);
            if (ok) ok = prw_renderer_render(rb, &v, 1, &st, e);
            if (ok) sx += sum_gpu(&st, "extra_work");
        }
        if (ok && !(sa > 0 && sx > 0)) ok = prw_fail(e, "bench A/B: calibration: no GPU pass times");
        if (!ok) break;
        *share = sx / sa;
        fprintf(stderr, "bench A/B: calibration round %d: replay fraction %.4f -> extra pass %.2f %% of A's GPU time\n",
                round + 1, *fraction, 100.0 * *share);
        *fraction *= target / *share;
        if (*fraction > 16) *fraction = 16;
    }
    prw_renderer_destroy(ra);
    prw_renderer_destroy(rb);
    return ok;
}

static bool timed_frame(prw_renderer *r, const prw_view *v, double *ms, prw_error *e)
{
    double t0 = prw_now();
    if (!prw_renderer_render(r, v, 1, NULL, e)) return false;
    *ms = (prw_now() - t0) * 1000.0;
    return true;
}

static bool write_ab(const bench_ctx *c, const uint32_t *frames, const double *ta, const double *tb, uint32_t n,
                     const char *a_knobs, const char *b_knobs, const prw_stats_ratio *ratio, prw_error *e)
{
    char path[4200], json[4200];
    bench_join(path, sizeof path, c->o.out_dir, "ab.csv");
    bench_join(json, sizeof json, c->o.out_dir, "ab.json");
    FILE *f = fopen(path, "w");
    if (!f) return prw_fail(e, "%s: cannot write", path);
    for (int i = 0; i < c->res.meta.count; i++) fprintf(f, "# %s: %s\n", c->res.meta.key[i], c->res.meta.value[i]);
    fprintf(f, "# A: %s\n# B: %s\npair,frame,a_ms,b_ms\n", a_knobs, b_knobs);
    for (uint32_t i = 0; i < n; i++) fprintf(f, "%u,%u,%.17g,%.17g\n", i, frames[i], ta[i], tb[i]);
    bool ok = fclose(f) == 0;
    f = fopen(json, "w");
    if (!f) return prw_fail(e, "%s: cannot write", json);
    fprintf(f,
            "{\"prw_bench_ab\": 1, \"a\": \"%s\", \"b\": \"%s\", \"pairs\": %u, \"ratio_b_over_a\": %.17g, "
            "\"ci95\": [%.17g, %.17g], \"median_a_ms\": %.17g, \"median_b_ms\": %.17g, \"resamples\": %d, "
            "\"seed\": %d, \"statistic\": \"median of pair ratios b/a\", \"bootstrap\": \"pairs resampled, percentile interval\"}\n",
            a_knobs, b_knobs, n, ratio->ratio, ratio->lo, ratio->hi, prw_stats_median(ta, n), prw_stats_median(tb, n),
            ratio->resamples, AB_SEED);
    ok = fclose(f) == 0 && ok;
    if (!ok) return prw_fail(e, "%s: write failed", path);
    printf("wrote %s, %s\n", path, json);
    return true;
}

static bool reflection_ran(const prw_frame_stats *st)
{
    for (uint32_t i = 0; i < st->pass_count; i++)
        if (st->passes[i].name && strcmp(st->passes[i].name, "mirror") == 0 && !st->passes[i].skipped) return true;
    return false;
}

/* See the top: B's image against A's after the timing. */
static bool image_diff(bench_ctx *c, prw_renderer *ra, prw_renderer *rb, prw_error *e)
{
    uint32_t k = c->nframes < AB_IMAGE_FRAMES ? c->nframes : AB_IMAGE_FRAMES;
    double flip_sum = 0, changed_flip = 0;
    size_t changed = 0, pixels = 0;
    uint32_t ran_a = 0, ran_b = 0;
    bool ok = true;
    for (uint32_t i = 0; ok && i < k; i++) {
        prw_view v;
        prw_frame_stats sa, sb;
        prw_image ia = {0}, ib = {0}, ta = {0}, tb = {0};
        ok = bench_frame_view(c, c->frames[(size_t)i * c->nframes / k], &v, e) &&
             prw_renderer_render(ra, &v, 1, &sa, e) && prw_renderer_read_hdr(ra, 0, &ia, e) &&
             prw_renderer_render(rb, &v, 1, &sb, e) && prw_renderer_read_hdr(rb, 0, &ib, e) &&
             prw_metric_tonemap(&ia, c->ev100, &ta, e) && prw_metric_tonemap(&ib, c->ev100, &tb, e);
        size_t n = (size_t)ia.width * ia.height;
        float *map = ok ? prw_malloc(n * sizeof *map) : NULL;
        if (ok) ok = prw_flip_ldr_encoded(&tb, &ta, PRW_FLIP_DEFAULT_PPD, map, e);
        if (ok) {
            ran_a += reflection_ran(&sa), ran_b += reflection_ran(&sb);
            for (size_t p = 0; p < n; p++) {
                flip_sum += map[p];
                bool diff = false;
                for (int ch = 0; ch < 3; ch++) diff |= ia.rgba[4 * p + ch] != ib.rgba[4 * p + ch];
                if (diff) changed++, changed_flip += map[p];
            }
            pixels += n;
        }
        free(map);
        prw_image_free(&ia), prw_image_free(&ib), prw_image_free(&ta), prw_image_free(&tb);
    }
    if (ok && pixels)
        printf("A/B: image of B against A (untimed, %u path frames, metric tone map EV100 %.2f, no noise: both "
               "deterministic): LDR-FLIP mean %.4f over the image, %.4f over the %.2f %% of pixels that differ; "
               "reflection passes ran in %u/%u frames of A, %u/%u of B\n",
               k, c->ev100, flip_sum / (double)pixels, changed ? changed_flip / (double)changed : 0.0,
               100.0 * (double)changed / (double)pixels, ran_a, k, ran_b, k);
    return ok;
}

bool bench_run_ab(bench_ctx *c, prw_gpu *gpu, const prw_quality *a, const prw_quality *b, const char *b_text,
                  prw_error *e)
{
    char ka[1024], kb[1024];
    prw_quality_format(a, ka, sizeof ka);
    prw_quality_format(b, kb, sizeof kb);
    bench_machine_meta(&c->res.meta, gpu);
    prw_render_desc da = bench_desc(c, a);
    prw_render_desc db = bench_desc(c, b);
    prw_renderer *ra = NULL, *rb = NULL;
    uint32_t n = c->nframes > AB_MIN_PAIRS ? c->nframes : AB_MIN_PAIRS;
    double *ta = prw_calloc(n, sizeof *ta), *tb = prw_calloc(n, sizeof *tb);
    uint32_t *fr = prw_calloc(n, sizeof *fr);
    bool ok = true;
    double calib_fraction = 0, calib_share = 0;
    bool calib = db.quality.extra_gpu_work > 0 && !(da.quality.extra_gpu_work > 0);
    if (calib) ok = calibrate_extra(c, gpu, &da, &db, &calib_fraction, &calib_share, e);
    ok = ok && prw_renderer_create(gpu, c->scene, &da, &ra, e) && prw_renderer_create(gpu, c->scene, &db, &rb, e);
    if (ok && calib) ok = prw_renderer_set_extra_work(rb, calib_fraction, e);
    prw_view v;
    if (ok) ok = bench_frame_view(c, c->frames[0], &v, e);
    for (long w = 0; ok && w < c->o.warmup; w++) ok = prw_renderer_render(ra, &v, 1, NULL, e) && prw_renderer_render(rb, &v, 1, NULL, e);
    fprintf(stderr, "bench A/B: A = %s\n           B = %s (%s)\n", ka, kb, b_text);
    for (uint32_t i = 0; ok && i < n; i++) {
        fr[i] = c->frames[i % c->nframes];
        ok = bench_frame_view(c, fr[i], &v, e);
        if (ok && i % 2 == 0) ok = timed_frame(ra, &v, &ta[i], e) && timed_frame(rb, &v, &tb[i], e);
        else if (ok) ok = timed_frame(rb, &v, &tb[i], e) && timed_frame(ra, &v, &ta[i], e);
        fprintf(stderr, "\rframes: %u/%u pairs   ", i + 1, n);
        fflush(stderr);
    }
    fprintf(stderr, "\n");
    if (ok) ok = image_diff(c, ra, rb, e);
    prw_renderer_destroy(ra);
    prw_renderer_destroy(rb);
    prw_stats_ratio ratio;
    if (ok && !prw_stats_bootstrap_pair_ratio(ta, tb, n, AB_RESAMPLES, AB_SEED, &ratio))
        ok = prw_fail(e, "bench A/B: no ratio (zero frame times)");
    if (ok && prw_gpu_validation_count(gpu) != 0)
        ok = prw_fail(e, "%u Vulkan validation messages (see above)", prw_gpu_validation_count(gpu));
    if (ok) ok = write_ab(c, fr, ta, tb, n, ka, kb, &ratio, e);
    if (ok)
        printf("A/B: B/A = %.3f (median of pair ratios), 95 %% interval [%.3f, %.3f] (median frame time A %.2f ms, B %.2f ms; %u interleaved "
               "frames each at %ux%u; bootstrap over pairs, %d resamples, seed %d; B = %s)\n",
               ratio.ratio, ratio.lo, ratio.hi, prw_stats_median(ta, n), prw_stats_median(tb, n), n, c->o.width,
               c->o.height, AB_RESAMPLES, AB_SEED, b_text);
    if (ok && calib)
        printf("A/B: known slowdown: B's extra pass calibrated to %.1f %% of A's GPU frame time (timestamps, %d frames; "
               "replay fraction %.4f): expected B/A = %.3f\n",
               100.0 * calib_share, CALIB_FRAMES, calib_fraction, 1.0 + db.quality.extra_gpu_work);
    free(ta);
    free(tb);
    free(fr);
    return ok;
}
