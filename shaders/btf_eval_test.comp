#version 450
#extension GL_GOOGLE_include_directive : require
// Evaluates a packed BTF material (btf_eval.glsl) at given texel positions and directions, for the
// GPU-vs-C test of the evaluation (tests/render/test_btf_eval_gpu.c).
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Blob { uint btf_blob[]; };
layout(std430, set = 0, binding = 1) readonly buffer Cases { vec4 cases[]; }; // (x, y, -, -), wv, wl
layout(std430, set = 0, binding = 2) writeonly buffer Out { vec4 results[]; };
layout(push_constant) uniform PC { uint count, material; } pc;

#define PRW_BTF_BLOB(i) btf_blob[i]
#include "btf_eval.glsl"

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    results[i] = vec4(btf_eval(pc.material, cases[3u * i].xy, cases[3u * i + 1u].xyz, cases[3u * i + 2u].xyz), 0.0);
}
