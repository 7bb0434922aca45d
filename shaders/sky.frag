#version 450
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "env_lookup.glsl"

// The environment seen directly (emission, k = 0: the path tracer's escaping camera rays) behind every
// surface: level 0 of the prefiltered maps (roughness 0) in the pixel's view direction.  PRW_GBUFFER also
// writes the G-buffer's clear values (nothing drawn there).
layout(location = 0) in vec2 v_ndc;
layout(location = 0) out vec4 o_color;
#ifdef PRW_GBUFFER
layout(location = 1) out vec4 o_normal;
layout(location = 2) out uint o_id;
#endif

void main()
{
    vec4 p = inverse(g.view_proj) * vec4(v_ndc, 1.0, 1.0); // a point on the near plane (reversed Z)
    vec3 d = normalize(p.xyz / p.w - g.eye_rel.xyz);
    o_color = vec4(prw_env_level(d, 0.0), 1.0);
#ifdef PRW_GBUFFER
    o_normal = vec4(0.0);
    o_id = 0u;
#endif
}
