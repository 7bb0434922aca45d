/* bench_run — phases 2 and 3 of prw bench, per configuration:
 *   timed run: warm-up frames (not recorded), then this shard's frames with timestamps off.  Per
 *     frame: frame_ms = wall time from this frame's start to the next one's (view evaluation, the
 *     renderer's record + submit + wait, the stats and memory queries), cpu_ms = the renderer's own
 *     record + submit + wait time, triangles, draws, and the allocator's live bytes after the frame.
 *   timestamped run: a second renderer with timestamps on (each timestamp flushes on lavapipe, so
 *     its frame times are not used); per-pass GPU times, and at the sampled frames the raster HDR
 *     image read back and compared with reference A.  Reading back is why errors come from this run:
 *     the timed run is never disturbed by readbacks or metric computations.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "bench_internal.h"

static bool warm_up(bench_ctx *c, prw_renderer *r, long frames, prw_error *e)
{
    prw_view v;
    if (!bench_frame_view(c, c->frames[0], &v, e)) return false;
    for (long i = 0; i < frames; i++)
        if (!prw_renderer_render(r, &v, 1, NULL, e)) return false;
    return true;
}

bool bench_run_timed(bench_ctx *c, prw_gpu *gpu, prw_error *e)
{
    bench_result *res = &c->res;
    for (uint32_t ci = 0; ci < res->config_count; ci++) {
        prw_render_desc d = bench_desc(c, &res->configs[ci].q);
        prw_renderer *r = NULL;
        if (!prw_renderer_create(gpu, c->scene, &d, &r, e)) return prw_fail_wrap(e, "config %u", ci);
        bool ok = warm_up(c, r, c->o.warmup, e);
        double prev_start = 0;
        size_t prev = SIZE_MAX; /* row index (rows may move while the table grows) */
        for (uint32_t i = 0; ok && i < c->nframes; i++) {
            uint32_t k = c->frames[i];
            double start = prw_now();
            if (prev != SIZE_MAX) res->rows[prev].frame_ms = (start - prev_start) * 1000.0;
            prw_view v;
            prw_frame_stats st;
            ok = bench_frame_view(c, k, &v, e) && prw_renderer_render(r, &v, 1, &st, e);
            if (!ok) break;
            prw_mem_stats ms;
            prw_gpu_mem_stats(gpu, &ms);
            bench_row *row = bench_result_row(res, ci, k);
            row->t_s = prw_camera_path_frame_time(&c->path, k);
            row->cpu_ms = st.cpu_ms;
            row->triangles = st.triangles;
            row->draws = st.draws;
            row->mem_used = ms.used_bytes;
            row->ref = c->is_ref[k];
            prev = (size_t)(row - res->rows);
            prev_start = start;
            if (i + 1 == c->nframes || (i + 1) % 10 == 0) {
                fprintf(stderr, "\rframes: config %u/%u  %u/%u timed   ", ci + 1, res->config_count, i + 1, c->nframes);
                fflush(stderr);
            }
        }
        /* the last frame ends when the loop does: its frame_ms is its own duration */
        if (ok && prev != SIZE_MAX) res->rows[prev].frame_ms = (prw_now() - prev_start) * 1000.0;
        prw_renderer_destroy(r);
        if (!ok) return prw_fail_wrap(e, "config %u", ci);
    }
    fprintf(stderr, "\n");
    return true;
}

static int pass_column(bench_result *res, const char *name)
{
    for (uint32_t i = 0; i < res->pass_count; i++)
        if (strcmp(res->pass_names[i], name) == 0) return (int)i;
    if (res->pass_count == BENCH_MAX_PASS_NAMES) return -1;
    snprintf(res->pass_names[res->pass_count], sizeof res->pass_names[0], "%s", name);
    return (int)res->pass_count++;
}

static bool measure_error(bench_ctx *c, prw_renderer *r, uint32_t k, bench_row *row, prw_error *e)
{
    prw_image hdr = {0};
    if (!prw_renderer_read_hdr(r, 0, &hdr, e)) return false;
    prw_compare_opts co = {.ev100 = c->ev100};
    prw_compare_metrics m;
    bool ok = prw_compare_images(&hdr, &c->ref_a[k], &co, &m, NULL, NULL, e);
    prw_image_free(&hdr);
    if (!ok) return false;
    row->err = (bench_err){m.ldr_flip.mean, m.hdr_flip.mean, m.basic.psnr, m.ssim};
    row->noise = c->noise[k];
    return true;
}

bool bench_run_timestamped(bench_ctx *c, prw_gpu *gpu, prw_error *e)
{
    bench_result *res = &c->res;
    for (uint32_t ci = 0; ci < res->config_count; ci++) {
        prw_render_desc d = bench_desc(c, &res->configs[ci].q);
        d.timestamps = true;
        prw_renderer *r = NULL;
        if (!prw_renderer_create(gpu, c->scene, &d, &r, e)) return prw_fail_wrap(e, "config %u (timestamps)", ci);
        bool ok = warm_up(c, r, c->o.warmup > 0 ? 1 : 0, e);
        for (uint32_t i = 0; ok && i < c->nframes; i++) {
            uint32_t k = c->frames[i];
            prw_view v;
            prw_frame_stats st;
            ok = bench_frame_view(c, k, &v, e) && prw_renderer_render(r, &v, 1, &st, e);
            if (!ok) break;
            bench_row *row = bench_result_row(res, ci, k);
            for (uint32_t p = 0; p < st.pass_count; p++) {
                int col = pass_column(res, st.passes[p].name);
                if (col >= 0) row->pass_ms[col] = st.passes[p].skipped ? NAN : st.passes[p].gpu_ms;
            }
            double b, fl;
            if (prw_frame_stats_base_floor(&st, &b, &fl)) row->base_ms = b, row->floor_ms = fl;
            if (c->is_ref[k]) ok = measure_error(c, r, k, row, e);
            if (i + 1 == c->nframes || (i + 1) % 10 == 0) {
                fprintf(stderr, "\rframes: config %u/%u  %u/%u with timestamps   ", ci + 1, res->config_count, i + 1,
                        c->nframes);
                fflush(stderr);
            }
        }
        prw_renderer_destroy(r);
        if (!ok) return prw_fail_wrap(e, "config %u (timestamps)", ci);
    }
    fprintf(stderr, "\n");
    return true;
}
