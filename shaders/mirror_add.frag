#version 450
#extension GL_GOOGLE_include_directive : require
#include "prw_brdf.h"

// Planar mirror, second half (engine/render/pass_mirror.c): in the pixels of the reflector's material
// (G-buffer id), adds the mirror image times the specular lobe's reflectance at the view angle,
// per channel: metallic * Schlick(F0 = base) + (1 - metallic) * specular * exact dielectric Fresnel
// (prw_brdf.h, the path tracer's model at roughness -> 0).  Elsewhere adds nothing.
// Glossy reflector (pc.glossy.x = alpha > 0): the mirror image convolved by the reflected GGX lobe,
// computed on mirror_glossy.frag's reduced grid (view x mirror_scale x glossy_scale), read bilinearly, times the split-sum
// reflectance per channel: metallic (base A + B) + (1 - metallic) specular (0.04 A + B).

layout(set = 0, binding = 0) uniform sampler2D u_mirror;  // the mirrored view's radiance (the target's grid x mirror_scale)
layout(set = 0, binding = 1) uniform sampler2D u_normal;  // G-buffer: camera-relative normal, roughness
layout(set = 0, binding = 2) uniform usampler2D u_id;     // G-buffer: material slot + 1
layout(set = 0, binding = 3) uniform sampler2D u_glossy;  // glossy: the convolved mirror image (its grid)
layout(set = 0, binding = 4) uniform prw_mirror_dfg {
    vec4 dfg[32]; // xy: split-sum A, B at mu = (i + 0.5) / 32 for the reflector's roughness
} u_dfg;

layout(push_constant) uniform prw_mirror_push {
    mat4 inv_view_proj; // clip -> camera-relative world of the real view
    vec4 base;          // rgb: base colour, a: metallic
    vec4 misc;          // x: specular, y: material id (slot + 1), zw: target size in pixels
    vec4 glossy;        // x: alpha (0: sharp mirror)
} pc;

vec3 finite_or_zero(vec3 L) { return (any(isnan(L)) || any(isinf(L))) ? vec3(0.0) : L; }

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
    // the mirror image may be smaller than the target (knob mirror_scale): then upsampled bilinearly
    bool full = vec2(textureSize(u_mirror, 0)) == pc.misc.zw;
    if (pc.glossy.x > 0.0) {
        vec3 sum = finite_or_zero(textureLod(u_glossy, gl_FragCoord.xy / pc.misc.zw, 0.0).rgb);
        float x = clamp(mu * 32.0 - 0.5, 0.0, 31.0);
        int i0 = int(floor(x));
        vec2 ab = mix(u_dfg.dfg[i0].xy, u_dfg.dfg[min(i0 + 1, 31)].xy, x - float(i0));
        // the split sum integrates Schlick's Fresnel; the dielectric lobe (prw_brdf.h) has the exact one:
        // scaled by their ratio at the mirror direction (v.h = mu), which the lobe straddles
        float fs = prw_F_schlick(0.04, mu);
        float sd = (1.0 - m) * clamp(pc.misc.x, 0.0, 1.0) * (0.04 * ab.x + ab.y) * (fs > 0.0 ? prw_F_dielectric(mu) / fs : 1.0);
        vec3 Fg = m * (pc.base.rgb * ab.x + ab.y) + sd;
        o_color = vec4(Fg * sum, 0.0);
        return;
    }
    vec3 F;
    float fd = (1.0 - m) * clamp(pc.misc.x, 0.0, 1.0) * prw_F_dielectric(mu);
    F.r = m * prw_F_schlick(pc.base.r, mu) + fd;
    F.g = m * prw_F_schlick(pc.base.g, mu) + fd;
    F.b = m * prw_F_schlick(pc.base.b, mu) + fd;
    // no NaN/Inf into the radiance: a non-finite mirror sample adds nothing
    vec3 L = finite_or_zero(full ? texelFetch(u_mirror, p, 0).rgb : textureLod(u_mirror, gl_FragCoord.xy / pc.misc.zw, 0.0).rgb);
    o_color = vec4(F * L, 0.0);
}
