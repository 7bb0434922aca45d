// btf_eval.glsl — a BTF material's value (prw_btf_material_eval, materials/btf/prw_btf_eval.h) on the
// GPU: the direction / texel interpolation through the shared definitions (btf/prw_btf_interp.h), the
// decode as btf/prw_btf_decode.h's formulas on RGB entries (one fetch per direction pair and stored row
// instead of one per channel; test_btf_eval_gpu holds it equal to the C decode).  What a fragment's
// lights share is computed once (btf_setup), then each light (btf_eval_light).  The material is packed
// in 32-bit words by prw_btf_gpu_pack (engine/render/prw_btf_gpu.h); the includer defines
// PRW_BTF_BLOB(i), the i-th word of that array (a storage buffer: no constant tables in shaders on
// lavapipe).
#ifndef PRW_BTF_EVAL_GLSL
#define PRW_BTF_EVAL_GLSL

struct BtfHeader {
    uint codec, width, height, views, lights, k, clusters;
    uint w, index, sp_start, sp_pair, sp_val, rgb, cols;
    uint vn, ln;   // triangle counts of the view and light tables
    uvec4 vdt, ldt; // their offsets: tri_inv, tri_vert, cos_theta, grid
};

// The codec the includer specialises on (PRW_BTF_CODEC: a constant, e.g. a specialisation constant;
// 0 or undefined: the header's, every codec's code kept).  On lavapipe both sides of a branch run, so
// a known codec removes the others' fetches.
#ifndef PRW_BTF_CODEC
#define PRW_BTF_CODEC 0u
#endif
// Likewise the components + 1 (PRW_BTF_K1; 0: the header's): constant loop counts unroll, and the
// per-texel components then sit in registers instead of a dynamically indexed array.
#ifndef PRW_BTF_K1
#define PRW_BTF_K1 0u
#endif
#define PRW_BTF_KMAX 16u // components held per texel in btf_px (PRW_BTF_GPU_KMAX, prw_btf_gpu.h)

float btf_half(uint base, uint i)
{
    vec2 h = unpackHalf2x16(PRW_BTF_BLOB(base + (i >> 1u)));
    return (i & 1u) == 0u ? h.x : h.y;
}

// 4-word texel e of the RGB blocks (prw_btf_gpu.h); the includer may define PRW_BTF_BLOCK(e) (e.g. a
// texel buffer over the same words: one vector fetch) instead of the four word loads
#ifndef PRW_BTF_BLOCK
#define PRW_BTF_BLOCK(e) uvec4(PRW_BTF_BLOB(4u * (e)), PRW_BTF_BLOB(4u * (e) + 1u), PRW_BTF_BLOB(4u * (e) + 2u), PRW_BTF_BLOB(4u * (e) + 3u))
#endif
#define PRW_BTF_BMAX ((3u * (PRW_BTF_KMAX + 1u) + 7u) / 8u) // texels of the largest block

// a direction table: the offsets of its tri_inv, tri_vert, cos_theta, grid (read once, btf_header)
#define PRW_BTF_DT_PARAMS uvec4 dt,
#define PRW_BTF_DT_ARGS dt,
#define PRW_BTF_TRI_INV(i) uintBitsToFloat(PRW_BTF_BLOB(dt.x + (i)))
#define PRW_BTF_TRI_VERT(i) PRW_BTF_BLOB(dt.y + (i))
#define PRW_BTF_DIR_COS(i) uintBitsToFloat(PRW_BTF_BLOB(dt.z + (i)))
#define PRW_BTF_GRID(i) PRW_BTF_BLOB(dt.w + (i))
#include "btf/prw_btf_interp.h"

BtfHeader btf_header(uint m)
{
    BtfHeader H;
    H.codec = PRW_BTF_CODEC != 0u ? PRW_BTF_CODEC : PRW_BTF_BLOB(m);
    H.width = PRW_BTF_BLOB(m + 1u), H.height = PRW_BTF_BLOB(m + 2u);
    H.views = PRW_BTF_BLOB(m + 3u), H.lights = PRW_BTF_BLOB(m + 4u), H.k = PRW_BTF_K1 != 0u ? PRW_BTF_K1 - 1u : min(PRW_BTF_BLOB(m + 5u), PRW_BTF_KMAX);
    H.clusters = PRW_BTF_BLOB(m + 6u), H.w = PRW_BTF_BLOB(m + 8u), H.index = PRW_BTF_BLOB(m + 11u);
    H.sp_start = PRW_BTF_BLOB(m + 12u), H.sp_pair = PRW_BTF_BLOB(m + 13u), H.sp_val = PRW_BTF_BLOB(m + 14u);
    H.rgb = PRW_BTF_BLOB(m + 17u), H.cols = PRW_BTF_BLOB(m + 18u);
    uint vt = PRW_BTF_BLOB(m + 15u), lt = PRW_BTF_BLOB(m + 16u);
    H.vn = PRW_BTF_BLOB(vt), H.ln = PRW_BTF_BLOB(lt);
    H.vdt = uvec4(PRW_BTF_BLOB(vt + 1u), PRW_BTF_BLOB(vt + 2u), PRW_BTF_BLOB(vt + 3u), PRW_BTF_BLOB(vt + 4u));
    H.ldt = uvec4(PRW_BTF_BLOB(lt + 1u), PRW_BTF_BLOB(lt + 2u), PRW_BTF_BLOB(lt + 3u), PRW_BTF_BLOB(lt + 4u));
    return H;
}

// What a fragment's lights share (btf_setup): the view's 3 directions and weights, the 4 texels of the
// bilinear filter (q = 2 j + i: column i, row j) with their weights, and what the codec stores per texel
// (its cluster, its components; PVF's depend on the view: fetched per light).
struct btf_px {
    BtfHeader H;
    uint vi[3];
    float vw[3];
    uint t[4];
    float wx[2], wy[2];
    uint ci[4];
    float W[4u * PRW_BTF_KMAX];
};

btf_px btf_setup(uint m, vec2 xy, vec3 wv)
{
    btf_px X;
    X.H = btf_header(m);
    float lv = length(wv);
    wv = lv > 0.0 ? wv / lv : vec3(0.0, 0.0, 1.0);
    prw_btf_interp_dir(X.H.vdt, wv.x, wv.y, wv.z, X.H.vn, X.vi, X.vw);
    uint tx[2], ty[2];
    prw_btf_interp_texel(xy.x, xy.y, X.H.width, X.H.height, tx, ty, X.wx, X.wy);
    for (uint q = 0u; q < 4u; q++) {
        uint t = ty[q >> 1u] * X.H.width + tx[q & 1u];
        X.t[q] = t;
        X.ci[q] = X.H.codec == 2u || X.H.codec == 4u ? PRW_BTF_BLOB(X.H.index + t) : 0u;
        if (X.H.codec != 3u)
            for (uint j = 0u; j < X.H.k; j++) X.W[q * PRW_BTF_KMAX + j] = btf_half(X.H.w, t * X.H.k + j);
    }
    return X;
}

// SPARSE: texel t's residual for direction pair p (prw_btf_decode_sparse's search), 0 without an entry
vec3 btf_sparse_residual(BtfHeader H, uint p, uint t)
{
    uint lo = PRW_BTF_BLOB(H.sp_start + t), end = PRW_BTF_BLOB(H.sp_start + t + 1u), hi = end;
    while (lo < hi) {
        uint mid = lo + (hi - lo) / 2u;
        if (((PRW_BTF_BLOB(H.sp_pair + (mid >> 1u)) >> ((mid & 1u) * 16u)) & 0xffffu) < p) lo = mid + 1u;
        else hi = mid;
    }
    if (lo < end && ((PRW_BTF_BLOB(H.sp_pair + (lo >> 1u)) >> ((lo & 1u) * 16u)) & 0xffffu) == p)
        return vec3(btf_half(H.sp_val, lo * 3u), btf_half(H.sp_val, lo * 3u + 1u), btf_half(H.sp_val, lo * 3u + 2u));
    return vec3(0.0);
}

// The RGB value of texel slot q at view v, light l: prw_btf_decode.h's formulas on the RGB blocks, each
// channel summed in its order (component 0 first), so the values equal prw_btf_packed_value's.
vec3 btf_rgb(btf_px X, uint q, uint v, uint l)
{
    BtfHeader H = X.H;
    uint p = v * H.lights + l, R = H.codec == 1u ? H.k : H.k + 1u, B = (3u * R + 7u) / 8u;
    uint g = H.codec == 1u ? 0u : H.codec == 3u ? v : X.ci[q], col = H.codec == 3u ? l : p;
    uint base = H.rgb + (g * H.cols + col) * B;
    float h[8u * PRW_BTF_BMAX];
    for (uint b = 0u; b < B; b++) {
        uvec4 u = PRW_BTF_BLOCK(base + b);
        vec2 h0 = unpackHalf2x16(u.x), h1 = unpackHalf2x16(u.y), h2 = unpackHalf2x16(u.z), h3 = unpackHalf2x16(u.w);
        h[8u * b] = h0.x, h[8u * b + 1u] = h0.y, h[8u * b + 2u] = h1.x, h[8u * b + 3u] = h1.y;
        h[8u * b + 4u] = h2.x, h[8u * b + 5u] = h2.y, h[8u * b + 6u] = h3.x, h[8u * b + 7u] = h3.y;
    }
    if (H.codec == 1u) { // FMF: sum_j U[d][j] W[t][j]
        vec3 s = vec3(0.0);
        for (uint j = 0u; j < H.k; j++) s += vec3(h[3u * j], h[3u * j + 1u], h[3u * j + 2u]) * X.W[q * PRW_BTF_KMAX + j];
        return s;
    }
    vec3 s = vec3(h[0], h[1], h[2]); // M
    if (H.codec == 3u) { // PVF: M[v][e] + sum_j W[v][t][j] B[v][j][e]
        uint N = H.width * H.height;
        for (uint j = 0u; j < H.k; j++)
            s += btf_half(H.w, (v * N + X.t[q]) * H.k + j) * vec3(h[3u * j + 3u], h[3u * j + 4u], h[3u * j + 5u]);
        return s;
    }
    // CLUSTER, SPARSE: M[i][d] + sum_j W[t][j] B[i][j][d]
    for (uint j = 0u; j < H.k; j++) s += X.W[q * PRW_BTF_KMAX + j] * vec3(h[3u * j + 3u], h[3u * j + 4u], h[3u * j + 5u]);
    if (H.codec == 4u) s += btf_sparse_residual(H, p, X.t[q]);
    return s;
}

// prw_btf_material_eval for one light direction wl (the BTF frame, unit or not) at the fragment's
// view and texels: the 3 x 3 (view, light) directions x 4 texels, in the C loops' order.
vec3 btf_eval_light(btf_px X, vec3 wl)
{
    uint li[3];
    float lw[3];
    float ll = length(wl);
    wl = ll > 0.0 ? wl / ll : vec3(0.0, 0.0, 1.0);
    prw_btf_interp_dir(X.H.ldt, wl.x, wl.y, wl.z, X.H.ln, li, lw);
    prw_btf_interp_light(X.H.ldt, wl.z, li, lw);
    vec3 s = vec3(0.0);
    for (uint a = 0u; a < 3u; a++)
        for (uint c = 0u; c < 3u; c++) {
            float w = X.vw[a] * lw[c];
            if (!(w > 0.0)) continue;
            for (uint j = 0u; j < 2u; j++)
                for (uint i = 0u; i < 2u; i++) {
                    float wt = w * X.wx[i] * X.wy[j];
                    if (!(wt > 0.0)) continue;
                    s += wt * btf_rgb(X, 2u * j + i, X.vi[a], li[c]);
                }
        }
    return s;
}

// prw_btf_material_eval: continuous texel coordinates xy (wrapped by the caller into a small range),
// view and light directions in the BTF frame (x along the texel columns, y the rows, z the normal).
vec3 btf_eval(uint m, vec2 xy, vec3 wv, vec3 wl) { return btf_eval_light(btf_setup(m, xy, wv), wl); }

#endif
