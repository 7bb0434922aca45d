#version 450
// Selective tone mapping, step 1 (pass_tonemap.c): one workgroup per T x T tile marks the tile
// important when the largest Sobel gradient magnitude |(Gx, Gy)| / 8 of log10(delta + Y) inside it
// exceeds the threshold (log10 units per pixel).  Mirror of prw_tm_classify (tonemap_ops.c).
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 16, local_size_y = 16) in;
#include "tonemap_common.glsl"

shared uint s_max;

float lg(ivec2 q)
{
    q = clamp(q, ivec2(0), ivec2(int(pc.width) - 1, int(pc.height) - 1));
    return log2(LOG_DELTA + lum3(san3(texelFetch(src, q, 0).rgb))) * 0.30102999566398120;
}

void main()
{
    uint t = gl_LocalInvocationIndex;
    if (t == 0u) s_max = 0u;
    barrier();
    int T = int(P.op2.w);
    ivec2 org = ivec2(gl_WorkGroupID.xy) * T;
    float g = 0.0;
    for (int sy = 0; sy < T; sy += 16)
        for (int sx = 0; sx < T; sx += 16) {
            ivec2 p = org + ivec2(sx, sy) + ivec2(gl_LocalInvocationID.xy);
            if (p.x >= int(pc.width) || p.y >= int(pc.height)) continue;
            float a = lg(p + ivec2(-1, -1)), b = lg(p + ivec2(0, -1)), c = lg(p + ivec2(1, -1));
            float d = lg(p + ivec2(-1, 0)), f = lg(p + ivec2(1, 0));
            float h = lg(p + ivec2(-1, 1)), i = lg(p + ivec2(0, 1)), j = lg(p + ivec2(1, 1));
            float gx = (c + 2.0 * f + j) - (a + 2.0 * d + h);
            float gy = (h + 2.0 * i + j) - (a + 2.0 * b + c);
            g = max(g, sqrt(gx * gx + gy * gy) / 8.0);
        }
    atomicMax(s_max, floatBitsToUint(g)); // non-negative floats order like their bits
    barrier();
    if (t == 0u) tl.data[gl_WorkGroupID.y * tm_tiles_x() + gl_WorkGroupID.x] = uintBitsToFloat(s_max) > P.op2.z ? 1u : 0u;
}
