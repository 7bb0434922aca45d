// env_lookup.glsl — the environment light's bindings (set 0, 5-7; engine/render/prw_env_gpu.h) and the
// lookup of its prefiltered levels in a direction: shared by the environment term (gi_env.glsl) and the
// background (sky.frag).  Needs common.glsl.
#ifndef PRW_ENV_LOOKUP_GLSL
#define PRW_ENV_LOOKUP_GLSL

layout(std430, set = 0, binding = 5) readonly buffer prw_env_block { // std430 = std140 here (vec4s)
    vec4 sh[9]; // rgb: SH radiance coefficients (prw_env.h's basis order, map space)
    vec4 rot;   // cos rotation, sin rotation, levels K, level height H
} prw_env;
layout(set = 0, binding = 6) uniform sampler2DArray prw_env_levels; // K layers, 2H x H, equirect
layout(set = 0, binding = 7) uniform sampler2DArray prw_env_dfg;    // x: mu, y: roughness; (A, B)

// World (camera-relative) direction to map space: d' = R_y(-rotation) d (prw_environment).
vec3 prw_env_to_map(vec3 d)
{
    float c = prw_env.rot.x, s = prw_env.rot.y;
    return vec3(c * d.x - s * d.z, d.y, s * d.x + c * d.z);
}

// The levels' texture coordinates of direction d (world, camera-relative).
vec2 prw_env_uv(vec3 d)
{
    vec3 m = prw_env_to_map(d);
    float u = 0.5 + atan(m.x, -m.z) * (1.0 / 6.28318530717959);
    float h = prw_env.rot.w;
    // v kept off the outer half rows: the sampler repeats (for u), the poles must not meet
    float v = clamp(acos(clamp(m.y, -1.0, 1.0)) * (1.0 / 3.14159265358979), 0.5 / h, 1.0 - 0.5 / h);
    return vec2(u, v);
}

vec3 prw_env_level(vec3 d, float layer) { return textureLod(prw_env_levels, vec3(prw_env_uv(d), layer), 0.0).rgb; }

#endif
