#version 450
// The global operators' tone map as a full-screen fragment pass (tonemap_gpu.c, when nothing is counted
// and no statistics are computed with it): on lavapipe a colour attachment is written by vectorised
// format code, a compute shader's imageStore lane by lane (prw tmbench --vs-copy yardsticks).  The
// same tm_pixel as tonemap_apply.comp; specialisation constants 0 (operator) and 1 (encoding); 2 and
// 3 (overlay, counting) are 0.  TM_FRAG_SIGNAL: the float signal too (location 1, RGBA32F).
#extension GL_GOOGLE_include_directive : require
#include "tonemap_common.glsl"
#include "tonemap_apply.glsl"

layout(location = 0) out vec4 o_ldr;
#ifdef TM_FRAG_SIGNAL
layout(location = 1) out vec4 o_sig;
#endif

void main()
{
    uint flags = 0u;
    float L;
    vec3 v = tm_pixel(texelFetch(src, ivec2(gl_FragCoord.xy), 0).rgb, L, flags);
    o_ldr = vec4(v, 1.0);
#ifdef TM_FRAG_SIGNAL
    o_sig = vec4(v, 1.0);
#endif
}
