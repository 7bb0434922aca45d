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
        int op = tm_mode_op();
        float exposure = P.range.x, lmin = P.range.y, lmax = P.range.z, dl = P.range.w;
        float white_cd = P.enc.w;
        vec3 raw = texelFetch(src, ivec2(p), 0).rgb;
        vec3 c = vec3(san(raw.r), san(raw.g), san(raw.b));
        float L = lum3(c);
        vec3 r;
        float ry;
        if (op == OP_EXPOSURE) {
            vec3 x = P.op1.x * exposure * c;
            if (max(x.r, max(x.g, x.b)) > 1.0) flags |= F_ABOVE;
            r = min(x, vec3(1.0));
            ry = lum3(r);
        } else if (op == OP_REINHARD) {
            float lavg = max(tm_log_avg(), LOG_DELTA);
            float scale = P.op1.y / lavg;
            float w = P.op1.z > 0.0 ? P.op1.z : WHITE_HEADROOM * scale * st.final_stats.y;
            float w2 = max(w * w, 1e-12);
            float ls = scale * L;
            float ld = ls / (1.0 + ls) * (1.0 + ls / w2);
            if (ld > 1.0) {
                flags |= F_ABOVE;
                ld = 1.0;
            }
            float k = L > 0.0 ? ld / L : 0.0;
            r = c * k;
            ry = ld;
        } else if (op == OP_LOCAL || op == OP_SELECTIVE) {
            // the global curve of the selective framework, Ld = L / (1 + L)
            float ls = P.op1.y / max(tm_log_avg(), LOG_DELTA) * L;
            ry = ls / (1.0 + ls);
            r = c * (L > 0.0 ? ry / L : 0.0);
        } else if (op == OP_NEUTRAL) {
            r = pbr_neutral(P.op1.x * exposure * c);
            ry = lum3(r);
        } else {
            if (op == OP_ADAPTIVE) {
                float lp = white_cd * exposure * L;
                float knee = P.op1.w;
                if (knee > 0.0 && lp < knee) {
                    ry = (knee - lmin) / dl * pow(lp / knee, P.op2.x);
                } else {
                    // shoulder constants from the frame statistics (prw_tm_derive)
                    float U = log(max(WHITE_HEADROOM * exposure * st.final_stats.y, 1e-30));
                    float V = log(lmax / white_cd);
                    bool on = V > 0.0 && U > V * (1.0 + 1e-6);
                    if (lp <= white_cd || !on) {
                        ry = (min(lp, lmax) - lmin) / dl;
                    } else {
                        float lam = P.op2.y;
                        float m = lam * V / U, a = 1.0 - m;
                        float b = (a * U / ((1.0 - lam) * V) - 1.0) / U;
                        float u = log(lp / white_cd);
                        float v = min(a * u / (1.0 + b * u) + m * u, V);
                        ry = (white_cd * exp(v) - lmin) / dl;
                    }
                }
            } else {
                if (L < lmin) flags |= F_BELOW;
                if (L > lmax) flags |= F_ABOVE;
                ry = (clamp(L, lmin, lmax) - lmin) / dl;
            }
            float yt = lmin + ry * dl;
            r = L > 0.0 ? ry + yt / dl * (c / L - 1.0) : vec3(ry);
        }
        vec3 v = tm_finish(r, ry, flags);
        imageStore(sig, ivec2(p), vec4(v, 1.0));
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
