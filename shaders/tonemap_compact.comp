#version 450
// Selective tone mapping, step 2 (pass_tonemap.c): one workgroup.  A tile is marked when the largest
// gradient of its blocks (tonemap_classify.comp) exceeds the threshold.  A 16 x 16 block needs the local
// operator when its tile or one of the 8 neighbouring tiles is marked (the blend band).  Lists of
// blocks in raster order (each with its indirect dispatch command in the header, x = count):
//   list 0: the needed blocks (vertical blur passes, final step);
//   list k = 1..3: blocks within k blocks above or below a needed one (horizontal pass of a level of
//   radius R <= 16 k: its result is read up to R rows away);
//   list 4: blocks within 3 blocks of a needed one in both directions (scaled luminance, read by
//   the horizontal passes up to 33 pixels away).
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 256) in;
#include "tonemap_common.glsl"

shared uint s_cnt[5], s_marked;
shared uint s_pre[5 * 256];

// Lists of block b as bits: k = 0..3 when a needed block is within k blocks above or below (k = 0: b
// itself), 4 when one is within 3 blocks in both directions.
uint lists_of(uint b, uint ntiles, uint bx, uint by)
{
    int x = int(b % bx), y = int(b / bx);
    int dv = 99;
    bool near = false;
    for (int j = max(y - 3, 0); j <= min(y + 3, int(by) - 1); j++)
        for (int i = max(x - 3, 0); i <= min(x + 3, int(bx) - 1); i++)
            if (tl.data[ntiles + uint(j) * bx + uint(i)] != 0u) {
                near = true;
                if (i == x) dv = min(dv, abs(j - y));
            }
    uint m = near ? 16u : 0u;
    for (int k = 0; k < 4; k++)
        if (dv <= k) m |= 1u << k;
    return m;
}

void main()
{
    uint t = gl_LocalInvocationIndex;
    if (t < 5u) s_cnt[t] = 0u;
    if (t == 0u) s_marked = 0u;
    barrier();
    int tx = int(tm_tiles_x()), ty = int(tm_tiles_y());
    uint ntiles = uint(tx * ty), bx = tm_blocks_x(), by = tm_blocks_y(), nblocks = bx * by;
    int sub = int(P.op2.w) / 16;
    uint gbase = tm_bgrad_base();
    for (uint i = t; i < ntiles; i += 256u) {
        int x0 = int(i % uint(tx)) * sub, y0 = int(i / uint(tx)) * sub;
        uint g = 0u;
        for (int y = y0; y < min(y0 + sub, int(by)); y++)
            for (int x = x0; x < min(x0 + sub, int(bx)); x++) g = max(g, tl.data[gbase + uint(y) * bx + uint(x)]);
        tl.data[i] = uintBitsToFloat(g) > P.op2.z ? 1u : 0u;
    }
    memoryBarrierBuffer();
    barrier();
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
    // lists in raster order (so the indirect passes walk the image like the full ones): each invocation
    // takes a run of consecutive blocks, counts, an exclusive scan gives its offsets, then it writes
    uint chunk = (nblocks + 255u) / 256u, b0 = min(t * chunk, nblocks), b1 = min(b0 + chunk, nblocks);
    uint c[5] = uint[5](0u, 0u, 0u, 0u, 0u);
    for (uint b = b0; b < b1; b++) {
        uint m = lists_of(b, ntiles, bx, by);
        for (int k = 0; k < 5; k++) c[k] += (m >> k) & 1u;
    }
    for (int k = 0; k < 5; k++) s_pre[k * 256 + int(t)] = c[k];
    barrier();
    if (t < 5u) {
        uint acc = 0u;
        for (uint i = 0u; i < 256u; i++) {
            uint v = s_pre[t * 256u + i];
            s_pre[t * 256u + i] = acc;
            acc += v;
        }
        s_cnt[t] = acc;
    }
    barrier();
    for (int k = 0; k < 5; k++) c[k] = s_pre[k * 256 + int(t)];
    for (uint b = b0; b < b1; b++) {
        uint m = lists_of(b, ntiles, bx, by);
        for (int k = 0; k < 5; k++)
            if (((m >> k) & 1u) != 0u) tl.data[ntiles + nblocks * uint(1 + k) + c[k]++] = b;
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
