#version 450
// Separable local tone mapping, step 3: scale selection (Reinhard 2002 eq. 8) over the 9 levels,
// Ld = L / (1 + V1(s_m)) (eq. 9), colour by Ld / Lw, gamut mapping and encoding.  Selective: only
// the blocks that need the local operator, blended with the global curve L / (1 + L) by the weight.
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 16, local_size_y = 16) in;
#include "tonemap_common.glsl"
#include "tonemap_sep.glsl"

shared uint s_cnt[3];

void main()
{
    ivec2 p = sep_pixel(0);
    uint t = gl_LocalInvocationIndex;
    bool count = P.mode.w != 0; // uniform: shared counters and barriers only when counting
    if (count) {
        if (t < 3u) s_cnt[t] = 0u;
        barrier();
    }
    bool inside = p.x < int(pc.width) && p.y < int(pc.height);
    uint flags = 0u;
    if (inside) {
        float Lc = imageLoad(scratch, ivec3(p, 0)).r;
        float prev = imageLoad(scratch, ivec3(p, 2)).r, chosen = prev;
        for (int lev = 1; lev <= 8; lev++) {
            float v = imageLoad(scratch, ivec3(p, 2 + lev)).r;
            float sc = pow(1.6, float(lev - 1));
            float vv = (prev - v) / (256.0 * P.op1.y / (sc * sc) + prev);
            if (abs(vv) < 0.05) chosen = prev;
            else break;
            prev = v;
        }
        vec3 c = san3(texelFetch(src, p, 0).rgb);
        float ld = Lc / (1.0 + chosen);
        if (P.mode.x == OP_SELECTIVE) {
            float w = tm_sel_weight(p);
            ld = w * ld + (1.0 - w) * (Lc / (1.0 + Lc));
        }
        vec3 o = tm_ratio(c, ld, flags);
        if (tm_mode_signal()) imageStore(sig, p, vec4(o, 1.0));
        imageStore(ldr, p, vec4(o, 1.0));
        if (count) {
            if ((flags & F_BELOW) != 0u) atomicAdd(s_cnt[0], 1u);
            if ((flags & F_ABOVE) != 0u) atomicAdd(s_cnt[1], 1u);
            if ((flags & F_GAMUT) != 0u) atomicAdd(s_cnt[2], 1u);
        }
    }
    if (!count) return;
    barrier();
    if (t == 0u) {
        atomicAdd(st.counts.x, s_cnt[0]);
        atomicAdd(st.counts.y, s_cnt[1]);
        atomicAdd(st.counts.z, s_cnt[2]);
        ivec2 org = p - ivec2(gl_LocalInvocationID.xy);
        uint w = uint(min(16, int(pc.width) - org.x)), h = uint(min(16, int(pc.height) - org.y));
        atomicAdd(st.counts.w, w * h);
    }
}
