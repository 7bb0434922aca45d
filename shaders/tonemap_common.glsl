// Shared declarations of the tone-mapping compute shaders (pass_tonemap.c): bindings, the
// parameter block (std140 mirror of pass_tonemap.c's tm_ubo), the display encoding and the gamut
// mapping; the float mirror of engine/render/tonemap_ops.c.
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
    vec4 op2;    // toe_p, lambda, selective threshold, selective tile
    vec4 m0, m1, m2; // Rec.709 -> display primaries, rows
    vec4 adapt;      // temporal adaptation: adapted luminance La (cd/m^2), on (1) / off (0), -, -
} P;
layout(set = 0, binding = 5, std430) buffer prw_tm_tiles_buf {
    uint hdr[20]; // 5 indirect dispatches (x, y, z) of lists 0-4; tiles marked; tiles; blocks needed; blocks; -
    uint data[];  // marks[tiles], need[blocks], list 0-4 [blocks each], block gradients [blocks]
                  // (selective: tonemap_classify.comp, tonemap_compact.comp)
} tl;
layout(push_constant) uniform prw_tm_pc {
    uint width, height, base, total;
} pc;

// P.mode as specialisation constants (tonemap_gpu.c builds the apply pipeline per combination): on
// lavapipe every branch of a shader runs for every pixel (as masks), so a runtime choice between
// operators and encodings costs all of them.  -1: read P.mode (the other shaders).
layout(constant_id = 0) const int TM_SC_OP = -1;
layout(constant_id = 1) const int TM_SC_EOTF = -1;
layout(constant_id = 2) const int TM_SC_OVERLAY = -1;
layout(constant_id = 3) const int TM_SC_COUNT = -1;
// 4: the apply writes the float signal too (0: only the RGBA8 image; nobody reads the signal)
layout(constant_id = 4) const int TM_SC_SIGNAL = 1;
// 5: the display primaries are the working space's (P.m0-m2 the identity): no matrix (d = r exactly,
// as the identity's dot products give), and the compiler sees the gamut test's range
layout(constant_id = 5) const int TM_SC_IDENTITY = 0;
int tm_mode_op() { return TM_SC_OP >= 0 ? TM_SC_OP : P.mode.x; }
int tm_mode_eotf() { return TM_SC_EOTF >= 0 ? TM_SC_EOTF : P.mode.y; }
bool tm_mode_overlay() { return TM_SC_OVERLAY >= 0 ? TM_SC_OVERLAY != 0 : P.mode.z != 0; }
bool tm_mode_count() { return TM_SC_COUNT >= 0 ? TM_SC_COUNT != 0 : P.mode.w != 0; }
bool tm_mode_signal() { return TM_SC_SIGNAL != 0; }

const float WHITE_HEADROOM = 1.05; // PRW_TM_WHITE_HEADROOM (engine/render/prw_tonemap.h)
const int OP_EXPOSURE = 0, OP_REINHARD = 1, OP_NEUTRAL = 2, OP_ADAPTIVE = 3, OP_ABSOLUTE = 4;
const int OP_LOCAL = 5, OP_SELECTIVE = 6;
const int EOTF_SRGB = 0, EOTF_GAMMA = 1, EOTF_BT1886 = 2, EOTF_PQ = 3;
const uint F_BELOW = 1u, F_ABOVE = 2u, F_GAMUT = 4u;
const float LOG_DELTA = 1e-6;
const float GAMUT_EPS = 1e-6;


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
    int eotf = tm_mode_eotf();
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

// Gamut mapping (working -> display primaries, desaturation towards grey) and encoding of
// display-relative r with luminance ry (prw_tm_pixel's tail in tonemap_ops.c).
vec3 tm_finish(vec3 r, float ry, inout uint flags)
{
    ry = clamp(ry, 0.0, 1.0);
    vec3 d = TM_SC_IDENTITY != 0 ? r : vec3(dot(P.m0.xyz, r), dot(P.m1.xyz, r), dot(P.m2.xyz, r));
    float tt = 1.0, lim_val = 0.0;
    int lim = -1; // the limiting channel lands exactly on its bound (see tonemap_ops.c)
    for (int i = 0; i < 3; i++) {
        // above 1 and below 0 exclude each other: one division per channel, the same quotient as
        // tonemap_ops.c's (lavapipe runs both sides of every branch, so each division counts)
        bool hi = d[i] > 1.0 + GAMUT_EPS, lo = d[i] < -GAMUT_EPS;
        float t = (hi ? 1.0 - ry : ry) / (hi ? d[i] - ry : ry - d[i]);
        if ((hi || lo) && t < tt) {
            tt = t;
            lim = i;
            lim_val = hi ? 1.0 : 0.0;
        }
    }
    if (tt < 1.0) flags |= F_GAMUT;
    if (ry <= 0.0 || ry >= 1.0) { // only grey at L_min and L_max (tonemap_ops.c)
        tt = 0.0;
        lim = -1;
    }
    vec3 v;
    for (int i = 0; i < 3; i++) v[i] = encode(i == lim ? lim_val : ry + tt * (d[i] - ry));
    if (tm_mode_overlay() && flags != 0u) {
        v.r = ((flags & (F_ABOVE | F_GAMUT)) != 0u && (flags & F_BELOW) == 0u) ? 1.0 : 0.0;
        v.g = 0.0;
        v.b = ((flags & (F_BELOW | F_GAMUT)) != 0u && (flags & F_ABOVE) == 0u) ? 1.0 : 0.0;
    }
    return v;
}

// The log-average luminance the operators key on: this frame's, or the adapted one.
float tm_log_avg() { return P.adapt.y != 0.0 ? P.adapt.x : st.final_stats.x; }

vec3 san3(vec3 c) { return vec3(san(c.r), san(c.g), san(c.b)); }

// Luminance-ratio operators (local, selective): target relative luminance ld -> signal.
vec3 tm_ratio(vec3 c, float ld, inout uint flags)
{
    float L = lum3(c);
    if (!(ld <= 1.0)) {
        flags |= F_ABOVE;
        ld = 1.0;
    }
    ld = max(ld, 0.0);
    float k = L > 0.0 ? ld / L : 0.0;
    return tm_finish(c * k, ld, flags);
}

// Selective layout in tl.data for a width x height view: tiles of T = P.op2.w pixels, blocks of 16.
uint tm_tiles_x() { return (pc.width + uint(P.op2.w) - 1u) / uint(P.op2.w); }
uint tm_tiles_y() { return (pc.height + uint(P.op2.w) - 1u) / uint(P.op2.w); }
uint tm_blocks_x() { return (pc.width + 15u) / 16u; }
uint tm_blocks_y() { return (pc.height + 15u) / 16u; }
// where tonemap_classify.comp leaves each block's largest gradient (float bits)
uint tm_bgrad_base() { return tm_tiles_x() * tm_tiles_y() + 6u * tm_blocks_x() * tm_blocks_y(); }

// Selective blend weight of pixel p: smoothstep(1 - d / T), d = distance to the nearest marked tile.
float tm_sel_weight(ivec2 p)
{
    int T = int(P.op2.w);
    int tx = int(tm_tiles_x()), ty = int(tm_tiles_y());
    int cx = p.x / T, cy = p.y / T;
    float px = float(p.x) + 0.5, py = float(p.y) + 0.5, d2 = 1e30;
    bool any = false;
    for (int j = cy - 1; j <= cy + 1; j++)
        for (int i = cx - 1; i <= cx + 1; i++) {
            if (i < 0 || j < 0 || i >= tx || j >= ty || tl.data[j * tx + i] == 0u) continue;
            float dx = max(max(float(i * T) - px, px - float((i + 1) * T)), 0.0);
            float dy = max(max(float(j * T) - py, py - float((j + 1) * T)), 0.0);
            d2 = min(d2, dx * dx + dy * dy);
            any = true;
        }
    if (!any) return 0.0;
    float t = clamp(1.0 - sqrt(d2) / float(T), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}
