#version 450
// Statistics and tone map in one pass (tonemap_gpu.c, operators that do not key on the frame's
// statistics: exposure, neutral, absolute), when the statistics or pixel counts are wanted (report,
// overlay, absolute, adaptation): each 16 x 16 workgroup covers a 64 x 64 region as tonemap_stats.glsl
// does, each invocation tone-maps its 16 pixels (tonemap_apply.glsl) and keeps the statistics' sums
// and its pixel counts in registers; one partial of each per invocation (no barrier, no atomics), the
// statistics at pc.base + i and the counts (below, above, out of gamut, pixels) at pc.total + pc.base
// + i, summed by tonemap_reduce.comp.  Specialisation constants as tonemap_apply.comp.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
layout(local_size_x = 16, local_size_y = 16) in;
#include "tonemap_common.glsl"
#include "tonemap_apply.glsl"

void main()
{
    ivec2 org = ivec2(gl_WorkGroupID.xy) * 64, lp = ivec2(gl_LocalInvocationID.xy);
    ivec2 size = ivec2(int(pc.width), int(pc.height));
    float s = 0.0, m = 0.0, n = 0.0;
    uint cb = 0u, ca = 0u, cg = 0u;
    // not unrolled: 16 copies of the tone map make the JIT code larger than the instruction cache
    [[dont_unroll]] for (int it = 0; it < 16; it++) {
            ivec2 q = org + lp + 16 * ivec2(it & 3, it >> 2);
            if (any(greaterThanEqual(q, size))) continue;
            uint flags = 0u;
            float y;
            vec3 v = tm_pixel(texelFetch(src, q, 0).rgb, y, flags);
            if (tm_mode_signal()) imageStore(sig, q, vec4(v, 1.0));
            imageStore(ldr, q, vec4(v, 1.0));
            s += log(LOG_DELTA + y);
            m = max(m, y);
            n += 1.0;
            cb += flags & F_BELOW;
            ca += (flags & F_ABOVE) >> 1;
            cg += (flags & F_GAMUT) >> 2;
        }
    uint k = pc.base + (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 256u + gl_LocalInvocationIndex;
    st.partial[k] = vec4(s, m, n, 0.0);
    if (tm_mode_count()) st.partial[pc.total + k] = vec4(float(cb), float(ca), float(cg), n);
}
