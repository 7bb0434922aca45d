#version 450
// Selective tone mapping, step 2 (pass_tonemap.c): one workgroup.  A 16 x 16 block needs the local
// operator when its tile or one of the 8 neighbouring tiles is marked (the blend band).  Lists of
// blocks (each with its indirect dispatch command in the header, x = count):
//   list 0: the needed blocks (vertical blur passes, final step);
//   list k = 1..3: blocks within k blocks above or below a needed one (horizontal pass of a level of
//   radius R <= 16 k: its result is read up to R rows away);
//   list 4: blocks within 3 blocks of a needed one in both directions (scaled luminance, read by
//   the horizontal passes up to 33 pixels away).
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 256) in;
#include "tonemap_common.glsl"

shared uint s_cnt[5], s_marked;

void main()
{
    uint t = gl_LocalInvocationIndex;
    if (t < 5u) s_cnt[t] = 0u;
    if (t == 0u) s_marked = 0u;
    barrier();
    int tx = int(tm_tiles_x()), ty = int(tm_tiles_y());
    uint ntiles = uint(tx * ty), bx = tm_blocks_x(), by = tm_blocks_y(), nblocks = bx * by;
    int sub = int(P.op2.w) / 16;
    for (uint b = t; b < nblocks; b += 256u) {
        int ci = int(b % bx) / sub, cj = int(b / bx) / sub;
        uint need = 0u;
        for (int j = cj - 1; j <= cj + 1; j++)
            for (int i = ci - 1; i <= ci + 1; i++)
                if (i >= 0 && j >= 0 && i < tx && j < ty && tl.data[j * tx + i] != 0u) need = 1u;
        tl.data[ntiles + b] = need;
    }
    for (uint i = t; i < ntiles; i += 256u)
        if (tl.data[i] != 0u) atomicAdd(s_marked, 1u);
    memoryBarrierBuffer();
    barrier();
    for (uint b = t; b < nblocks; b += 256u) {
        int x = int(b % bx), y = int(b / bx);
        int dv = 99;
        bool near = false;
        for (int j = max(y - 3, 0); j <= min(y + 3, int(by) - 1); j++)
            for (int i = max(x - 3, 0); i <= min(x + 3, int(bx) - 1); i++)
                if (tl.data[ntiles + uint(j) * bx + uint(i)] != 0u) {
                    near = true;
                    if (i == x) dv = min(dv, abs(j - y));
                }
        for (int k = 0; k < 4; k++)
            if (dv <= k) tl.data[ntiles + nblocks * uint(1 + k) + atomicAdd(s_cnt[k], 1u)] = b;
        if (near) tl.data[ntiles + nblocks * 5u + atomicAdd(s_cnt[4], 1u)] = b;
    }
    barrier();
    if (t < 5u) {
        tl.hdr[3u * t] = s_cnt[t];
        tl.hdr[3u * t + 1u] = 1u;
        tl.hdr[3u * t + 2u] = 1u;
    }
    if (t == 0u) {
        tl.hdr[15] = s_marked;
        tl.hdr[16] = ntiles;
        tl.hdr[17] = s_cnt[0];
        tl.hdr[18] = nblocks;
    }
}
