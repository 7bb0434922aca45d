#version 450
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(location = 0) in vec3 in_pos;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec2 in_uv;
layout(location = 3) in vec4 in_tangent;

layout(push_constant) uniform prw_draw {
    mat4 model;      // object -> camera-relative world
    vec4 normal_m[3];// inverse-transpose of model's 3x3, columns
} pc;

layout(location = 0) out vec3 v_pos;
layout(location = 1) out vec3 v_normal;
layout(location = 2) out vec2 v_uv;
layout(location = 3) out vec4 v_tangent;

void main()
{
    vec4 p = pc.model * vec4(in_pos, 1.0);
    mat3 nm = mat3(pc.normal_m[0].xyz, pc.normal_m[1].xyz, pc.normal_m[2].xyz);
    v_pos = p.xyz;
    v_normal = nm * in_normal;
    v_tangent = vec4(mat3(pc.model) * in_tangent.xyz, in_tangent.w * pc.normal_m[0].w);
    v_uv = in_uv;
    gl_Position = g.view_proj * p;
}
