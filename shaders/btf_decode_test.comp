#version 450
#extension GL_GOOGLE_include_directive : require
// Decodes compressed-BTF values through the shared decode (materials/btf/prw_btf_decode.h) for the
// CPU-vs-GPU equality test (tests/render/test_btf_gpu.c).  The stored halves (and SPARSE's u16 pairs)
// come two per uint.
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer U { uint u[]; };
layout(std430, set = 0, binding = 1) readonly buffer W { uint w[]; };
layout(std430, set = 0, binding = 2) readonly buffer Mean { uint mean[]; };
layout(std430, set = 0, binding = 3) readonly buffer Basis { uint basis[]; };
layout(std430, set = 0, binding = 4) readonly buffer Index { uint index[]; };
layout(std430, set = 0, binding = 5) readonly buffer Cases { uvec4 cases[]; }; // v, l, t, c
layout(std430, set = 0, binding = 6) writeonly buffer Out { float results[]; };
layout(std430, set = 0, binding = 7) readonly buffer SpStart { uint sp_start[]; };
layout(std430, set = 0, binding = 8) readonly buffer SpPair { uint sp_pair[]; };
layout(std430, set = 0, binding = 9) readonly buffer SpVal { uint sp_val[]; };
layout(push_constant) uniform PC { uint count, codec, k, lights, views, texels; } pc;

float half_at(uint word, uint i) { vec2 h = unpackHalf2x16(word); return (i & 1u) == 0u ? h.x : h.y; }
#define PRW_BTF_PARAMS
#define PRW_BTF_U(i) half_at(u[(i) >> 1], (i))
#define PRW_BTF_W(i) half_at(w[(i) >> 1], (i))
#define PRW_BTF_MEAN(i) half_at(mean[(i) >> 1], (i))
#define PRW_BTF_BASIS(i) half_at(basis[(i) >> 1], (i))
#define PRW_BTF_INDEX(t) index[t]
#define PRW_BTF_ARGS
#define PRW_BTF_SP_START(t) sp_start[t]
#define PRW_BTF_SP_PAIR(j) ((sp_pair[(j) >> 1] >> (((j) & 1u) * 16u)) & 0xffffu)
#define PRW_BTF_SP_VAL(i) half_at(sp_val[(i) >> 1], (i))
#include "btf/prw_btf_decode.h"

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    uvec4 q = cases[i];
    uint d = (q.x * pc.lights + q.y) * 3u + q.w;
    float v = 0.0;
    if (pc.codec == 1u) v = prw_btf_decode_fmf(d, q.z, pc.k);
    else if (pc.codec == 2u) v = prw_btf_decode_cluster(d, q.z, pc.k, pc.views * pc.lights * 3u);
    else if (pc.codec == 4u) v = prw_btf_decode_sparse(d, q.z, pc.k, pc.views * pc.lights * 3u);
    else v = prw_btf_decode_pvf(q.x, q.y * 3u + q.w, q.z, pc.k, pc.texels, pc.lights * 3u);
    results[i] = v;
}
