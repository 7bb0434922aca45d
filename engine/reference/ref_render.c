/* ref_render.c — renders a tile over a sample range with a pool of pthreads (prw_threads budget):
 * sample batches (each a contiguous sample range for every pixel of the tile) are split into 8x8
 * pixel blocks handed out by an atomic counter; each pixel's samples go straight into its
 * fixed-point accumulator, so the result does not depend on the thread count or the batching. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "ref_internal.h"

#define BLOCK 8

typedef struct job {
    const prw_ref_renderer *r;
    const prw_view *v;
    const prw_ref_desc *d;
    prw_ref_acc *acc;
    uint64_t b0, b1; /* this batch's samples */
    uint32_t bw, bh; /* blocks across / down the tile */
    atomic_uint next_block;
    atomic_uint_fast64_t done; /* pixel samples, this render */
    atomic_uint_fast64_t rays;
    atomic_uint_fast64_t nonfinite;
    atomic_int workers_left;
    pthread_mutex_t mu; /* with cv: the last worker of a batch wakes the main thread */
    pthread_cond_t cv;
} job;

/* An integral double to the accumulator type: through int64 where it fits (the library's
 * double -> int128 conversion is a call), the same value either way. */
static inline prw_ref_fixed to_fixed(double x)
{
    return fabs(x) < 0x1p62 ? (prw_ref_fixed)(int64_t)x : (prw_ref_fixed)x;
}

static inline void acc_add(prw_ref_acc *a, size_t idx, const double v[3], uint64_t *nonfinite)
{
    bool ok = true;
    for (int c = 0; c < 3; c++) ok = ok && isfinite(v[c]) && fabs(v[c]) < 1e24;
    if (!ok) {
        (*nonfinite)++;
        return;
    }
    for (int c = 0; c < 3; c++) {
        a->sum[3 * idx + c] += to_fixed(nearbyint(v[c] * PRW_REF_SUM_SCALE));
        a->sq[3 * idx + c] += to_fixed(nearbyint(v[c] * v[c] * PRW_REF_SQ_SCALE));
    }
}

static void *worker(void *arg)
{
    job *j = arg;
    const prw_ref_renderer *r = j->r;
    prw_ref_acc *a = j->acc;
    uint32_t tw = a->x1 - a->x0;
    uint64_t rays = 0, nonfinite = 0;
    for (;;) {
        unsigned b = atomic_fetch_add(&j->next_block, 1u);
        if (b >= j->bw * j->bh) break;
        uint32_t bx = a->x0 + (b % j->bw) * BLOCK, by = a->y0 + (b / j->bw) * BLOCK;
        uint32_t ex = PRW_MIN(bx + BLOCK, a->x1), ey = PRW_MIN(by + BLOCK, a->y1);
        for (uint32_t y = by; y < ey; y++)
            for (uint32_t x = bx; x < ex; x++) {
                uint64_t pix = (uint64_t)y * a->width + x;
                size_t idx = (size_t)(y - a->y0) * tw + (x - a->x0);
                for (uint64_t s = j->b0; s < j->b1; s++) {
                    ref_rng rng = ref_rng_make(a->seed, pix, s);
                    double jx, jy;
                    ref_pixel_jitter(a->seed, pix, s, &jx, &jy);
                    rng.dim = 2; /* dimensions 0, 1 were the jitter's; the path's stay where they were */
                    double L[3];
                    ref_trace_sample(r, j->v, a->filter, x + jx, y + jy, &rng, L, &rays);
                    acc_add(a, idx, L, &nonfinite);
                }
            }
        atomic_fetch_add(&j->done, (uint64_t)(ex - bx) * (ey - by) * (j->b1 - j->b0));
    }
    atomic_fetch_add(&j->rays, rays);
    atomic_fetch_add(&j->nonfinite, nonfinite);
    pthread_mutex_lock(&j->mu);
    if (atomic_fetch_sub(&j->workers_left, 1) == 1) pthread_cond_signal(&j->cv);
    pthread_mutex_unlock(&j->mu);
    return NULL;
}

void prw_ref_acc_free(prw_ref_acc *a)
{
    if (!a) return;
    free(a->sum);
    free(a->sq);
    a->sum = a->sq = NULL;
}

/* Waits until the workers are done or `s` seconds pass. */
static void wait_workers(job *j, double s)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    long ns = ts.tv_nsec + (long)(s * 1e9);
    ts.tv_sec += ns / 1000000000L;
    ts.tv_nsec = ns % 1000000000L;
    pthread_mutex_lock(&j->mu);
    while (atomic_load(&j->workers_left) > 0)
        if (pthread_cond_timedwait(&j->cv, &j->mu, &ts) != 0) break;
    pthread_mutex_unlock(&j->mu);
}

uint64_t prw_ref_memory_bytes(uint32_t width, uint32_t height, uint64_t tile_pixels, bool exr)
{
    uint64_t b = prw_mul_sat(tile_pixels, 6 * sizeof(prw_ref_fixed));
    if (exr) b = prw_add_sat(b, prw_mul_sat((uint64_t)width * height, 48));
    return b;
}

bool prw_ref_render(prw_ref_renderer *r, const prw_view *view, const prw_ref_desc *d, prw_ref_acc *acc,
                    prw_ref_stats *stats, prw_error *e)
{
    memset(acc, 0, sizeof *acc);
    if (stats) memset(stats, 0, sizeof *stats);
    if (view->width == 0 || view->height == 0 || (uint64_t)view->width * view->height > ((uint64_t)1 << 28))
        return prw_fail(e, "reference: image size %ux%u is empty or too large", view->width, view->height);
    uint32_t x0 = d->x0, y0 = d->y0, x1 = d->x1, y1 = d->y1;
    if (x0 == 0 && y0 == 0 && x1 == 0 && y1 == 0) x1 = view->width, y1 = view->height;
    if (!(x0 < x1 && y0 < y1 && x1 <= view->width && y1 <= view->height))
        return prw_fail(e, "reference: tile %u,%u,%u,%u is empty or outside the %ux%u image", x0, y0, x1, y1,
                        view->width, view->height);
    if (!(d->s1 > d->s0) || d->s1 - d->s0 > PRW_REF_MAX_SPP)
        return prw_fail(e, "reference: sample range [%llu, %llu) must hold 1..%llu samples", (unsigned long long)d->s0,
                        (unsigned long long)d->s1, (unsigned long long)PRW_REF_MAX_SPP);
    if ((unsigned)d->filter.kind >= PRW_REF_FILTER_COUNT)
        return prw_fail(e, "reference: unknown light-path filter %d", (int)d->filter.kind);
    int threads = d->threads > 0 ? d->threads : r->threads;
    if (threads < 1) threads = 1;

    acc->width = view->width;
    acc->height = view->height;
    acc->x0 = x0, acc->y0 = y0, acc->x1 = x1, acc->y1 = y1;
    acc->s0 = acc->s1 = d->s0;
    acc->seed = d->seed;
    acc->scene_hash = prw_scene_hash(r->scene);
    acc->material_hash = prw_ref_material_hash();
    acc->filter = d->filter;
    acc->ev100 = view->ev100;
    size_t npix = (size_t)(x1 - x0) * (y1 - y0);
    if (!prw_mem_check(prw_mul_sat(npix, 6 * sizeof(prw_ref_fixed)), "reference", "the accumulation of the tile", e)) {
        memset(acc, 0, sizeof *acc);
        return false;
    }
    acc->sum = prw_calloc(3 * npix, sizeof(prw_ref_fixed));
    acc->sq = prw_calloc(3 * npix, sizeof(prw_ref_fixed));

    job j;
    memset(&j, 0, sizeof j);
    j.r = r;
    j.v = view;
    j.d = d;
    j.acc = acc;
    j.bw = (x1 - x0 + BLOCK - 1) / BLOCK;
    j.bh = (y1 - y0 + BLOCK - 1) / BLOCK;
    atomic_init(&j.done, 0);
    atomic_init(&j.rays, 0);
    atomic_init(&j.nonfinite, 0);
    pthread_mutex_init(&j.mu, NULL);
    pthread_cond_init(&j.cv, NULL);

    const uint64_t total = (uint64_t)npix * (d->s1 - d->s0);
    double t0 = prw_now(), last_report = -1;
    uint64_t s = d->s0, batch = 1;
    pthread_t *tid = prw_calloc((size_t)threads, sizeof(pthread_t));
    bool limited = false;
    while (s < d->s1) {
        uint64_t n = PRW_MIN(batch, d->s1 - s);
        double elapsed = prw_now() - t0;
        if (d->time_limit_s > 0 && s > d->s0) {
            /* a batch that would overrun the limit (by the rate so far) is shortened */
            double per_sample = elapsed / (double)(s - d->s0);
            double left = d->time_limit_s - elapsed;
            uint64_t fit = per_sample > 0 ? (uint64_t)fmax(1.0, floor(left / per_sample)) : n;
            n = PRW_MIN(n, fit);
        }
        j.b0 = s;
        j.b1 = s + n;
        atomic_init(&j.next_block, 0u);
        atomic_init(&j.workers_left, threads);
        int started = 0;
        for (int t = 0; t < threads; t++) {
            if (pthread_create(&tid[t], NULL, worker, &j) != 0) break;
            started++;
        }
        if (started < threads) {
            pthread_mutex_lock(&j.mu);
            atomic_fetch_sub(&j.workers_left, threads - started);
            pthread_mutex_unlock(&j.mu);
        }
        if (started == 0) { /* no threads available: work here */
            atomic_store(&j.workers_left, 1);
            worker(&j);
        }
        while (atomic_load(&j.workers_left) > 0) {
            wait_workers(&j, 0.25);
            double now = prw_now() - t0;
            if (d->progress && now - last_report >= 0.25) {
                last_report = now;
                prw_ref_progress p = {atomic_load(&j.done), total, s - d->s0, now, -1};
                if (p.done > 0) p.eta_s = now * (double)(total - p.done) / (double)p.done;
                d->progress(d->user, &p);
            }
        }
        for (int t = 0; t < started; t++) pthread_join(tid[t], NULL);
        s += n;
        acc->s1 = s;
        if (batch < 64) batch *= 2;
        if (d->time_limit_s > 0 && prw_now() - t0 >= d->time_limit_s && s < d->s1) {
            limited = true;
            break;
        }
    }
    free(tid);
    pthread_mutex_destroy(&j.mu);
    pthread_cond_destroy(&j.cv);
    double secs = prw_now() - t0;
    acc->nonfinite = atomic_load(&j.nonfinite);
    if (d->progress) {
        prw_ref_progress p = {atomic_load(&j.done), total, acc->s1 - acc->s0, secs, 0};
        d->progress(d->user, &p);
    }
    if (stats) {
        stats->spp = acc->s1 - acc->s0;
        stats->rays = atomic_load(&j.rays);
        stats->seconds = secs;
        stats->time_limited = limited;
        stats->tess_px = ref_nurbs_px(r, view);
    }
    return true;
}
