#version 450
// Yardstick of the tone-mapping stage as a full-screen fragment pass (tonemap_gpu.c
// prw_tm_session_time_floor): texelFetch of the pixel -> the RGBA8 colour attachment, and with
// TM_FLOOR_TWO also the RGBA32F one (the apply's two outputs).
layout(set = 0, binding = 0) uniform sampler2D src;
layout(location = 0) out vec4 o_ldr;
#ifdef TM_FLOOR_TWO
layout(location = 1) out vec4 o_sig;
#endif
void main()
{
    vec4 c = texelFetch(src, ivec2(gl_FragCoord.xy), 0);
    o_ldr = clamp(c, 0.0, 1.0);
#ifdef TM_FLOOR_TWO
    o_sig = c;
#endif
}
