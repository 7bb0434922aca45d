/* prw_btf_decode.h — THE decode of a compressed BTF (prw_btf_codec.h's value formulas), one source for
 * GLSL 4.50 (the base pass and the GPU test, shaders/) and C17 (prw_btf_packed_value, the path
 * tracer's BTF kind).  A scalar header: the includer defines how the stored numbers are fetched,
 *   PRW_BTF_U(i), PRW_BTF_W(i), PRW_BTF_MEAN(i), PRW_BTF_BASIS(i)  the i-th stored half as a float,
 *   PRW_BTF_INDEX(t)                                                texel t's cluster (PRW_BTF_UINT),
 *   PRW_BTF_SP_START(t), PRW_BTF_SP_PAIR(j)                         SPARSE: offsets, entries' pairs (PRW_BTF_UINT),
 *   PRW_BTF_SP_VAL(i)                                               SPARSE: the i-th residual half as a float,
 *   PRW_BTF_PARAMS                                                  leading parameters the fetches use
 *                                                                   (e.g. the packed BTF in C; empty in GLSL),
 *   PRW_BTF_ARGS                                                    the same parameters passed on (e.g. "p,"),
 * and calls the decode of the codec with the call's own leading arguments.  Each sums in float in one
 * fixed order (component 0 first), so both sides compute the same roundings (up to fused multiply-adds
 * on the GPU).  d = (v * lights + l) * 3 + c, e = l * 3 + c, t = y * width + x. */
#ifndef PRW_BTF_DECODE_H
#define PRW_BTF_DECODE_H

#ifdef GL_core_profile
#define PRW_BTF_UINT uint
#define PRW_BTF_FN
#else
#include <stdint.h>
#define PRW_BTF_UINT uint32_t
#define PRW_BTF_FN static inline
#endif

/* FMF: sum_k U[d][k] W[t][k] */
PRW_BTF_FN float prw_btf_decode_fmf(PRW_BTF_PARAMS PRW_BTF_UINT d, PRW_BTF_UINT t, PRW_BTF_UINT k)
{
    float s = 0.0;
    for (PRW_BTF_UINT j = 0u; j < k; j++) s += PRW_BTF_U(d * k + j) * PRW_BTF_W(t * k + j);
    return s;
}

/* CLUSTER: M[i][d] + sum_k W[t][k] B[i][k][d], i = texel t's cluster, D directions x channels */
PRW_BTF_FN float prw_btf_decode_cluster(PRW_BTF_PARAMS PRW_BTF_UINT d, PRW_BTF_UINT t, PRW_BTF_UINT k, PRW_BTF_UINT D)
{
    PRW_BTF_UINT i = PRW_BTF_INDEX(t);
    float s = PRW_BTF_MEAN(i * D + d);
    for (PRW_BTF_UINT j = 0u; j < k; j++) s += PRW_BTF_W(t * k + j) * PRW_BTF_BASIS((i * k + j) * D + d);
    return s;
}

/* PVF: M[v][e] + sum_k W[v][t][k] B[v][k][e], N texels, E = lights x 3 */
PRW_BTF_FN float prw_btf_decode_pvf(PRW_BTF_PARAMS PRW_BTF_UINT v, PRW_BTF_UINT e, PRW_BTF_UINT t, PRW_BTF_UINT k, PRW_BTF_UINT N,
                                    PRW_BTF_UINT E)
{
    float s = PRW_BTF_MEAN(v * E + e);
    for (PRW_BTF_UINT j = 0u; j < k; j++) s += PRW_BTF_W((v * N + t) * k + j) * PRW_BTF_BASIS((v * k + j) * E + e);
    return s;
}

/* SPARSE: the CLUSTER value plus texel t's residual entry for pair d / 3, if it has one */
PRW_BTF_FN float prw_btf_decode_sparse(PRW_BTF_PARAMS PRW_BTF_UINT d, PRW_BTF_UINT t, PRW_BTF_UINT k, PRW_BTF_UINT D)
{
    float s = prw_btf_decode_cluster(PRW_BTF_ARGS d, t, k, D);
    PRW_BTF_UINT q = d / 3u, lo = PRW_BTF_SP_START(t), end = PRW_BTF_SP_START(t + 1u), hi = end;
    while (lo < hi) {
        PRW_BTF_UINT mid = lo + (hi - lo) / 2u;
        if (PRW_BTF_SP_PAIR(mid) < q) lo = mid + 1u;
        else hi = mid;
    }
    if (lo < end && PRW_BTF_SP_PAIR(lo) == q) s += PRW_BTF_SP_VAL(lo * 3u + (d - q * 3u));
    return s;
}

#endif
