#version 450
#extension GL_GOOGLE_include_directive : require
#ifdef PRW_MULTIVIEW
#extension GL_EXT_multiview : require
layout(std140, set = 2, binding = 0) uniform prw_mv_block { mat4 view_proj[2]; vec4 eye_rel[2]; } prw_mv;
#endif
#include "common.glsl"
#include "prw_brdf.h"
#include "prw_shading.h"
#include "shadows.glsl"
#include "lights.glsl"
#include "material_gltf.glsl"

// Base pass: emission + direct light from every light (shadowed by shadow maps), in cd/m^2, for one
// material kind (material_gltf.glsl; variants by -D, shaders/CMakeLists.txt).  PRW_GBUFFER also writes
// the shading normal / roughness and the material id for later passes.

layout(location = 0) in vec3 v_pos;
layout(location = 1) in vec3 v_normal;
layout(location = 2) in vec2 v_uv;
layout(location = 3) in vec4 v_tangent;

layout(location = 0) out vec4 o_color;
#ifdef PRW_GBUFFER
layout(location = 1) out vec4 o_normal; // camera-relative shading normal, roughness
layout(location = 2) out uint o_id;     // material slot + 1
#endif

void main()
{
    prw_surface S = prw_material_surface(v_uv, v_normal, v_tangent, gl_FrontFacing);
    vec3 n = S.n;
#ifdef PRW_MULTIVIEW
    vec3 v = normalize(prw_mv.eye_rel[gl_ViewIndex].xyz - v_pos);
#else
    vec3 v = normalize(g.eye_rel.xyz - v_pos);
#endif
    float bend = prw_normal_bend(dot(n, v));
    if (bend > 0.0) n = normalize(n + v * bend);

    vec3 radiance = S.emission;
    prw_direct_light(radiance, v_pos, n, v, S.base, S.metallic, S.roughness, S.specular, 1.5);
    o_color = vec4(radiance, 1.0);
#ifdef PRW_GBUFFER
    o_normal = vec4(n, S.roughness);
    o_id = uint(mat.extra.y);
#endif
}
