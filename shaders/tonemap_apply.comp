#version 450
// Display-aware tone mapping (pass_tonemap.c "tonemap"): operator -> gamut mapping -> inverse display
// model, for one view.  The float mirror of engine/render/tonemap_ops.c (prw_tm_pixel): see
// prw_tonemap.h for the operators and their sources (Reinhard et al. 2002 eqs. 1-4; Khronos PBR
// Neutral 2024; the display model of Mantiuk, Daly, Kerofsky 2008; SMPTE ST 2084; IEC 61966-2-1;
// ITU-R BT.1886).  Writes the signal V as float (before quantisation) and as RGBA8.
#extension GL_GOOGLE_include_directive : require
// One 16 x 16 block per workgroup (selective skips whole blocks; on lavapipe larger workgroups also
// cost less per pixel); the counters' shared memory and barriers only when counting.  The operator,
// encoding, overlay and counting are specialisation constants (tonemap_common.glsl).
layout(local_size_x = 16, local_size_y = 16) in;
#include "tonemap_common.glsl"
#include "tonemap_apply.glsl"

shared uint s_cnt[3];

void main()
{
    uvec2 p = gl_GlobalInvocationID.xy;
    uint t = gl_LocalInvocationIndex;
    bool count = tm_mode_count();
    if (count) {
        if (t < 3u) s_cnt[t] = 0u;
        barrier();
    }
    bool inside = p.x < pc.width && p.y < pc.height;
    // selective: the blocks the local pass covers are skipped (uniform per 8 x 8 workgroup)
    bool skip = false;
    if (tm_mode_op() == OP_SELECTIVE) {
        uvec2 b = gl_WorkGroupID.xy;
        skip = tl.data[tm_tiles_x() * tm_tiles_y() + b.y * tm_blocks_x() + b.x] != 0u;
    }
    inside = inside && !skip;
    uint flags = 0u;
    if (inside) {
        float L;
        vec3 v = tm_pixel(texelFetch(src, ivec2(p), 0).rgb, L, flags);
        if (tm_mode_signal()) imageStore(sig, ivec2(p), vec4(v, 1.0));
        imageStore(ldr, ivec2(p), vec4(v, 1.0));
        if (count) {
            if ((flags & F_BELOW) != 0u) atomicAdd(s_cnt[0], 1u);
            if ((flags & F_ABOVE) != 0u) atomicAdd(s_cnt[1], 1u);
            if ((flags & F_GAMUT) != 0u) atomicAdd(s_cnt[2], 1u);
        }
    }
    if (!count) return;
    barrier();
    if (t == 0u && !skip) {
        atomicAdd(st.counts.x, s_cnt[0]);
        atomicAdd(st.counts.y, s_cnt[1]);
        atomicAdd(st.counts.z, s_cnt[2]);
        uint w = min(16u, pc.width - min(pc.width, gl_WorkGroupID.x * 16u));
        uint h = min(16u, pc.height - min(pc.height, gl_WorkGroupID.y * 16u));
        atomicAdd(st.counts.w, w * h);
    }
}
