/* btf_linalg.c — see btf_linalg.h. */
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "btf_linalg.h"

typedef struct par_job {
    void (*fn)(void *, uint64_t, uint64_t);
    void *user;
    uint64_t begin, end;
} par_job;

static void *par_run(void *p)
{
    par_job *j = p;
    j->fn(j->user, j->begin, j->end);
    return NULL;
}

void btf_parallel(uint64_t n, int threads, void (*fn)(void *user, uint64_t begin, uint64_t end), void *user)
{
    int t = threads > 0 ? threads : prw_threads_get();
    if (t < 1) t = 1;
    if ((uint64_t)t > n) t = n ? (int)n : 1;
    if (t > 64) t = 64;
    par_job jobs[64];
    pthread_t tid[64];
    bool started[64] = {false};
    for (int i = 0; i < t; i++) jobs[i] = (par_job){fn, user, n * (uint64_t)i / (uint64_t)t, n * (uint64_t)(i + 1) / (uint64_t)t};
    for (int i = 1; i < t; i++) started[i] = pthread_create(&tid[i], NULL, par_run, &jobs[i]) == 0;
    for (int i = 1; i < t; i++)
        if (!started[i]) par_run(&jobs[i]); /* no thread to be had: this one does the part */
    par_run(&jobs[0]);
    for (int i = 1; i < t; i++)
        if (started[i]) pthread_join(tid[i], NULL);
}

typedef struct mul_ctx {
    const btf_mat *a;
    const double *x;
    uint32_t l;
    double *y;
} mul_ctx;

static void mul_rows(void *p, uint64_t b, uint64_t e)
{
    mul_ctx *c = p;
    const btf_mat *a = c->a;
    uint32_t l = c->l;
    for (uint64_t i = b; i < e; i++) {
        double *yi = c->y + i * l;
        memset(yi, 0, sizeof(double) * l);
        const float *row = a->base + btf_mat_row(a, i);
        for (uint64_t j = 0; j < a->n; j++) {
            double v = (double)row[btf_mat_col(a, j)] - (a->sub ? a->sub[j] : 0.0);
            const double *xj = c->x + j * l;
            for (uint32_t k = 0; k < l; k++) yi[k] += v * xj[k];
        }
    }
}

void btf_mat_mul(const btf_mat *a, const double *x, uint32_t l, double *y, int threads)
{
    mul_ctx c = {a, x, l, y};
    btf_parallel(a->m, threads, mul_rows, &c);
}

static void tmul_cols(void *p, uint64_t b, uint64_t e)
{
    mul_ctx *c = p; /* x: Y (m x l), y: Z (n x l) */
    const btf_mat *a = c->a;
    uint32_t l = c->l;
    memset(c->y + b * l, 0, sizeof(double) * l * (e - b));
    for (uint64_t i = 0; i < a->m; i++) {
        const float *row = a->base + btf_mat_row(a, i);
        const double *yi = c->x + i * l;
        for (uint64_t j = b; j < e; j++) {
            double v = (double)row[btf_mat_col(a, j)] - (a->sub ? a->sub[j] : 0.0);
            double *zj = c->y + j * l;
            for (uint32_t k = 0; k < l; k++) zj[k] += v * yi[k];
        }
    }
}

void btf_mat_tmul(const btf_mat *a, const double *y, uint32_t l, double *z, int threads)
{
    mul_ctx c = {a, y, l, z};
    btf_parallel(a->n, threads, tmul_cols, &c);
}

/* Orthonormal columns (modified Gram-Schmidt, twice) of the m x l row-major q; a column that is
 * (numerically) in the span of the ones before becomes 0. */
static void orthonormalise(double *q, uint64_t m, uint32_t l)
{
    for (uint32_t c = 0; c < l; c++) {
        double n0 = 0;
        for (uint64_t i = 0; i < m; i++) n0 += q[i * l + c] * q[i * l + c];
        for (int pass = 0; pass < 2; pass++)
            for (uint32_t p = 0; p < c; p++) {
                double d = 0;
                for (uint64_t i = 0; i < m; i++) d += q[i * l + p] * q[i * l + c];
                for (uint64_t i = 0; i < m; i++) q[i * l + c] -= d * q[i * l + p];
            }
        double n = 0;
        for (uint64_t i = 0; i < m; i++) n += q[i * l + c] * q[i * l + c];
        n = sqrt(n);
        double inv = n > 1e-12 * sqrt(n0) && n > 1e-300 ? 1.0 / n : 0.0;
        for (uint64_t i = 0; i < m; i++) q[i * l + c] *= inv;
    }
}

/* Eigen-decomposition of the symmetric l x l matrix g (destroyed) by cyclic Jacobi: values in w
 * (descending), vectors as the columns of vec (row-major l x l). */
static void jacobi(double *g, uint32_t l, double *w, double *vec)
{
    for (uint32_t i = 0; i < l; i++)
        for (uint32_t j = 0; j < l; j++) vec[i * l + j] = i == j;
    for (int sweep = 0; sweep < 100; sweep++) {
        double off = 0, diag = 0;
        for (uint32_t i = 0; i < l; i++)
            for (uint32_t j = 0; j < l; j++) {
                double q = g[i * l + j] * g[i * l + j];
                if (i == j) diag += q;
                else off += q;
            }
        if (off <= 1e-30 * diag || off == 0) break;
        for (uint32_t p = 0; p < l; p++)
            for (uint32_t q = p + 1; q < l; q++) {
                double apq = g[p * l + q];
                if (fabs(apq) < 1e-300) continue;
                double theta = (g[q * l + q] - g[p * l + p]) / (2 * apq);
                double t = (theta >= 0 ? 1 : -1) / (fabs(theta) + sqrt(theta * theta + 1));
                double c = 1 / sqrt(t * t + 1), s = t * c;
                for (uint32_t k = 0; k < l; k++) { /* rotate columns p, q */
                    double gkp = g[k * l + p], gkq = g[k * l + q];
                    g[k * l + p] = c * gkp - s * gkq;
                    g[k * l + q] = s * gkp + c * gkq;
                }
                for (uint32_t k = 0; k < l; k++) { /* and rows p, q */
                    double gpk = g[p * l + k], gqk = g[q * l + k];
                    g[p * l + k] = c * gpk - s * gqk;
                    g[q * l + k] = s * gpk + c * gqk;
                }
                for (uint32_t k = 0; k < l; k++) {
                    double vkp = vec[k * l + p], vkq = vec[k * l + q];
                    vec[k * l + p] = c * vkp - s * vkq;
                    vec[k * l + q] = s * vkp + c * vkq;
                }
            }
    }
    for (uint32_t i = 0; i < l; i++) w[i] = g[i * l + i];
    for (uint32_t i = 0; i < l; i++) { /* selection sort, descending, columns with the values */
        uint32_t best = i;
        for (uint32_t j = i + 1; j < l; j++)
            if (w[j] > w[best]) best = j;
        if (best == i) continue;
        double t = w[i];
        w[i] = w[best], w[best] = t;
        for (uint32_t k = 0; k < l; k++) {
            t = vec[k * l + i];
            vec[k * l + i] = vec[k * l + best], vec[k * l + best] = t;
        }
    }
}

static double gauss(uint64_t *s)
{
    double u[2];
    for (int i = 0; i < 2; i++) {
        *s += 0x9E3779B97F4A7C15ull;
        uint64_t z = *s;
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        z ^= z >> 31;
        u[i] = ((double)(z >> 11) + 0.5) * 0x1.0p-53;
    }
    return sqrt(-2 * log(u[0])) * cos(6.283185307179586 * u[1]);
}

bool btf_svd(const btf_mat *a, uint32_t k, uint32_t oversample, uint32_t power, uint64_t seed, int threads, double *u,
             double *s, double *v, prw_error *e)
{
    uint64_t m = a->m, n = a->n;
    if (k < 1 || k > m || k > n) return prw_fail(e, "btf svd: %u components of a %llu x %llu matrix", k, (unsigned long long)m, (unsigned long long)n);
    uint64_t l64 = (uint64_t)k + oversample;
    if (l64 > m) l64 = m;
    if (l64 > n) l64 = n;
    uint32_t l = (uint32_t)l64;
    uint64_t bytes = prw_mul_sat(prw_add_sat(prw_mul_sat(m, 2), prw_mul_sat(n, 2)), prw_mul_sat(l, 8));
    if (!prw_mem_check(bytes, "btf svd", "its work matrices", e)) return false;
    double *q = prw_malloc(sizeof(double) * m * l), *z = prw_malloc(sizeof(double) * n * l);
    uint64_t st = seed * 0x2545F4914F6CDD1Dull + 1;
    for (uint64_t i = 0; i < n * l; i++) z[i] = gauss(&st);
    btf_mat_mul(a, z, l, q, threads);
    orthonormalise(q, m, l);
    for (uint32_t it = 0; it < power; it++) {
        btf_mat_tmul(a, q, l, z, threads);
        orthonormalise(z, n, l);
        btf_mat_mul(a, z, l, q, threads);
        orthonormalise(q, m, l);
    }
    btf_mat_tmul(a, q, l, z, threads); /* z = A^T Q = B^T (n x l) */
    double *g = prw_calloc((size_t)l * l, sizeof(double)), *w = prw_malloc(sizeof(double) * l),
           *vec = prw_malloc(sizeof(double) * l * l);
    for (uint64_t i = 0; i < n; i++)
        for (uint32_t p = 0; p < l; p++)
            for (uint32_t r = 0; r < l; r++) g[p * l + r] += z[i * l + p] * z[i * l + r];
    jacobi(g, l, w, vec);
    for (uint32_t c = 0; c < k; c++) s[c] = w[c] > 0 ? sqrt(w[c]) : 0;
    for (uint64_t i = 0; i < m; i++)
        for (uint32_t c = 0; c < k; c++) {
            double sum = 0;
            for (uint32_t p = 0; p < l; p++) sum += q[i * l + p] * vec[p * l + c];
            u[i * k + c] = sum;
        }
    for (uint64_t i = 0; i < n; i++)
        for (uint32_t c = 0; c < k; c++) {
            double sum = 0;
            for (uint32_t p = 0; p < l; p++) sum += z[i * l + p] * vec[p * l + c];
            v[i * k + c] = s[c] > 1e-300 ? sum / s[c] : 0;
        }
    free(q), free(z), free(g), free(w), free(vec);
    return true;
}
