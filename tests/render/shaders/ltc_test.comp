#version 450
#extension GL_GOOGLE_include_directive : require
// Evaluates rect_specular_ltc and ltc_lookup (shaders/ltc.glsl) for the GPU-vs-C-twin test (test_ltc_gpu.c):
// per case 11 floats, the RGB specular then the lookup's two texels.
#define PRW_LTC_SET 0
#define PRW_LTC_BINDING 2
#include "prw_brdf.h"
#include "polygon.glsl"
#include "ltc.glsl"
layout(local_size_x = 64) in;
// per case 24 floats: p, n, v, c, du, dv, base (3 each), metallic, roughness, specular
layout(std430, set = 0, binding = 0) readonly buffer In { float cases[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Out { float results[]; };
layout(push_constant) uniform PC { uint count; } pc;
vec3 at(uint i, uint k) { return vec3(cases[i * 24u + k], cases[i * 24u + k + 1u], cases[i * 24u + k + 2u]); }
void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    vec3 r = rect_specular_ltc(at(i, 0u), at(i, 3u), at(i, 6u), at(i, 9u), at(i, 12u), at(i, 15u), at(i, 18u),
                               cases[i * 24u + 21u], cases[i * 24u + 22u], cases[i * 24u + 23u]);
    results[i * 11u] = r.x;
    results[i * 11u + 1u] = r.y;
    results[i * 11u + 2u] = r.z;
    // the table lookup alone, at this case's roughness and a cosine from its base colour's red
    vec4 m, f;
    ltc_lookup(cases[i * 24u + 22u], cases[i * 24u + 18u], m, f);
    for (uint k = 0u; k < 4u; k++) {
        results[i * 11u + 3u + k] = m[k];
        results[i * 11u + 7u + k] = f[k];
    }
}
