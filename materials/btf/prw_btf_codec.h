/* prw_btf_codec — BTF compression (CPU): codecs, our compressed form and its file, and the error
 * figures of issue "BTF materials".
 *
 * A BTF A (prw_btf.h) is a D x N matrix: D = views * lights * 3 rows (direction pair and channel,
 * d = (v * lights + l) * 3 + c) by N = width * height texel columns (t = y * width + x).
 * Codecs, each with its knobs:
 *  - FMF (full-matrix factorisation, as the Bonn FMF files): A ~ U W^T with `components` columns,
 *    the truncated SVD (U carries the singular values);
 *      value(d, t) = sum_k U[d][k] W[t][k]
 *  - CLUSTER (clustered ABRDFs with local PCA; Mueller et al. 2003, Meseth's clustered reflectance
 *    fields with per-cluster components): the texels' ABRDFs (columns) are clustered by k-means
 *    (on their coordinates in the leading FMF components), each cluster keeps its mean and
 *    `components` principal directions (0: pure vector quantisation);
 *      value(d, t) = M[i][d] + sum_k W[t][k] B[i][k][d],   i = cluster of t
 *  - PVF (per-view factorisation, as the Bonn PVF files): for each view v the texels x (light,
 *    channel) matrix by PCA with `components` components;
 *      value(d, t) = M[v][e] + sum_k W[v][t][k] B[v][k][e],   e = l * 3 + c
 *  - SPARSE (CLUSTER plus a sparse residual): the CLUSTER approximation, then the `sparse_per_texel`
 *    x N (texel, direction pair) entries with the largest residual energy (summed over the channels)
 *    over the whole BTF keep their RGB residual; what few texels hold in few direction pairs (the
 *    narrow highlights of metallic flakes) is stored where it is instead of being clustered away;
 *      value(d, t) = CLUSTER value(d, t) + R[j][c] if texel t has an entry j for pair q = d / 3
 *    (entries per texel ascending in q, found by binary search); at most 65535 clusters and
 *    65535 direction pairs.
 * Every stored number is a half float (what the GPU reads); the errors are measured after that.
 *
 * Promises:
 *  - prw_btf_compress is deterministic for a given seed and thread count; it reports progress
 *    through the callback (may be NULL) and checks its working memory against the budget first.  It
 *    also fits the scale rule's average (prw_btf_fit_average) into out->average (has_average false when
 *    a direction is at or below the horizon).
 *  - prw_btf_packed_value is the one decode definition (the GPU and path-tracer decodes must equal
 *    it); it reads indices in range only.
 *  - The file ("PRWBTFC1", little-endian) round-trips exactly; its reader refuses with one line
 *    naming the file, place and problem anything else, counts checked against the bytes left
 *    before allocating.
 *  - prw_btf_errors: rms % = 100 |A - Ahat| / |A|; varying % = 100 |(A - Abar) - (Ahat - Abar)| /
 *    |A - Abar| with Abar the per-direction mean over texels (= 100 |A - Ahat| / |A - Abar|); mean
 *    abs = mean |A - Ahat|; all over every texel, direction pair and channel, linear values.
 */
#ifndef PRW_BTF_CODEC_H
#define PRW_BTF_CODEC_H

#include <stdbool.h>
#include <stdint.h>

#include "prw_btf.h"
#include "prw_core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum prw_btf_codec {
    PRW_BTF_CODEC_FMF = 1,
    PRW_BTF_CODEC_CLUSTER = 2,
    PRW_BTF_CODEC_PVF = 3,
    PRW_BTF_CODEC_SPARSE = 4,
} prw_btf_codec;

typedef struct prw_btf_codec_params {
    prw_btf_codec codec;
    uint32_t components; /* FMF >= 1; CLUSTER >= 0; PVF >= 1 */
    uint32_t clusters;   /* CLUSTER, SPARSE: >= 1 */
    double sparse_per_texel; /* SPARSE: residual entries kept, per texel on average (>= 0) */
    uint32_t kmeans_iterations; /* CLUSTER: 0 = 20 */
    uint32_t power;      /* subspace iterations of the SVDs: 0 = 2 */
    uint64_t seed;
    int threads;         /* 0: prw_threads_get() */
    void (*progress)(void *user, const char *stage, double fraction);
    void *user;
} prw_btf_codec_params;

/* The scale rule's average (issue 17): the BTF averaged over its texels, fitted by the project's material
 * model (prw_bsdf.h: base colour, metallic, roughness, specular; no coat) in least squares over every
 * measured (view, light) pair of f cos theta_l; rms_pct = 100 |fit - mean| / |mean| over those pairs. */
typedef struct prw_btf_average {
    float base[3], metallic, roughness, specular, rms_pct;
} prw_btf_average;

/* Fits the average of a (raw) BTF; errors only for directions at or below the horizon. */
bool prw_btf_fit_average(const prw_btf *a, prw_btf_average *out, prw_error *e);

typedef struct prw_btf_packed {
    prw_btf_codec codec;
    uint32_t width, height, views, lights;
    float *view_dirs, *light_dirs; /* 2 per direction: theta, phi */
    uint32_t components, clusters; /* PVF: clusters = views (one basis per view) */
    uint16_t *u;     /* FMF: D x components */
    uint16_t *w;     /* FMF: N x components; CLUSTER, SPARSE: N x components; PVF: views x N x components */
    uint16_t *mean;  /* CLUSTER, SPARSE: clusters x D; PVF: views x (lights * 3) */
    uint16_t *basis; /* CLUSTER, SPARSE: clusters x components x D; PVF: views x components x (lights * 3) */
    uint32_t *index; /* CLUSTER, SPARSE: N cluster indices */
    uint32_t sparse_count; /* SPARSE: M residual entries */
    uint32_t *sp_start;    /* SPARSE: N + 1 offsets: texel t's entries are [sp_start[t], sp_start[t + 1]) */
    uint16_t *sp_pair;     /* SPARSE: M direction pairs v * lights + l, ascending within a texel */
    uint16_t *sp_val;      /* SPARSE: M x 3 halves, the RGB residual */
    bool has_average;      /* prw_btf_compress fits it (file version 2 stores it; version 1 files have none) */
    prw_btf_average average;
} prw_btf_packed;

bool prw_btf_compress(const prw_btf *a, const prw_btf_codec_params *p, prw_btf_packed *out, prw_error *e);
void prw_btf_packed_free(prw_btf_packed *p);

/* Channel c of texel (x, y) at view v, light l. */
float prw_btf_packed_value(const prw_btf_packed *p, uint32_t v, uint32_t l, uint32_t x, uint32_t y, uint32_t c);
/* The bytes the file of p takes. */
uint64_t prw_btf_packed_bytes(const prw_btf_packed *p);

bool prw_btf_packed_write(const char *path, const prw_btf_packed *p, prw_error *e);
bool prw_btf_packed_read(const char *path, prw_btf_packed *out, prw_error *e);
bool prw_btf_packed_read_memory(const void *data, size_t size, const char *name, prw_btf_packed *out, prw_error *e);

typedef struct prw_btf_error {
    double rms_pct, varying_pct, mean_abs;
    double norm, varying_norm; /* |A|, |A - Abar| */
} prw_btf_error;
void prw_btf_errors(const prw_btf *a, const prw_btf_packed *p, int threads, prw_btf_error *out);
/* |A - Abar| / |A|: how much of the BTF varies over the texels. */
double prw_btf_varying_fraction(const prw_btf *a);

#ifdef __cplusplus
}
#endif
#endif
