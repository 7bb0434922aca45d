#version 450
#extension GL_GOOGLE_include_directive : require
#ifdef PRW_MULTIVIEW
#extension GL_EXT_multiview : require
layout(std140, set = 2, binding = 0) uniform prw_mv_block { mat4 view_proj[2]; vec4 eye_rel[2]; } prw_mv;
#endif
#include "common.glsl"

layout(location = 0) in vec3 in_pos;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec2 in_uv;
layout(location = 3) in vec4 in_tangent;
#ifdef PRW_GLTF_EXT
layout(location = 4) in vec2 in_uv1; // uv set 1 (constants: PRW_UV1_FLOATS)
layout(location = 4) out vec2 v_uv1;
#endif

#ifdef PRW_GI
layout(location = 5) in vec4 in_gi; // the light map's stream (gi_lightmap.glsl)
layout(location = 6) in vec4 in_gi_cone; // VERTEX mode: the open cone (gi_lightmap.glsl)
layout(location = 5) out vec4 v_gi;
layout(location = 6) out vec4 v_gi_cone;
#endif

layout(push_constant) uniform prw_draw {
    mat4 model;      // object -> camera-relative world
    vec4 normal_m[3];// inverse-transpose of model's 3x3, columns
#ifdef PRW_CLIP_PLANE
    vec4 clip_plane; // camera-relative plane: drawn where dot(plane, (p, 1)) >= 0
#endif
} pc;

layout(location = 0) out vec3 v_pos;
layout(location = 1) out vec3 v_normal;
layout(location = 2) out vec2 v_uv;
layout(location = 3) out vec4 v_tangent;
#ifdef PRW_CLIP_PLANE
out gl_PerVertex {
    vec4 gl_Position;
    float gl_ClipDistance[1];
};
#endif

void main()
{
    vec4 p = pc.model * vec4(in_pos, 1.0);
    mat3 nm = mat3(pc.normal_m[0].xyz, pc.normal_m[1].xyz, pc.normal_m[2].xyz);
    v_pos = p.xyz;
    v_normal = nm * in_normal;
    v_tangent = vec4(mat3(pc.model) * in_tangent.xyz, in_tangent.w * pc.normal_m[0].w);
    v_uv = in_uv;
#ifdef PRW_GLTF_EXT
    v_uv1 = in_uv1;
#endif
#ifdef PRW_GI
    v_gi = in_gi;
    v_gi_cone = in_gi_cone;
#endif
#ifdef PRW_MULTIVIEW
    gl_Position = prw_mv.view_proj[gl_ViewIndex] * p;
#else
    gl_Position = g.view_proj * p;
#endif
#ifdef PRW_CLIP_PLANE
    gl_ClipDistance[0] = dot(pc.clip_plane, vec4(p.xyz, 1.0));
#endif
}
