/* btf_linalg.h — the dense linear algebra of the BTF codecs (internal to materials/btf): a strided
 * view of a float matrix inside a BTF, a parallel loop over the one thread budget, and a truncated
 * SVD by randomised subspace iteration (Halko, Martinsson, Tropp 2011, algorithm 4.4).
 * Everything accumulates in double. */
#ifndef PRW_BTF_LINALG_H
#define PRW_BTF_LINALG_H

#include <stdbool.h>
#include <stdint.h>

#include "prw_core.h"

/* Element (i, j) of an m x n matrix inside `base`:
 *   row r = rows ? rows[i] : i, offset (r / rd) * r1 + (r % rd) * r2 + (j / cd) * c1 + (j % cd) * c2,
 * minus sub[j] when sub is set (a column mean).  rd, cd >= 1. */
typedef struct btf_mat {
    const float *base;
    uint64_t m, n;
    uint64_t rd, r1, r2, cd, c1, c2;
    const uint32_t *rows;
    const double *sub;
} btf_mat;

static inline uint64_t btf_mat_row(const btf_mat *a, uint64_t i)
{
    uint64_t r = a->rows ? a->rows[i] : i;
    return (r / a->rd) * a->r1 + (r % a->rd) * a->r2;
}

static inline uint64_t btf_mat_col(const btf_mat *a, uint64_t j) { return (j / a->cd) * a->c1 + (j % a->cd) * a->c2; }

static inline double btf_mat_at(const btf_mat *a, uint64_t i, uint64_t j)
{
    return (double)a->base[btf_mat_row(a, i) + btf_mat_col(a, j)] - (a->sub ? a->sub[j] : 0.0);
}

/* Runs fn(user, begin, end) over [0, n) split into contiguous parts on up to `threads` threads
 * (0: prw_threads_get()); the calling thread takes one part. */
void btf_parallel(uint64_t n, int threads, void (*fn)(void *user, uint64_t begin, uint64_t end), void *user);

/* Y (m x l, row-major) = A X with X (n x l); Z (n x l) = A^T Y with Y (m x l). */
void btf_mat_mul(const btf_mat *a, const double *x, uint32_t l, double *y, int threads);
void btf_mat_tmul(const btf_mat *a, const double *y, uint32_t l, double *z, int threads);

/* A ~ U diag(s) V^T with k components (k <= min(m, n)): U m x k, s k (descending), V n x k,
 * row-major.  oversample extra columns, `power` subspace iterations, seeded. */
bool btf_svd(const btf_mat *a, uint32_t k, uint32_t oversample, uint32_t power, uint64_t seed, int threads, double *u,
             double *s, double *v, prw_error *e);

#endif
