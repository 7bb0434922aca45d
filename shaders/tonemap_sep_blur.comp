#version 450
// Separable local tone mapping, step 2: blur level pc.base; pc.total = 0: horizontal, layer 0 -> 1;
// 1: vertical, layer 1 -> 2 + level.  Selective: only the blocks whose result is read (lists), and in
// the horizontal pass only the rows the vertical pass reads (within R rows of a needed block of the
// same block column; a row is two SIMD batches on lavapipe, so skipped rows cost nothing).
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 16, local_size_y = 16) in;
#include "tonemap_common.glsl"
#include "tonemap_sep.glsl"

// Selective, horizontal pass: is row p.y read by the vertical pass of radius R in p's block column?
bool row_read(ivec2 p, int R)
{
    uint bx = tm_blocks_x(), need = tm_tiles_x() * tm_tiles_y();
    int cx = p.x / 16, cy = p.y / 16;
    for (int j = max(cy - 3, 0); j <= min(cy + 3, int(tm_blocks_y()) - 1); j++)
        if (tl.data[need + uint(j) * bx + uint(cx)] != 0u && max(max(16 * j - p.y, p.y - 16 * j - 15), 0) <= R)
            return true;
    return false;
}

void main()
{
    int lev = int(pc.base), R = SEP_RAD[lev];
    ivec2 p = sep_pixel(pc.total != 0u ? 0 : (R + 15) / 16);
    if (p.x >= int(pc.width) || p.y >= int(pc.height)) return;
    if (pc.total == 0u && P.mode.x == OP_SELECTIVE && !row_read(p, R)) return;
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
