/* ref_rays.c — the path integrator along caller-given rays (prw_ref_trace_rays) with a pool of
 * pthreads (the renderer's thread budget): blocks of rays handed out by an atomic counter, each
 * ray's samples summed in its own fixed-point accumulator (the rules of ref_render.c), so the
 * result does not depend on the thread count. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "ref_internal.h"

#define RAY_BLOCK 32

typedef struct ray_job {
    const prw_ref_renderer *r;
    const prw_ref_ray *rays;
    size_t n;
    const prw_ref_ray_desc *d;
    prw_ref_ray_result *out;
    atomic_size_t next;
    atomic_uint_fast64_t traced, nonfinite;
} ray_job;

static inline prw_ref_fixed to_fixed(double x)
{
    return fabs(x) < 0x1p62 ? (prw_ref_fixed)(int64_t)x : (prw_ref_fixed)x;
}

static void one_ray(ray_job *j, size_t i, uint64_t *traced, uint64_t *nonfinite)
{
    const prw_ref_renderer *r = j->r;
    const prw_ref_ray *ray = &j->rays[i];
    double o[3] = {ray->origin.x - r->origin.x, ray->origin.y - r->origin.y, ray->origin.z - r->origin.z};
    double d[3] = {ray->dir.x, ray->dir.y, ray->dir.z};
    double l2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    if (fabs(l2 - 1) > 1e-12) {
        double l = sqrt(l2);
        for (int c = 0; c < 3; c++) d[c] /= l;
    }
    prw_ref_fixed sum[3] = {0, 0, 0}, sq[3] = {0, 0, 0};
    uint64_t backs = 0;
    for (uint64_t s = j->d->s0; s < j->d->s1; s++) {
        ref_rng rng = ref_rng_make(j->d->seed, j->d->first_index + i, s);
        rng.dim = 2; /* as a pixel's path: dimensions 0, 1 are the pixel jitter's */
        double L[3];
        bool back = false;
        ref_trace_ray(r, o, d, ray->tnear, j->d->camera, j->d->filter, &rng, L, traced, &back);
        backs += back;
        bool ok = true;
        for (int c = 0; c < 3; c++) ok = ok && isfinite(L[c]) && fabs(L[c]) < 1e24;
        if (!ok) { /* dropped: counts as 0, as in prw_ref_render */
            (*nonfinite)++;
            continue;
        }
        for (int c = 0; c < 3; c++) {
            sum[c] += to_fixed(nearbyint(L[c] * PRW_REF_SUM_SCALE));
            sq[c] += to_fixed(nearbyint(L[c] * L[c] * PRW_REF_SQ_SCALE));
        }
    }
    j->out[i].back_faces = backs;
    double n = (double)(j->d->s1 - j->d->s0);
    for (int c = 0; c < 3; c++) {
        double m = (double)sum[c] / PRW_REF_SUM_SCALE / n;
        double m2 = (double)sq[c] / PRW_REF_SQ_SCALE / n;
        j->out[i].mean[c] = m;
        j->out[i].var_mean[c] = n > 1 ? fmax(m2 - m * m, 0.0) * n / (n - 1) / n : 0;
    }
}

static void *ray_worker(void *arg)
{
    ray_job *j = arg;
    uint64_t traced = 0, nonfinite = 0;
    for (;;) {
        size_t b = atomic_fetch_add(&j->next, (size_t)1);
        size_t i0 = b * RAY_BLOCK;
        if (i0 >= j->n) break;
        size_t i1 = PRW_MIN(i0 + RAY_BLOCK, j->n);
        for (size_t i = i0; i < i1; i++) one_ray(j, i, &traced, &nonfinite);
    }
    atomic_fetch_add(&j->traced, traced);
    atomic_fetch_add(&j->nonfinite, nonfinite);
    return NULL;
}

bool prw_ref_trace_rays(const prw_ref_renderer *r, const prw_ref_ray *rays, size_t n, const prw_ref_ray_desc *d,
                        prw_ref_ray_result *out, uint64_t *rays_traced, uint64_t *nonfinite, prw_error *e)
{
    if (rays_traced) *rays_traced = 0;
    if (nonfinite) *nonfinite = 0;
    if ((uint64_t)n > ((uint64_t)1 << 32)) return prw_fail(e, "reference: %zu rays in one call (at most 2^32)", n);
    if (!(d->s1 > d->s0) || d->s1 - d->s0 > PRW_REF_MAX_SPP)
        return prw_fail(e, "reference: sample range [%llu, %llu) must hold 1..%llu samples", (unsigned long long)d->s0,
                        (unsigned long long)d->s1, (unsigned long long)PRW_REF_MAX_SPP);
    if ((unsigned)d->filter.kind >= PRW_REF_FILTER_COUNT)
        return prw_fail(e, "reference: unknown light-path filter %d", (int)d->filter.kind);
    for (size_t i = 0; i < n; i++) {
        const prw_ref_ray *q = &rays[i];
        double l2 = q->dir.x * q->dir.x + q->dir.y * q->dir.y + q->dir.z * q->dir.z;
        if (!(isfinite(q->origin.x) && isfinite(q->origin.y) && isfinite(q->origin.z) && isfinite(l2) && l2 > 0 &&
              isfinite(q->tnear) && q->tnear >= 0))
            return prw_fail(e, "reference: ray %zu has a non-finite origin, a zero or non-finite direction or a "
                               "negative tnear", i);
    }
    if (n == 0) return true;
    ray_job j;
    memset(&j, 0, sizeof j);
    j.r = r;
    j.rays = rays;
    j.n = n;
    j.d = d;
    j.out = out;
    atomic_init(&j.next, (size_t)0);
    atomic_init(&j.traced, 0);
    atomic_init(&j.nonfinite, 0);
    int threads = d->threads > 0 ? d->threads : r->threads;
    size_t blocks = (n + RAY_BLOCK - 1) / RAY_BLOCK;
    if (threads < 1) threads = 1;
    if ((size_t)threads > blocks) threads = (int)blocks;
    pthread_t *tid = prw_calloc((size_t)threads, sizeof(pthread_t));
    int started = 0;
    for (int t = 1; t < threads; t++) {
        if (pthread_create(&tid[t], NULL, ray_worker, &j) != 0) break;
        started++;
    }
    ray_worker(&j); /* this thread works too */
    for (int t = 1; t <= started; t++) pthread_join(tid[t], NULL);
    free(tid);
    if (rays_traced) *rays_traced = atomic_load(&j.traced);
    if (nonfinite) *nonfinite = atomic_load(&j.nonfinite);
    return true;
}

prw_ref_ray prw_ref_camera_ray(const prw_ref_renderer *r, const prw_view *view, uint64_t seed, uint32_t x, uint32_t y,
                               uint64_t s)
{
    double jx, jy;
    ref_pixel_jitter(seed, (uint64_t)y * view->width + x, s, &jx, &jy);
    double o[3], d[3], tnear;
    ref_camera_ray(r, view, x + jx, y + jy, o, d, &tnear);
    prw_ref_ray ray;
    (void)o;
    ray.origin = view->eye; /* o = eye - r->origin: prw_ref_trace_rays recomputes exactly these bits */
    ray.dir = prw_v3(d[0], d[1], d[2]);
    ray.tnear = tnear;
    return ray;
}
