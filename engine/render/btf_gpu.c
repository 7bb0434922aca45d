/* btf_gpu.c — a BTF material packed into 32-bit words for shaders/btf_eval.glsl (prw_btf_gpu.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_btf_gpu.h"
#include "prw_math.h"
/* the interpolation header's fetches, for its grid size (the functions are not used here) */
#define PRW_BTF_DT_PARAMS const prw_btf_dirtab *dt,
#define PRW_BTF_DT_ARGS dt,
#define PRW_BTF_TRI_INV(i) (dt->tri_inv[(i)])
#define PRW_BTF_TRI_VERT(i) (dt->tri_vert[(i)])
#define PRW_BTF_DIR_COS(i) (dt->cos_theta[(i)])
#define PRW_BTF_GRID(i) (dt->grid[(i)])
#include "prw_btf_interp.h"

static uint32_t grow(prw_btf_gpu_words *a, size_t n)
{
    if (a->count + n > a->cap) {
        size_t cap = a->cap ? a->cap : 1024;
        while (cap < a->count + n) cap *= 2;
        a->w = prw_realloc(a->w, sizeof(uint32_t) * cap);
        a->cap = cap;
    }
    uint32_t at = (uint32_t)a->count;
    memset(a->w + at, 0, sizeof(uint32_t) * n);
    a->count += n;
    return at;
}

/* n 16-bit values, two per word (the lower first, as unpackHalf2x16 reads them); 0 for none */
static uint32_t put16(prw_btf_gpu_words *a, const uint16_t *v, uint64_t n)
{
    if (!v || n == 0) return 0;
    uint32_t at = grow(a, (size_t)((n + 1) / 2));
    for (uint64_t i = 0; i < n; i++) a->w[at + i / 2] |= (uint32_t)v[i] << (16 * (i & 1));
    return at;
}

static uint32_t put32(prw_btf_gpu_words *a, const void *v, uint64_t n)
{
    if (!v || n == 0) return 0;
    uint32_t at = grow(a, (size_t)n);
    memcpy(a->w + at, v, sizeof(uint32_t) * n);
    return at;
}

static uint32_t put_table(prw_btf_gpu_words *a, const prw_btf_dirtab *t)
{
    uint32_t at = grow(a, 5);
    uint32_t inv = put32(a, t->tri_inv, (uint64_t)9 * t->tri_count);
    uint32_t vert = put32(a, t->tri_vert, (uint64_t)3 * t->tri_count);
    uint32_t cs = put32(a, t->cos_theta, t->count);
    uint32_t grid = grow(a, PRW_BTF_GRID_WORDS); /* no grid: triangle 0 as every candidate, as the C side */
    if (t->grid) memcpy(a->w + grid, t->grid, sizeof(uint32_t) * PRW_BTF_GRID_WORDS);
    uint32_t h[5] = {t->tri_count, inv, vert, cs, grid};
    memcpy(a->w + at, h, sizeof h);
    return at;
}

/* Block (g, col) of the RGB blocks (prw_btf_gpu.h): the R rows' channel triples, row r channel c at half
 * 3 r + c, 8 halves per 4-word texel; row r of group g is src[r], whose channel triples lie at stride 3
 * (channel step `step`) from first[r]. */
static void put_block(uint32_t *w, uint64_t col, uint32_t R, const uint16_t *const *src, const uint64_t *first,
                      uint64_t step)
{
    for (uint32_t r = 0; r < R; r++)
        for (uint32_t c = 0; c < 3; c++) {
            uint32_t h = 3 * r + c;
            w[h / 2] |= (uint32_t)src[r][first[r] + col * 3 * step + c * step] << (16 * (h & 1));
        }
}

/* The environment table (prw_btf_gpu.h).  The interpolated BTF is sum_k w_k(l) f_k with w_k the light
 * weights of prw_btf_dirtab_weights (w_k cos theta_l / cos theta_k), so under a distant light L(l)
 *   int BTF(l) L(l) dl = sum_k f_k int w_k(l) L(l) dl = sum_k f_k A_k Lbar_k,
 * A_k = int w_k dl, Lbar_k = L averaged with the kernel w_k: read from the prefiltered environment at the
 * kernel's centroid c_k, at the roughness whose prefilter kernel has the kernel's median angle about c_k.
 * Integrals by the midpoint rule on ENV_NZ x ENV_NP cells of equal solid angle (z = cos theta, phi). */
#define ENV_NZ 96
#define ENV_NP 384
#define ENV_BINS 360 /* quarter-degree bins of the angle from the centroid */
#define ENV_ROUGH 101

/* Median angle of the environment prefilter's kernel at GGX alpha (materials/env/prw_env.h: l the
 * reflection of d about h, h ~ D(h) cos theta_h, weight d.l = cos 2 theta_h; the angle is 2 theta_h). */
static double ggx_median_angle(double alpha)
{
    enum { N = 4000 };
    double a2 = alpha * alpha, tot = 0, cdf[N];
    for (int i = 0; i < N; i++) {
        double th = (i + 0.5) * (0.25 * PRW_PI / N), c = cos(th), q = c * c * (a2 - 1) + 1;
        tot += a2 / (PRW_PI * q * q) * c * sin(th) * cos(2 * th);
        cdf[i] = tot;
    }
    for (int i = 0; i < N; i++)
        if (cdf[i] >= 0.5 * tot) return 2 * (i + 0.5) * (0.25 * PRW_PI / N);
    return 0.5 * PRW_PI;
}

static uint32_t put_env_table(prw_btf_gpu_words *a, const prw_btf_dirtab *t)
{
    uint32_t n = t->count;
    double *A = prw_calloc(n, sizeof *A), *c = prw_calloc(3 * (size_t)n, sizeof *c);
    double *hist = prw_calloc((size_t)n * ENV_BINS, sizeof *hist);
    double dw = (1.0 / ENV_NZ) * (2 * PRW_PI / ENV_NP), med_r[ENV_ROUGH];
    for (int pass = 0; pass < 2; pass++)
        for (int i = 0; i < ENV_NZ; i++)
            for (int j = 0; j < ENV_NP; j++) {
                double z = (i + 0.5) / ENV_NZ, s = sqrt(1 - z * z), p = 2 * PRW_PI * (j + 0.5) / ENV_NP;
                double d[3] = {s * cos(p), s * sin(p), z};
                uint32_t idx[3];
                float w[3];
                prw_btf_dirtab_weights(t, d, true, idx, w);
                for (int k = 0; k < 3; k++) {
                    if (!(w[k] > 0) || idx[k] >= n) continue;
                    double wk = w[k] * dw;
                    uint32_t m = idx[k];
                    if (pass == 0) {
                        A[m] += wk;
                        for (int q = 0; q < 3; q++) c[3 * m + q] += wk * d[q];
                    } else {
                        double ca = d[0] * c[3 * m] + d[1] * c[3 * m + 1] + d[2] * c[3 * m + 2];
                        int b = (int)(acos(fmin(fmax(ca, -1.0), 1.0)) * (180.0 / PRW_PI) * 4);
                        hist[(size_t)m * ENV_BINS + (b < ENV_BINS ? b : ENV_BINS - 1)] += wk;
                    }
                }
                if (pass == 0 && i == ENV_NZ - 1 && j == ENV_NP - 1)
                    for (uint32_t m = 0; m < n; m++) { /* the centroids made unit for the second pass */
                        double l = sqrt(c[3 * m] * c[3 * m] + c[3 * m + 1] * c[3 * m + 1] + c[3 * m + 2] * c[3 * m + 2]);
                        for (int q = 0; q < 3; q++) c[3 * m + q] = l > 0 ? c[3 * m + q] / l : (q == 2);
                    }
            }
    for (int r = 0; r < ENV_ROUGH; r++) { /* prw_alpha_from_roughness (prw_brdf.h): max(r^2, 0.002) */
        double rr = (double)r / (ENV_ROUGH - 1);
        med_r[r] = ggx_median_angle(fmax(rr * rr, 0.002));
    }
    uint32_t at = grow(a, 5 * (size_t)n);
    for (uint32_t m = 0; m < n; m++) {
        double acc = 0, med = 0;
        for (int b = 0; b < ENV_BINS; b++) {
            acc += hist[(size_t)m * ENV_BINS + b];
            if (acc >= 0.5 * A[m]) {
                med = (b + 0.5) / 4 * (PRW_PI / 180);
                break;
            }
        }
        double rough = 1.0; /* the roughness whose median angle is med, linear between the table's */
        for (int r = 1; r < ENV_ROUGH; r++)
            if (med_r[r] >= med) {
                double f = (med - med_r[r - 1]) / fmax(med_r[r] - med_r[r - 1], 1e-12);
                rough = ((r - 1) + fmin(fmax(f, 0.0), 1.0)) / (ENV_ROUGH - 1);
                break;
            }
        float v[5] = {(float)c[3 * m], (float)c[3 * m + 1], (float)c[3 * m + 2], (float)A[m], (float)rough};
        memcpy(a->w + at + 5 * m, v, sizeof v);
    }
    free(A), free(c), free(hist);
    return at;
}

bool prw_btf_gpu_pack(const prw_btf_material *m, const char *name, prw_btf_gpu_words *a, uint32_t *offset, prw_error *e)
{
    const prw_btf_packed *p = &m->p;
    uint64_t P = (uint64_t)p->views * p->lights, D = P * 3, N = (uint64_t)p->width * p->height, k = p->components;
    uint64_t nw = 0, ni = 0, M = 0, rows = 0, cols = P;
    if (p->codec == PRW_BTF_CODEC_FMF) nw = N * k, rows = k;
    else if (p->codec == PRW_BTF_CODEC_CLUSTER || p->codec == PRW_BTF_CODEC_SPARSE)
        nw = N * k, ni = N, rows = (uint64_t)p->clusters * (k + 1);
    else nw = p->views * N * k, rows = (uint64_t)p->views * (k + 1), cols = p->lights;
    if (p->codec == PRW_BTF_CODEC_SPARSE) M = p->sparse_count;
    /* the codec arrays (halves two per word; RGB entries two words), then at most two tables of <= 2 x 512
     * triangles (12 words each), 256 cosines and the grid */
    uint64_t table = 5 + 12 * 2 * 512 + PRW_BTF_DIRS_MAX + PRW_BTF_GRID_WORDS;
    uint64_t need = a->count + PRW_BTF_GPU_HEADER + (nw + 4 * M) / 2 + 8 + ni + (N + 1) + 6 * rows * cols + 4 + 2 * table + 5 * (uint64_t)p->lights;
    if (k > PRW_BTF_GPU_KMAX)
        return prw_fail(e, "%s: %u components: the base pass holds at most %u", name, p->components, PRW_BTF_GPU_KMAX);
    if (need >= (1ull << 31)) return prw_fail(e, "%s: %llu words do not fit one GPU buffer", name, (unsigned long long)need);
    uint32_t at = grow(a, PRW_BTF_GPU_HEADER);
    uint32_t h[PRW_BTF_GPU_HEADER] = {(uint32_t)p->codec, p->width, p->height, p->views, p->lights, p->components, p->clusters};
    h[8] = put16(a, p->w, nw);
    h[11] = put32(a, p->index, ni);
    if (p->codec == PRW_BTF_CODEC_SPARSE) {
        h[12] = put32(a, p->sp_start, N + 1);
        h[13] = put16(a, p->sp_pair, M);
        h[14] = put16(a, p->sp_val, 3 * M);
    }
    h[15] = put_table(a, &m->views);
    h[16] = m->shared ? h[15] : put_table(a, &m->lights);
    /* the RGB blocks: groups (clusters, views, or one) of R rows */
    uint32_t R = (uint32_t)(p->codec == PRW_BTF_CODEC_FMF ? k : k + 1), B = (3 * R + 7) / 8;
    uint64_t groups = rows / R;
    while (a->count & 3) grow(a, 1); /* blocks start at a multiple of 4 words */
    uint32_t blk = grow(a, (size_t)(4 * B * groups * cols));
    const uint16_t *src[PRW_BTF_GPU_KMAX + 1];
    uint64_t first[PRW_BTF_GPU_KMAX + 1];
    for (uint64_t g = 0; g < groups; g++) {
        uint64_t step = 1;
        for (uint32_t r = 0; r < R; r++) {
            if (p->codec == PRW_BTF_CODEC_FMF) src[r] = p->u, first[r] = r, step = k; /* U[d][r], d = col * 3 + c */
            else if (p->codec == PRW_BTF_CODEC_PVF) /* M[v][e], B[v][r - 1][e], e = col * 3 + c */
                src[r] = r ? p->basis : p->mean, first[r] = r ? (g * k + r - 1) * cols * 3 : g * cols * 3;
            else src[r] = r ? p->basis : p->mean, first[r] = r ? (g * k + r - 1) * D : g * D; /* M[i][d], B[i][r - 1][d] */
        }
        for (uint64_t col = 0; col < cols; col++) put_block(a->w + blk + 4 * B * (g * cols + col), col, R, src, first, step);
    }
    h[17] = blk / 4, h[18] = (uint32_t)cols;
    h[19] = put_env_table(a, m->shared ? &m->views : &m->lights);
    memcpy(a->w + at, h, sizeof h);
    *offset = at;
    return true;
}

uint32_t prw_btf_gpu_spec(const prw_btf_packed *p)
{
    uint32_t c = ((uint32_t)p->codec - 1u) & 3u;
    return p->components <= 14 ? c | (p->components + 1u) << 2 : c;
}
