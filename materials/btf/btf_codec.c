/* btf_codec.c — the BTF codecs, the decode definition and the error figures (prw_btf_codec.h). */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "btf_linalg.h"
#include "prw_btf_codec.h"

static uint16_t h16(double v) { return prw_btf_float_to_half((float)v); }

/* prw_btf_half_to_float of every half, for the decode (the path tracer decodes ~100 halves per shading
 * point: the conversion was a third of its instructions); filled once, the same values to the bit. */
static float half_table[65536];
/* filled before main: every decode path reads it, and a path that forgot to fill it first read zeros
 * (SPARSE's residuals, f376c19) */
static void half_fill(void) __attribute__((constructor));
static void half_fill(void)
{
    for (uint32_t h = 0; h < 65536; h++) half_table[h] = prw_btf_half_to_float((uint16_t)h);
}

static void progress(const prw_btf_codec_params *p, const char *stage, double f)
{
    if (p->progress) p->progress(p->user, stage, f);
}

/* A as D x N: row d = (v * lights + l) * 3 + c, column t = texel. */
static btf_mat whole(const prw_btf *a)
{
    uint64_t n = (uint64_t)a->width * a->height;
    return (btf_mat){.base = a->rgb, .m = (uint64_t)a->views * a->lights * 3, .n = n, .rd = 3, .r1 = n * 3, .r2 = 1,
                     .cd = 1, .c1 = 3, .c2 = 0};
}

void prw_btf_packed_free(prw_btf_packed *p)
{
    if (!p) return;
    free(p->view_dirs), free(p->light_dirs), free(p->u), free(p->w), free(p->mean), free(p->basis), free(p->index);
    free(p->sp_start), free(p->sp_pair), free(p->sp_val);
    memset(p, 0, sizeof *p);
}

static void copy_dirs(const prw_btf *a, prw_btf_packed *p)
{
    p->width = a->width, p->height = a->height, p->views = a->views, p->lights = a->lights;
    p->view_dirs = prw_malloc(sizeof(float) * 2 * a->views);
    p->light_dirs = prw_malloc(sizeof(float) * 2 * a->lights);
    memcpy(p->view_dirs, a->view_dirs, sizeof(float) * 2 * a->views);
    memcpy(p->light_dirs, a->light_dirs, sizeof(float) * 2 * a->lights);
}

static bool fmf(const prw_btf *a, const prw_btf_codec_params *p, prw_btf_packed *out, prw_error *e)
{
    btf_mat m = whole(a);
    uint32_t k = p->components;
    if (k < 1 || k > m.m || k > m.n) return prw_fail(e, "btf fmf: %u components for %llu x %llu", k, (unsigned long long)m.m, (unsigned long long)m.n);
    double *u = prw_malloc(sizeof(double) * m.m * k), *s = prw_malloc(sizeof(double) * k), *v = prw_malloc(sizeof(double) * m.n * k);
    progress(p, "fmf: svd", 0);
    bool ok = btf_svd(&m, k, 8, p->power ? p->power : 2, p->seed, p->threads, u, s, v, e);
    if (ok) {
        /* balanced for half floats: W ~ 1 per entry, U carries the values' magnitude */
        double sq = sqrt((double)m.n);
        out->u = prw_malloc(sizeof(uint16_t) * m.m * k);
        out->w = prw_malloc(sizeof(uint16_t) * m.n * k);
        for (uint64_t i = 0; i < m.m * k; i++) out->u[i] = h16(u[i] * s[i % k] / sq);
        for (uint64_t i = 0; i < m.n * k; i++) out->w[i] = h16(v[i] * sq);
    }
    free(u), free(s), free(v);
    progress(p, "fmf: svd", 1);
    return ok;
}

typedef struct assign_ctx {
    const double *pts; /* N x dim */
    const double *cent; /* c x dim */
    uint32_t dim, c;
    uint32_t *idx;
    double *dist;
} assign_ctx;

static void assign_part(void *user, uint64_t b, uint64_t e)
{
    assign_ctx *x = user;
    for (uint64_t t = b; t < e; t++) {
        double best = DBL_MAX;
        uint32_t bi = 0;
        for (uint32_t i = 0; i < x->c; i++) {
            double d = 0;
            for (uint32_t k = 0; k < x->dim; k++) {
                double q = x->pts[t * x->dim + k] - x->cent[i * x->dim + k];
                d += q * q;
            }
            if (d < best) best = d, bi = i;
        }
        x->idx[t] = bi;
        x->dist[t] = best;
    }
}

static double urand(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) * 0x1.0p-53;
}

/* k-means (k-means++ seeding, Lloyd iterations) of N points of dimension dim into c clusters. */
static void kmeans(const double *pts, uint64_t n, uint32_t dim, uint32_t c, uint32_t iters, uint64_t seed, int threads,
                   uint32_t *idx, const prw_btf_codec_params *p)
{
    double *cent = prw_calloc((size_t)c * dim, sizeof(double)), *dist = prw_malloc(sizeof(double) * n);
    uint64_t st = seed * 2862933555777941757ull + 3037000493ull;
    uint64_t first = (uint64_t)(urand(&st) * (double)n) % n;
    memcpy(cent, pts + first * dim, sizeof(double) * dim);
    for (uint64_t t = 0; t < n; t++) dist[t] = DBL_MAX;
    for (uint32_t i = 1; i < c; i++) {
        double total = 0;
        for (uint64_t t = 0; t < n; t++) {
            double d = 0;
            for (uint32_t k = 0; k < dim; k++) {
                double q = pts[t * dim + k] - cent[(i - 1) * dim + k];
                d += q * q;
            }
            if (d < dist[t]) dist[t] = d;
            total += dist[t];
        }
        uint64_t pick = 0;
        if (total > 0) {
            double r = urand(&st) * total, acc = 0;
            for (pick = 0; pick + 1 < n; pick++) {
                acc += dist[pick];
                if (acc > r) break;
            }
        } else {
            pick = (uint64_t)(urand(&st) * (double)n) % n;
        }
        memcpy(cent + (size_t)i * dim, pts + pick * dim, sizeof(double) * dim);
    }
    uint64_t *count = prw_malloc(sizeof(uint64_t) * c);
    for (uint32_t it = 0; it < iters; it++) {
        assign_ctx x = {pts, cent, dim, c, idx, dist};
        btf_parallel(n, threads, assign_part, &x);
        memset(cent, 0, sizeof(double) * c * dim);
        memset(count, 0, sizeof(uint64_t) * c);
        for (uint64_t t = 0; t < n; t++) {
            count[idx[t]]++;
            for (uint32_t k = 0; k < dim; k++) cent[idx[t] * dim + k] += pts[t * dim + k];
        }
        for (uint32_t i = 0; i < c; i++) {
            if (count[i]) {
                for (uint32_t k = 0; k < dim; k++) cent[i * dim + k] /= (double)count[i];
            } else { /* an empty cluster takes the point farthest from its centre */
                uint64_t far = 0;
                for (uint64_t t = 1; t < n; t++)
                    if (dist[t] > dist[far]) far = t;
                memcpy(cent + (size_t)i * dim, pts + far * dim, sizeof(double) * dim);
                dist[far] = 0;
            }
        }
        progress(p, "cluster: k-means", (double)(it + 1) / iters);
    }
    assign_ctx x = {pts, cent, dim, c, idx, dist};
    btf_parallel(n, threads, assign_part, &x);
    free(cent), free(dist), free(count);
}

static bool cluster(const prw_btf *a, const prw_btf_codec_params *p, prw_btf_packed *out, prw_error *e)
{
    btf_mat m = whole(a);
    uint64_t D = m.m, N = m.n;
    uint32_t c = p->clusters, k = p->components;
    if (c < 1 || c > N) return prw_fail(e, "btf cluster: %u clusters for %llu texels", c, (unsigned long long)N);
    if (k > D) return prw_fail(e, "btf cluster: %u components for %llu directions", k, (unsigned long long)D);
    /* the texels' coordinates in the leading components of the whole BTF */
    uint32_t dim = (uint32_t)PRW_MIN((uint64_t)16, PRW_MIN(D, N));
    double *u = prw_malloc(sizeof(double) * D * dim), *s = prw_malloc(sizeof(double) * dim),
           *v = prw_malloc(sizeof(double) * N * dim);
    progress(p, "cluster: svd", 0);
    if (!btf_svd(&m, dim, 8, p->power ? p->power : 2, p->seed, p->threads, u, s, v, e)) {
        free(u), free(s), free(v);
        return false;
    }
    for (uint64_t t = 0; t < N; t++)
        for (uint32_t j = 0; j < dim; j++) v[t * dim + j] *= s[j];
    free(u), free(s);
    out->index = prw_malloc(sizeof(uint32_t) * N);
    kmeans(v, N, dim, c, p->kmeans_iterations ? p->kmeans_iterations : 20, p->seed, p->threads, out->index, p);
    free(v);
    /* per cluster: its texels, the mean ABRDF, the local principal components */
    uint32_t *order = prw_malloc(sizeof(uint32_t) * N);
    uint64_t *start = prw_calloc((size_t)c + 1, sizeof(uint64_t));
    for (uint64_t t = 0; t < N; t++) start[out->index[t] + 1]++;
    for (uint32_t i = 0; i < c; i++) start[i + 1] += start[i];
    uint64_t *fill = prw_malloc(sizeof(uint64_t) * c);
    memcpy(fill, start, sizeof(uint64_t) * c);
    for (uint64_t t = 0; t < N; t++) order[fill[out->index[t]]++] = (uint32_t)t;
    free(fill);
    out->mean = prw_calloc((size_t)c * D, sizeof(uint16_t));
    out->basis = prw_calloc((size_t)c * (k ? k : 1) * D, sizeof(uint16_t));
    out->w = prw_calloc((size_t)N * (k ? k : 1), sizeof(uint16_t));
    double *mean = prw_malloc(sizeof(double) * D);
    bool ok = true;
    double sd = sqrt((double)D);
    for (uint32_t i = 0; ok && i < c; i++) {
        uint64_t n_i = start[i + 1] - start[i];
        const uint32_t *rows = order + start[i];
        for (uint64_t d = 0; d < D; d++) {
            double sum = 0;
            for (uint64_t r = 0; r < n_i; r++) sum += btf_mat_at(&m, d, rows[r]);
            mean[d] = n_i ? sum / (double)n_i : 0;
            out->mean[(uint64_t)i * D + d] = h16(mean[d]);
        }
        uint32_t ki = (uint32_t)PRW_MIN((uint64_t)k, n_i);
        if (ki) {
            /* texels x directions, centred on the cluster's mean */
            btf_mat cm = {.base = a->rgb, .m = n_i, .n = D, .rd = 1, .r1 = 3, .r2 = 0, .cd = 3, .c1 = N * 3, .c2 = 1,
                          .rows = rows, .sub = mean};
            double *cu = prw_malloc(sizeof(double) * n_i * ki), *cs = prw_malloc(sizeof(double) * ki),
                   *cv = prw_malloc(sizeof(double) * D * ki);
            ok = btf_svd(&cm, ki, 6, p->power ? p->power : 2, p->seed + i + 1, p->threads, cu, cs, cv, e);
            if (ok) {
                for (uint32_t j = 0; j < ki; j++)
                    for (uint64_t d = 0; d < D; d++) out->basis[((uint64_t)i * k + j) * D + d] = h16(cv[d * ki + j] * sd);
                for (uint64_t r = 0; r < n_i; r++)
                    for (uint32_t j = 0; j < ki; j++) out->w[(uint64_t)rows[r] * k + j] = h16(cu[r * ki + j] * cs[j] / sd);
            }
            free(cu), free(cs), free(cv);
        }
        progress(p, "cluster: local components", (double)(i + 1) / c);
    }
    free(mean), free(order), free(start);
    if (!k) { /* pure vector quantisation: no weights or bases */
        free(out->basis), free(out->w);
        out->basis = NULL, out->w = NULL;
    }
    return ok;
}

static bool pvf(const prw_btf *a, const prw_btf_codec_params *p, prw_btf_packed *out, prw_error *e)
{
    uint64_t N = (uint64_t)a->width * a->height, E = (uint64_t)a->lights * 3;
    uint32_t k = p->components;
    if (k < 1 || k > E || k > N) return prw_fail(e, "btf pvf: %u components for %llu x %llu per view", k, (unsigned long long)N, (unsigned long long)E);
    out->clusters = a->views;
    out->mean = prw_malloc(sizeof(uint16_t) * a->views * E);
    out->basis = prw_malloc(sizeof(uint16_t) * a->views * k * E);
    out->w = prw_malloc(sizeof(uint16_t) * a->views * N * k);
    double *mean = prw_malloc(sizeof(double) * E), *cu = prw_malloc(sizeof(double) * N * k),
           *cs = prw_malloc(sizeof(double) * k), *cv = prw_malloc(sizeof(double) * E * k);
    bool ok = true;
    double se = sqrt((double)E);
    for (uint32_t v = 0; ok && v < a->views; v++) {
        const float *base = a->rgb + (uint64_t)v * a->lights * N * 3;
        btf_mat vm = {.base = base, .m = N, .n = E, .rd = 1, .r1 = 3, .r2 = 0, .cd = 3, .c1 = N * 3, .c2 = 1};
        for (uint64_t j = 0; j < E; j++) {
            double sum = 0;
            for (uint64_t t = 0; t < N; t++) sum += btf_mat_at(&vm, t, j);
            mean[j] = sum / (double)N;
            out->mean[v * E + j] = h16(mean[j]);
        }
        vm.sub = mean;
        ok = btf_svd(&vm, k, 6, p->power ? p->power : 2, p->seed + v, p->threads, cu, cs, cv, e);
        for (uint32_t j = 0; ok && j < k; j++)
            for (uint64_t i = 0; i < E; i++) out->basis[((uint64_t)v * k + j) * E + i] = h16(cv[i * k + j] * se);
        for (uint64_t t = 0; ok && t < N; t++)
            for (uint32_t j = 0; j < k; j++) out->w[((uint64_t)v * N + t) * k + j] = h16(cu[t * k + j] * cs[j] / se);
        progress(p, "pvf: views", (double)(v + 1) / a->views);
    }
    free(mean), free(cu), free(cs), free(cv);
    return ok;
}

static bool sparse(const prw_btf *a, const prw_btf_codec_params *p, prw_btf_packed *out, prw_error *e);

bool prw_btf_compress(const prw_btf *a, const prw_btf_codec_params *p, prw_btf_packed *out, prw_error *e)
{
    memset(out, 0, sizeof *out);
    if (!a->rgb) return prw_fail(e, "btf compress: empty BTF");
    uint64_t D = (uint64_t)a->views * a->lights * 3, N = (uint64_t)a->width * a->height;
    uint64_t kk = p->components ? p->components : 1, big = PRW_MAX(PRW_MAX(D * kk, N * kk), (uint64_t)a->views * N * kk);
    if (big > UINT32_MAX || prw_mul_sat(prw_mul_sat(p->clusters, kk), D) > UINT32_MAX)
        return prw_fail(e, "btf compress: %llu texels x %llu directions x %llu components: an array beyond 2^32 elements "
                        "(the decode indexes with 32 bits)", (unsigned long long)N, (unsigned long long)D, (unsigned long long)kk);
    copy_dirs(a, out);
    out->codec = p->codec;
    out->components = p->components;
    out->clusters = p->clusters;
    bool ok;
    switch (p->codec) {
    case PRW_BTF_CODEC_FMF: out->clusters = 0, ok = fmf(a, p, out, e); break;
    case PRW_BTF_CODEC_CLUSTER: ok = cluster(a, p, out, e); break;
    case PRW_BTF_CODEC_PVF: ok = pvf(a, p, out, e); break;
    case PRW_BTF_CODEC_SPARSE: ok = sparse(a, p, out, e); break;
    default: ok = prw_fail(e, "btf compress: unknown codec %d", (int)p->codec);
    }
    /* the scale rule's average: only for directions above the horizon (a measured BTF's) */
    prw_error fe;
    if (ok) out->has_average = prw_btf_fit_average(a, &out->average, &fe);
    if (!ok) prw_btf_packed_free(out);
    return ok;
}

/* the shared decode (prw_btf_decode.h) on the packed struct */
#define PRW_BTF_PARAMS const prw_btf_packed *p,
#define PRW_BTF_U(i) half_table[p->u[i]]
#define PRW_BTF_W(i) half_table[p->w[i]]
#define PRW_BTF_MEAN(i) half_table[p->mean[i]]
#define PRW_BTF_BASIS(i) half_table[p->basis[i]]
#define PRW_BTF_INDEX(t) p->index[t]
#define PRW_BTF_ARGS p,
#define PRW_BTF_SP_START(t) p->sp_start[t]
#define PRW_BTF_SP_PAIR(j) p->sp_pair[j]
#define PRW_BTF_SP_VAL(i) half_table[p->sp_val[i]]
#include "prw_btf_decode.h"

/* SPARSE: log2 energy in 1/64 octave bins from 2^-100 (bin 0: below, or zero) */
enum { SP_BINS = 140 * 64 };

static uint16_t energy_bin(double en)
{
    if (!(en > 0x1.0p-100)) return 0;
    double b = (log2(en) + 100.0) * 64.0 + 1.0;
    return (uint16_t)(b >= SP_BINS - 1 ? SP_BINS - 1 : b);
}

typedef struct sparse_ctx {
    const prw_btf *a;
    const prw_btf_packed *p;
    uint16_t *bin; /* N x pairs */
} sparse_ctx;

/* per texel and direction pair: the bin of the residual energy after the cluster decode */
static void sparse_bins(void *user, uint64_t b, uint64_t e)
{
    sparse_ctx *x = user;
    const prw_btf *a = x->a;
    uint64_t N = (uint64_t)a->width * a->height, P = (uint64_t)a->views * a->lights;
    uint32_t D = (uint32_t)(P * 3);
    for (uint64_t t = b; t < e; t++)
        for (uint64_t q = 0; q < P; q++) {
            double en = 0;
            for (uint32_t c = 0; c < 3; c++) {
                double r = a->rgb[(q * N + t) * 3 + c] -
                           (double)prw_btf_decode_cluster(x->p, (uint32_t)q * 3 + c, (uint32_t)t, x->p->components, D);
                en += r * r;
            }
            x->bin[t * P + q] = energy_bin(en);
        }
}

/* Without components, each cluster's mean ABRDF again over the entries the residual does not hold: the
 * spikes it holds no longer leak into the mean of every texel of their cluster. */
static void refit_means(const prw_btf *a, prw_btf_packed *out)
{
    uint64_t N = (uint64_t)a->width * a->height, P = (uint64_t)a->views * a->lights, D = P * 3;
    double *sum = prw_calloc((size_t)(out->clusters * D), sizeof(double));
    uint32_t *count = prw_calloc((size_t)(out->clusters * P), sizeof(uint32_t));
    for (uint64_t t = 0; t < N; t++) {
        uint64_t i = out->index[t];
        uint32_t j = out->sp_start[t], end = out->sp_start[t + 1];
        for (uint64_t q = 0; q < P; q++) {
            if (j < end && out->sp_pair[j] == q) {
                j++;
                continue;
            }
            count[i * P + q]++;
            for (uint32_t c = 0; c < 3; c++) sum[i * D + q * 3 + c] += a->rgb[(q * N + t) * 3 + c];
        }
    }
    for (uint64_t i = 0; i < out->clusters; i++)
        for (uint64_t q = 0; q < P; q++)
            if (count[i * P + q])
                for (uint32_t c = 0; c < 3; c++) out->mean[i * D + q * 3 + c] = h16(sum[i * D + q * 3 + c] / count[i * P + q]);
    free(sum), free(count);
}

static bool sparse(const prw_btf *a, const prw_btf_codec_params *p, prw_btf_packed *out, prw_error *e)
{
    uint64_t N = (uint64_t)a->width * a->height, P = (uint64_t)a->views * a->lights;
    if (p->clusters > 65535 || P > 65535)
        return prw_fail(e, "btf sparse: %u clusters, %llu direction pairs (at most 65535 each)", p->clusters, (unsigned long long)P);
    if (!(p->sparse_per_texel >= 0) || p->sparse_per_texel * (double)N > (double)PRW_MIN(N * P, (uint64_t)UINT32_MAX / 3))
        return prw_fail(e, "btf sparse: %g entries per texel for %llu texels x %llu direction pairs", p->sparse_per_texel,
                        (unsigned long long)N, (unsigned long long)P);
    if (!prw_mem_check(prw_mul_sat(N * P, 2), "btf sparse", "the residual energies", e)) return false;
    if (!cluster(a, p, out, e)) return false;
    uint64_t M = (uint64_t)llround(p->sparse_per_texel * (double)N);
    progress(p, "sparse: residual", 0);
    sparse_ctx x = {a, out, prw_malloc(sizeof(uint16_t) * N * P)};
    btf_parallel(N, p->threads, sparse_bins, &x);
    /* the threshold bin: entries above it are all kept, in it the first ones in texel order */
    uint64_t *hist = prw_calloc(SP_BINS, sizeof(uint64_t));
    for (uint64_t i = 0; i < N * P; i++) hist[x.bin[i]]++;
    uint64_t above = 0;
    int thr = SP_BINS - 1;
    while (thr > 0 && above + hist[thr] <= M) above += hist[thr--];
    uint64_t quota = thr > 0 ? M - above : 0; /* bin 0 (no residual) is never kept */
    free(hist);
    out->sp_start = prw_malloc(sizeof(uint32_t) * (N + 1));
    out->sp_pair = prw_malloc(sizeof(uint16_t) * (M ? M : 1));
    out->sp_val = prw_malloc(sizeof(uint16_t) * 3 * (M ? M : 1));
    uint32_t D = (uint32_t)(P * 3), j = 0;
    for (uint64_t t = 0; t < N; t++) {
        out->sp_start[t] = j;
        for (uint64_t q = 0; q < P; q++) {
            int b = x.bin[t * P + q];
            if (b < thr || b == 0 || (b == thr && !quota)) continue;
            if (b == thr) quota--;
            out->sp_pair[j++] = (uint16_t)q;
        }
        if ((t & 1023) == 0) progress(p, "sparse: residual", (double)t / (double)N);
    }
    out->sp_start[N] = j;
    out->sparse_count = j;
    free(x.bin);
    if (!out->components) refit_means(a, out);
    for (uint64_t t = 0; t < N; t++)
        for (uint32_t i = out->sp_start[t]; i < out->sp_start[t + 1]; i++) {
            uint64_t q = out->sp_pair[i];
            for (uint32_t c = 0; c < 3; c++)
                out->sp_val[(uint64_t)i * 3 + c] =
                    h16(a->rgb[(q * N + t) * 3 + c] - (double)prw_btf_decode_cluster(out, (uint32_t)q * 3 + c, (uint32_t)t, out->components, D));
        }
    progress(p, "sparse: residual", 1);
    return true;
}

float prw_btf_packed_value(const prw_btf_packed *p, uint32_t v, uint32_t l, uint32_t x, uint32_t y, uint32_t c)
{
    uint32_t N = p->width * p->height, t = y * p->width + x, d = (v * p->lights + l) * 3 + c;
    switch (p->codec) {
    case PRW_BTF_CODEC_FMF: return prw_btf_decode_fmf(p, d, t, p->components);
    case PRW_BTF_CODEC_CLUSTER: return prw_btf_decode_cluster(p, d, t, p->components, p->views * p->lights * 3);
    case PRW_BTF_CODEC_PVF: return prw_btf_decode_pvf(p, v, l * 3 + c, t, p->components, N, p->lights * 3);
    case PRW_BTF_CODEC_SPARSE: return prw_btf_decode_sparse(p, d, t, p->components, p->views * p->lights * 3);
    }
    return 0;
}

typedef struct err_ctx {
    const prw_btf *a;
    const prw_btf_packed *p;
    double *part; /* per direction pair: |A|^2, |A - Abar|^2, |A - Ahat|^2, sum |A - Ahat| */
} err_ctx;

static void err_part(void *user, uint64_t b, uint64_t e)
{
    err_ctx *x = user;
    const prw_btf *a = x->a;
    uint64_t N = (uint64_t)a->width * a->height;
    for (uint64_t vl = b; vl < e; vl++) {
        uint32_t v = (uint32_t)(vl / a->lights), l = (uint32_t)(vl % a->lights);
        double *r = x->part + vl * 4;
        r[0] = r[1] = r[2] = r[3] = 0;
        for (uint32_t c = 0; c < 3; c++) {
            double mean = 0;
            for (uint64_t t = 0; t < N; t++) mean += a->rgb[(vl * N + t) * 3 + c];
            mean /= (double)N;
            for (uint32_t y = 0; y < a->height; y++)
                for (uint32_t xx = 0; xx < a->width; xx++) {
                    double A = a->rgb[prw_btf_at(a, v, l, xx, y) + c];
                    double h = x->p ? prw_btf_packed_value(x->p, v, l, xx, y, c) : A;
                    r[0] += A * A;
                    r[1] += (A - mean) * (A - mean);
                    r[2] += (A - h) * (A - h);
                    r[3] += fabs(A - h);
                }
        }
    }
}

void prw_btf_errors(const prw_btf *a, const prw_btf_packed *p, int threads, prw_btf_error *out)
{
    uint64_t pairs = (uint64_t)a->views * a->lights;
    err_ctx x = {a, p, prw_malloc(sizeof(double) * 4 * pairs)};
    btf_parallel(pairs, threads, err_part, &x);
    double s[4] = {0, 0, 0, 0};
    for (uint64_t i = 0; i < pairs; i++)
        for (int k = 0; k < 4; k++) s[k] += x.part[i * 4 + k];
    free(x.part);
    double count = (double)pairs * a->width * a->height * 3;
    out->norm = sqrt(s[0]);
    out->varying_norm = sqrt(s[1]);
    out->rms_pct = s[0] > 0 ? 100 * sqrt(s[2] / s[0]) : 0;
    out->varying_pct = s[1] > 0 ? 100 * sqrt(s[2] / s[1]) : 0;
    out->mean_abs = s[3] / count;
}

double prw_btf_varying_fraction(const prw_btf *a)
{
    prw_btf_error r;
    prw_btf_errors(a, NULL, 0, &r);
    return r.norm > 0 ? r.varying_norm / r.norm : 0;
}
