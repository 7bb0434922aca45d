#version 450
#extension GL_GOOGLE_include_directive : require
#include "prw_brdf.h"

// Planar mirror, second half (engine/render/pass_mirror.c): in the pixels of the reflector's material
// (G-buffer id), adds the mirror image times the specular lobe's reflectance at the view angle,
// per channel: metallic * Schlick(F0 = base) + (1 - metallic) * specular * exact dielectric Fresnel
// (prw_brdf.h, the path tracer's model at roughness -> 0).  Elsewhere adds nothing.

layout(set = 0, binding = 0) uniform sampler2D u_mirror;  // the mirrored view's radiance, same pixel grid
layout(set = 0, binding = 1) uniform sampler2D u_normal;  // G-buffer: camera-relative normal, roughness
layout(set = 0, binding = 2) uniform usampler2D u_id;     // G-buffer: material slot + 1

layout(push_constant) uniform prw_mirror_push {
    mat4 inv_view_proj; // clip -> camera-relative world of the real view
    vec4 base;          // rgb: base colour, a: metallic
    vec4 misc;          // x: specular, y: material id (slot + 1), zw: target size in pixels
} pc;

layout(location = 0) out vec4 o_color;

void main()
{
    ivec2 p = ivec2(gl_FragCoord.xy);
    if (texelFetch(u_id, p, 0).r != uint(pc.misc.y)) {
        o_color = vec4(0.0);
        return;
    }
    vec3 n = texelFetch(u_normal, p, 0).xyz;
    float ln = length(n);
    n = ln > 1e-6 ? n / ln : vec3(0.0);
    vec2 ndc = gl_FragCoord.xy / pc.misc.zw * 2.0 - 1.0;
    vec4 q = pc.inv_view_proj * vec4(ndc, 1.0, 1.0); // on the near plane (reversed Z)
    vec3 d = q.xyz / q.w;                               // camera-relative: the eye is the origin
    float ld = length(d);
    vec3 v = ld > 1e-20 ? -d / ld : vec3(0.0, 0.0, 1.0);
    float mu = clamp(abs(dot(n, v)), 0.0, 1.0);
    float m = clamp(pc.base.a, 0.0, 1.0);
    vec3 F;
    float fd = (1.0 - m) * clamp(pc.misc.x, 0.0, 1.0) * prw_F_dielectric(mu);
    F.r = m * prw_F_schlick(pc.base.r, mu) + fd;
    F.g = m * prw_F_schlick(pc.base.g, mu) + fd;
    F.b = m * prw_F_schlick(pc.base.b, mu) + fd;
    vec3 L = texelFetch(u_mirror, p, 0).rgb;
    // no NaN/Inf into the radiance: a non-finite mirror sample adds nothing
    if (any(isnan(L)) || any(isinf(L))) L = vec3(0.0);
    o_color = vec4(F * L, 0.0);
}
