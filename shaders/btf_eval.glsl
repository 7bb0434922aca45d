// btf_eval.glsl — a BTF material's value (prw_btf_material_eval, materials/btf/prw_btf_eval.h) on the
// GPU, through the shared definitions: the decode (btf/prw_btf_decode.h) and the direction / texel
// interpolation (btf/prw_btf_interp.h).  The material is packed in 32-bit words by prw_btf_gpu_pack
// (engine/render/prw_btf_gpu.h); the includer defines PRW_BTF_BLOB(i), the i-th word of that array
// (a storage buffer: no constant tables in shaders on lavapipe).
#ifndef PRW_BTF_EVAL_GLSL
#define PRW_BTF_EVAL_GLSL

struct BtfHeader {
    uint codec, width, height, views, lights, k, clusters;
    uint u, w, mean, basis, index, sp_start, sp_pair, sp_val, vtab, ltab;
};

float btf_half(uint base, uint i)
{
    vec2 h = unpackHalf2x16(PRW_BTF_BLOB(base + (i >> 1u)));
    return (i & 1u) == 0u ? h.x : h.y;
}

#define PRW_BTF_PARAMS BtfHeader H,
#define PRW_BTF_ARGS H,
#define PRW_BTF_U(i) btf_half(H.u, (i))
#define PRW_BTF_W(i) btf_half(H.w, (i))
#define PRW_BTF_MEAN(i) btf_half(H.mean, (i))
#define PRW_BTF_BASIS(i) btf_half(H.basis, (i))
#define PRW_BTF_INDEX(t) PRW_BTF_BLOB(H.index + (t))
#define PRW_BTF_SP_START(t) PRW_BTF_BLOB(H.sp_start + (t))
#define PRW_BTF_SP_PAIR(j) ((PRW_BTF_BLOB(H.sp_pair + ((j) >> 1u)) >> (((j) & 1u) * 16u)) & 0xffffu)
#define PRW_BTF_SP_VAL(i) btf_half(H.sp_val, (i))
#include "btf/prw_btf_decode.h"

// a direction table at word dt: triangle count, offsets of tri_inv, tri_vert, cos_theta, grid
#define PRW_BTF_DT_PARAMS uint dt,
#define PRW_BTF_DT_ARGS dt,
#define PRW_BTF_TRI_INV(i) uintBitsToFloat(PRW_BTF_BLOB(PRW_BTF_BLOB(dt + 1u) + (i)))
#define PRW_BTF_TRI_VERT(i) PRW_BTF_BLOB(PRW_BTF_BLOB(dt + 2u) + (i))
#define PRW_BTF_DIR_COS(i) uintBitsToFloat(PRW_BTF_BLOB(PRW_BTF_BLOB(dt + 3u) + (i)))
#define PRW_BTF_GRID(i) PRW_BTF_BLOB(PRW_BTF_BLOB(dt + 4u) + (i))
#include "btf/prw_btf_interp.h"

BtfHeader btf_header(uint m)
{
    BtfHeader H;
    H.codec = PRW_BTF_BLOB(m), H.width = PRW_BTF_BLOB(m + 1u), H.height = PRW_BTF_BLOB(m + 2u);
    H.views = PRW_BTF_BLOB(m + 3u), H.lights = PRW_BTF_BLOB(m + 4u), H.k = PRW_BTF_BLOB(m + 5u);
    H.clusters = PRW_BTF_BLOB(m + 6u), H.u = PRW_BTF_BLOB(m + 7u), H.w = PRW_BTF_BLOB(m + 8u);
    H.mean = PRW_BTF_BLOB(m + 9u), H.basis = PRW_BTF_BLOB(m + 10u), H.index = PRW_BTF_BLOB(m + 11u);
    H.sp_start = PRW_BTF_BLOB(m + 12u), H.sp_pair = PRW_BTF_BLOB(m + 13u), H.sp_val = PRW_BTF_BLOB(m + 14u);
    H.vtab = PRW_BTF_BLOB(m + 15u), H.ltab = PRW_BTF_BLOB(m + 16u);
    return H;
}

// prw_btf_packed_value: channel c of texel t at view v, light l
float btf_value(BtfHeader H, uint v, uint l, uint t, uint c)
{
    uint D = H.views * H.lights * 3u, d = (v * H.lights + l) * 3u + c;
    if (H.codec == 1u) return prw_btf_decode_fmf(H, d, t, H.k);
    if (H.codec == 2u) return prw_btf_decode_cluster(H, d, t, H.k, D);
    if (H.codec == 4u) return prw_btf_decode_sparse(H, d, t, H.k, D);
    return prw_btf_decode_pvf(H, v, l * 3u + c, t, H.k, H.width * H.height, H.lights * 3u);
}

// prw_btf_material_eval: continuous texel coordinates xy (wrapped by the caller into a small range),
// view and light directions in the BTF frame (x along the texel columns, y the rows, z the normal).
vec3 btf_eval(uint m, vec2 xy, vec3 wv, vec3 wl)
{
    BtfHeader H = btf_header(m);
    uint vi[3], li[3], tx[2], ty[2];
    float vw[3], lw[3], wx[2], wy[2];
    float lv = length(wv), ll = length(wl);
    wv = lv > 0.0 ? wv / lv : vec3(0.0, 0.0, 1.0);
    wl = ll > 0.0 ? wl / ll : vec3(0.0, 0.0, 1.0);
    prw_btf_interp_dir(H.vtab, wv.x, wv.y, wv.z, PRW_BTF_BLOB(H.vtab), vi, vw);
    prw_btf_interp_dir(H.ltab, wl.x, wl.y, wl.z, PRW_BTF_BLOB(H.ltab), li, lw);
    prw_btf_interp_light(H.ltab, wl.z, li, lw);
    prw_btf_interp_texel(xy.x, xy.y, H.width, H.height, tx, ty, wx, wy);
    vec3 s = vec3(0.0);
    for (uint a = 0u; a < 3u; a++)
        for (uint c = 0u; c < 3u; c++) {
            float w = vw[a] * lw[c];
            if (!(w > 0.0)) continue;
            for (uint j = 0u; j < 2u; j++)
                for (uint i = 0u; i < 2u; i++) {
                    float wt = w * wx[i] * wy[j];
                    if (!(wt > 0.0)) continue;
                    uint t = ty[j] * H.width + tx[i];
                    s += wt * vec3(btf_value(H, vi[a], li[c], t, 0u), btf_value(H, vi[a], li[c], t, 1u),
                                   btf_value(H, vi[a], li[c], t, 2u));
                }
        }
    return s;
}

#endif
