#version 450
// Display-aware tone mapping (pass_tonemap.c "tonemap"): operator -> gamut mapping -> inverse display
// model, for one view.  The float mirror of engine/render/tonemap_ops.c (prw_tm_pixel): see
// prw_tonemap.h for the operators and their sources (Reinhard et al. 2002 eqs. 1-4; Khronos PBR
// Neutral 2024; the display model of Mantiuk, Daly, Kerofsky 2008; SMPTE ST 2084; IEC 61966-2-1;
// ITU-R BT.1886).  Writes the signal V as float (before quantisation) and as RGBA8.
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0) uniform sampler2D src;
layout(set = 0, binding = 1, rgba8) uniform writeonly image2D ldr;
layout(set = 0, binding = 2, rgba32f) uniform writeonly image2D sig;
layout(set = 0, binding = 3, std430) buffer prw_tm_stats_buf {
    vec4 final_stats; // log-average, max, count, sum
    uvec4 counts;     // below black, above peak, out of gamut, pixels
    vec4 partial[];
} st;
layout(set = 0, binding = 4, std140) uniform prw_tm_params {
    ivec4 mode;  // op, eotf, overlay, count
    vec4 range;  // exposure, lmin, lmax, dl
    vec4 disp;   // black, peak, refl, gamma
    vec4 enc;    // enc_scale, bt_a, bt_b, white_cd
    vec4 op1;    // gain, key, white, knee
    vec4 op2;    // toe_p, lambda, -, -
    vec4 m0, m1, m2; // Rec.709 -> display primaries, rows
} P;
layout(push_constant) uniform prw_tm_pc {
    uint width, height, base, total;
} pc;

const int OP_EXPOSURE = 0, OP_REINHARD = 1, OP_NEUTRAL = 2, OP_ADAPTIVE = 3, OP_ABSOLUTE = 4;
const int EOTF_SRGB = 0, EOTF_GAMMA = 1, EOTF_BT1886 = 2, EOTF_PQ = 3;
const uint F_BELOW = 1u, F_ABOVE = 2u, F_GAMUT = 4u;
const float LOG_DELTA = 1e-6;
const float GAMUT_EPS = 1e-6;

shared uint s_cnt[3];

float san(float x) { return (isnan(x) || !(x > 0.0)) ? 0.0 : min(x, 1e12); }
float lum3(vec3 c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }

float srgb_oetf(float x)
{
    x = clamp(x, 0.0, 1.0);
    return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055;
}

float pq_inverse(float cd)
{
    // SMPTE ST 2084: E = ((c1 + c2 Y^m1) / (1 + c3 Y^m1))^m2, Y = L / 10000
    const float m1 = 2610.0 / 16384.0, m2 = 2523.0 / 32.0;
    const float c1 = 3424.0 / 4096.0, c2 = 2413.0 / 128.0, c3 = 2392.0 / 128.0;
    float y = clamp(cd / 10000.0, 0.0, 1.0);
    float p = pow(y, m1);
    return pow((c1 + c2 * p) / (1.0 + c3 * p), m2);
}

float encode(float r)
{
    r = clamp(r, 0.0, 1.0);
    int eotf = P.mode.y;
    if (eotf == EOTF_SRGB) return srgb_oetf(r * P.enc.x);
    if (eotf == EOTF_GAMMA) {
        float x = r * P.enc.x;
        return x > 0.0 ? pow(x, 1.0 / P.disp.w) : 0.0;
    }
    if (eotf == EOTF_BT1886) {
        float em = P.disp.x + r * P.range.w;
        return clamp(pow(em / P.enc.y, 1.0 / P.disp.w) - P.enc.z, 0.0, 1.0);
    }
    return pq_inverse(P.disp.x + r * P.range.w);
}

vec3 pbr_neutral(vec3 c)
{
    // Khronos PBR Neutral (2024): F90 = 0.04, compression starts at 0.8 - 0.04, desaturation 0.15
    const float start = 0.8 - 0.04, desat = 0.15;
    float x = min(c.r, min(c.g, c.b));
    float offset = x < 0.08 ? x - 6.25 * x * x : 0.04;
    c -= offset;
    float peak = max(c.r, max(c.g, c.b));
    if (peak < start) return c;
    float d = 1.0 - start;
    float np = 1.0 - d * d / (peak + d - start);
    c *= np / peak;
    float g = 1.0 - 1.0 / (desat * (peak - np) + 1.0);
    return mix(c, vec3(np), g);
}

void main()
{
    uvec2 p = gl_GlobalInvocationID.xy;
    uint t = gl_LocalInvocationIndex;
    if (t < 3u) s_cnt[t] = 0u;
    barrier();
    bool inside = p.x < pc.width && p.y < pc.height;
    uint flags = 0u;
    if (inside) {
        int op = P.mode.x;
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
            float lavg = max(st.final_stats.x, LOG_DELTA);
            float scale = P.op1.y / lavg;
            float w = P.op1.z > 0.0 ? P.op1.z : scale * st.final_stats.y;
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
                    float U = log(max(exposure * st.final_stats.y, 1e-30));
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
        ry = clamp(ry, 0.0, 1.0);
        vec3 d = vec3(dot(P.m0.xyz, r), dot(P.m1.xyz, r), dot(P.m2.xyz, r));
        float tt = 1.0, lim_val = 0.0;
        int lim = -1; // the limiting channel lands exactly on its bound (see tonemap_ops.c)
        for (int i = 0; i < 3; i++) {
            if (d[i] > 1.0 + GAMUT_EPS && (1.0 - ry) / (d[i] - ry) < tt) {
                tt = (1.0 - ry) / (d[i] - ry);
                lim = i;
                lim_val = 1.0;
            }
            if (d[i] < -GAMUT_EPS && ry / (ry - d[i]) < tt) {
                tt = ry / (ry - d[i]);
                lim = i;
                lim_val = 0.0;
            }
        }
        if (tt < 1.0) flags |= F_GAMUT;
        if (ry <= 0.0 || ry >= 1.0) { // only grey at L_min and L_max (tonemap_ops.c)
            tt = 0.0;
            lim = -1;
        }
        vec3 v;
        for (int i = 0; i < 3; i++) v[i] = encode(i == lim ? lim_val : ry + tt * (d[i] - ry));
        if (P.mode.z != 0 && flags != 0u) {
            v.r = ((flags & (F_ABOVE | F_GAMUT)) != 0u && (flags & F_BELOW) == 0u) ? 1.0 : 0.0;
            v.g = 0.0;
            v.b = ((flags & (F_BELOW | F_GAMUT)) != 0u && (flags & F_ABOVE) == 0u) ? 1.0 : 0.0;
        }
        imageStore(sig, ivec2(p), vec4(v, 1.0));
        imageStore(ldr, ivec2(p), vec4(v, 1.0));
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
        uint w = min(8u, pc.width - min(pc.width, gl_WorkGroupID.x * 8u));
        uint h = min(8u, pc.height - min(pc.height, gl_WorkGroupID.y * 8u));
        atomicAdd(st.counts.w, w * h);
    }
}
