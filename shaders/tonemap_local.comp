#version 450
// Local tone mapping (pass_tonemap.c): Reinhard, Stark, Shirley, Ferwerda 2002 eqs. 5-9 on one 16 x 16
// block per workgroup.  The scaled luminance of the block and a 33-pixel clamp-to-edge halo is kept in
// shared memory; each of the 9 Gaussian levels (sigma = 0.25 * 1.6^j) is a horizontal then a
// vertical pass in shared memory; each pixel picks its scale as it goes (eq. 8) and maps
// Ld = L / (1 + V1(s_m)) (eq. 9).  Selective: blended with Ld = L / (1 + L) by the tile weight.
// Used for the operator "local" with settings.local_tiled (a benchmark baseline: the separable passes
// of tonemap_sep_*.comp are faster on lavapipe).  pc.base = 0: the workgroup grid is the block grid;
// 1: blocks from list 0 of tonemap_compact.comp (dispatched indirectly).
// Mirror of prw_tm_local_ld / prw_tm_apply (tonemap_ops.c).
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 16, local_size_y = 16) in;
#include "tonemap_common.glsl"

const int HALO = 33;             // the largest radius, ceil(3 * 0.25 * 1.6^8)
const int SIDE = 16 + 2 * HALO;  // 82
const int RAD[9] = int[9](1, 2, 2, 4, 5, 8, 13, 21, 33); // prw_tm_local_radius
const int SCALES = 8;
const float PHI2 = 256.0;        // 2^phi, phi = 8
const float EPS = 0.05;

shared float sL[SIDE * SIDE];
shared float sT[SIDE * 16];
shared uint s_cnt[3];

void main()
{
    uint t = gl_LocalInvocationIndex;
    uint bx = tm_blocks_x();
    uint block = pc.base == 0u ? gl_WorkGroupID.y * bx + gl_WorkGroupID.x
                               : tl.data[tm_tiles_x() * tm_tiles_y() + bx * tm_blocks_y() + gl_WorkGroupID.x];
    ivec2 org = ivec2(int(block % bx), int(block / bx)) * 16;
    ivec2 hi = ivec2(int(pc.width) - 1, int(pc.height) - 1);
    float scale = P.op1.y / max(tm_log_avg(), LOG_DELTA);
    if (t < 3u) s_cnt[t] = 0u;
    for (uint i = t; i < uint(SIDE * SIDE); i += 256u) {
        ivec2 q = clamp(org - HALO + ivec2(int(i) % SIDE, int(i) / SIDE), ivec2(0), hi);
        sL[i] = scale * lum3(san3(texelFetch(src, q, 0).rgb));
    }
    ivec2 lp = ivec2(gl_LocalInvocationID.xy);
    float Lc = 0.0, prev = 0.0, chosen = 0.0;
    bool done = false;
    for (int lev = 0; lev <= SCALES; lev++) {
        int R = RAD[lev];
        float sg = 0.25 * pow(1.6, float(lev));
        float k[HALO + 1]; // the kernel, normalised (every invocation computes the same values)
        float norm = 0.0;
        for (int q = 0; q <= R; q++) {
            k[q] = exp(-float(q * q) / (2.0 * sg * sg));
            norm += q == 0 ? k[q] : 2.0 * k[q];
        }
        for (int q = 0; q <= R; q++) k[q] /= norm;
        barrier(); // the previous level is finished with sT (and sL is loaded)
        uint rows = uint(16 + 2 * R);
        for (uint i = t; i < rows * 16u; i += 256u) {
            int base = (HALO - R + int(i / 16u)) * SIDE + HALO + int(i % 16u);
            float s = k[0] * sL[base];
            for (int q = 1; q <= R; q++) s += k[q] * (sL[base - q] + sL[base + q]);
            sT[(HALO - R) * 16 + int(i)] = s;
        }
        barrier();
        int row = HALO + lp.y;
        int tb = row * 16 + lp.x;
        float v = k[0] * sT[tb];
        for (int q = 1; q <= R; q++) v += k[q] * (sT[tb - 16 * q] + sT[tb + 16 * q]);
        if (lev == 0) {
            chosen = v;
            Lc = sL[row * SIDE + HALO + lp.x];
        } else if (!done) {
            float sc = pow(1.6, float(lev - 1));
            float vv = (prev - v) / (PHI2 * P.op1.y / (sc * sc) + prev);
            if (abs(vv) < EPS) chosen = prev;
            else done = true;
        }
        prev = v;
    }
    ivec2 p = org + lp;
    uint flags = 0u;
    bool inside = p.x < int(pc.width) && p.y < int(pc.height);
    if (inside) {
        float ld = Lc / (1.0 + chosen);
        if (P.mode.x == OP_SELECTIVE) {
            float w = tm_sel_weight(p);
            ld = w * ld + (1.0 - w) * (Lc / (1.0 + Lc));
        }
        vec3 c = san3(texelFetch(src, p, 0).rgb);
        vec3 v = tm_ratio(c, ld, flags);
        if (tm_mode_signal()) imageStore(sig, p, vec4(v, 1.0));
        imageStore(ldr, p, vec4(v, 1.0));
        if (P.mode.w != 0) {
            if ((flags & F_BELOW) != 0u) atomicAdd(s_cnt[0], 1u);
            if ((flags & F_ABOVE) != 0u) atomicAdd(s_cnt[1], 1u);
            if ((flags & F_GAMUT) != 0u) atomicAdd(s_cnt[2], 1u);
        }
    }
    barrier();
    if (t == 0u && P.mode.w != 0) {
        atomicAdd(st.counts.x, s_cnt[0]);
        atomicAdd(st.counts.y, s_cnt[1]);
        atomicAdd(st.counts.z, s_cnt[2]);
        uint w = uint(min(16, int(pc.width) - org.x)), h = uint(min(16, int(pc.height) - org.y));
        atomicAdd(st.counts.w, w * h);
    }
}
