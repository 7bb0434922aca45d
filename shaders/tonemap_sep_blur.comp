#version 450
// Separable local tone mapping, step 2: blur level pc.base; pc.total = 0: horizontal, layer 0 -> 1;
// 1: vertical, layer 1 -> 2 + level.  Selective: only the blocks whose result is read (lists).
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 16, local_size_y = 16) in;
#include "tonemap_common.glsl"
#include "tonemap_sep.glsl"

void main()
{
    int lev = int(pc.base), R = SEP_RAD[lev];
    ivec2 p = sep_pixel(pc.total != 0u ? 0 : (R + 15) / 16);
    if (p.x >= int(pc.width) || p.y >= int(pc.height)) return;
    float sg = 0.25 * pow(1.6, float(lev));
    float k[34];
    float norm = 0.0;
    for (int q = 0; q <= R; q++) {
        k[q] = exp(-float(q * q) / (2.0 * sg * sg));
        norm += q == 0 ? k[q] : 2.0 * k[q];
    }
    bool vertical = pc.total != 0u;
    int from = vertical ? 1 : 0, to = vertical ? 2 + lev : 1;
    ivec2 d = vertical ? ivec2(0, 1) : ivec2(1, 0);
    ivec2 hi = ivec2(int(pc.width) - 1, int(pc.height) - 1);
    float s = k[0] / norm * imageLoad(scratch, ivec3(p, from)).r;
    for (int q = 1; q <= R; q++) {
        float a = imageLoad(scratch, ivec3(clamp(p - q * d, ivec2(0), hi), from)).r;
        float b = imageLoad(scratch, ivec3(clamp(p + q * d, ivec2(0), hi), from)).r;
        s += k[q] / norm * (a + b);
    }
    imageStore(scratch, ivec3(p, to), vec4(s));
}
