// lights.glsl — direct light of every light of the per-view globals at a surface point, in cd/m^2, with
// the shared material model (prw_brdf.h) and the shared falloff rules (prw_shading.h):
//  - point / spot / directional: f(n, v, l) E cos, E = intensity / d^2 (x range window, x spot cone) or
//    the directional illuminance, shadowed by shadows.glsl;
//  - rect area lights: diffuse (and the multiple-scattering specular) from Lambert's polygon formula
//    (exact irradiance, clipped to the receiver's hemisphere), single-scattering specular by a
//    lobe-resolving quadrature over the rectangle (rect_specular_single; linearly transformed cosines,
//    ltc.glsl, with PRW_RECT_LTC defined), visibility from the shadow map at the rectangle's centre:
//    hard, or soft with the quality knob soft_shadows (shadows.glsl, shadow_factor_rect).
// Needs common.glsl, shadows.glsl, prw_brdf.h and prw_shading.h included before it.
#include "polygon.glsl"
#include "ltc.glsl"
#ifndef PRW_LIGHTS_GLSL
#define PRW_LIGHTS_GLSL

const float PI = 3.14159265358979323846;

// Irradiance per unit radiance from the quad q0..q3 (camera-relative, convex, planar) at p with normal n,
// after clipping the quad to the hemisphere above p (Lambert's formula: E/L = 1/2 sum theta_i n.gamma_i).
// fdir receives the direction of the vector form factor (the irradiance-weighted mean direction).
float quad_irradiance(vec3 p, vec3 n, vec3 q0, vec3 q1, vec3 q2, vec3 q3, out vec3 fdir)
{
    fdir = n;
    vec3 sum;
    if (!quad_edge_sum(q0 - p, q1 - p, q2 - p, q3 - p, n, sum)) return 0.0;
    float e = dot(n, sum);
    if (e < 0.0) sum = -sum;
    float len = length(sum);
    if (len > 1e-12) fdir = sum / len;
    return 0.5 * abs(e);
}

// Single-scattering specular of a rect light (centre c, half axes du, dv, emitting towards +ln,
// radiance 1) at p: the D * V * cos factor is integrated by midpoint quadrature over the quad on a
// grid whose cells subtend at most half the GGX alpha (radians, seen from p), so the lobe is
// resolved.  When that grid would need more than PRW_RECT_NODES cells along an axis (a glossy surface
// reflecting a large light), the nodes are mapped instead: per axis x = x* + s tan(t), t uniform, with
// x* the mirror ray's hit on the light's plane and s = PRW_RECT_SCALE alpha times its distance, so
// PRW_RECT_NODES^2 nodes cluster where the GGX lobe is (its heavy tails are what the tan map's
// Jacobian s / cos^2 t follows): fewer nodes than the grid, and no longer the grid's dotted reflection
// at its 32 x 32 cap (materials/tools/rect_quad_study.c compares both rules with a converged
// quadrature).  Fresnel, which varies slowly over the light, is taken at the quadrature's D V-weighted
// mean cos(v, h).
#define PRW_RECT_NODES 10
#define PRW_RECT_SCALE 3.0
// shape (emissive meshes' lights, view_globals.c): 0 rectangle; 1 parallelogram and 2 triangle (corners c - du - dv,
// c + du - dv, c + du + dv: the grid's nodes beyond the diagonal dropped) take the grid only.
vec3 rect_specular_quadrature(vec3 p, vec3 n, vec3 v, vec3 c, vec3 du, vec3 dv, vec3 ln, vec3 base, float metallic,
                              float roughness, float specular, float shape)
{
    float alpha = prw_alpha_from_roughness(roughness);
    float dist = max(length(c - p), 1e-4);
    float lu = length(du), lv = length(dv);
    float cell = 0.5 * alpha * dist; // metres on the light per cell, at the light's distance
    int nu = int(clamp(ceil(2.0 * lu / cell), 1.0, 32.0));
    int nv = int(clamp(ceil(2.0 * lv / cell), 1.0, 32.0));
    float NoV = min(max(dot(n, v), 1e-4), 1.0);
    // the mirror ray's hit on the light's plane (light coordinates), if it reaches it
    vec3 r = 2.0 * dot(n, v) * n - v;
    float rl = dot(r, ln), tr = dot(c - p, ln) / rl;
    bool mapped = (nu > PRW_RECT_NODES || nv > PRW_RECT_NODES) && rl < 0.0 && tr > 0.0 && shape == 0.0;
    float xu = 0.0, xv = 0.0, s = 1.0, tu0 = 0.0, tv0 = 0.0, Tu = 0.0, Tv = 0.0, dtu = 0.0, dtv = 0.0;
    if (mapped) {
        vec3 hit = p + r * tr - c;
        xu = dot(hit, du) / lu;
        xv = dot(hit, dv) / lv;
        s = PRW_RECT_SCALE * alpha * tr;
        nu = PRW_RECT_NODES;
        nv = PRW_RECT_NODES;
        // t ranges atan(y0) .. atan(y1) from the light's edges; far off the light both are near +-pi/2
        // and their float difference cancels, so the width comes from atan((y1 - y0) / (1 + y0 y1)) then,
        // and the first node from the addition theorem on tan(atan(y0)) = y0
        float yu0 = (-lu - xu) / s, yu1 = (lu - xu) / s, yv0 = (-lv - xv) / s, yv1 = (lv - xv) / s;
        dtu = (yu0 * yu1 > 0.0 ? atan((yu1 - yu0) / (1.0 + yu0 * yu1)) : atan(yu1) - atan(yu0)) / float(nu);
        dtv = (yv0 * yv1 > 0.0 ? atan((yv1 - yv0) / (1.0 + yv0 * yv1)) : atan(yv1) - atan(yv0)) / float(nv);
        float hu = tan(0.5 * dtu), hv = tan(0.5 * dtv);
        tu0 = (yu0 + hu) / (1.0 - yu0 * hu); // tan of the first node; the next by the addition theorem
        tv0 = (yv0 + hv) / (1.0 - yv0 * hv);
        Tu = tan(dtu);
        Tv = tan(dtv);
    }
    vec3 eu = du / lu, ev = dv / lv;
    // per node one division: D V (n.l) cos_light / d^2 =
    //   (a^2 / (2 pi)) (n.d) (-ln.d) / (dd^2 (gv + gl) d2^2) with l = d / |d|, dd = (n.h)^2 (a^2 - 1) + 1,
    // gv = min(n.l, 1) sqrt((n.v)^2 (1 - a^2) + a^2) and gl = n.v sqrt(min(n.l, 1)^2 (1 - a^2) + a^2)
    // (prw_D_ggx and prw_V_smith_ggx up to float rounding); n.h and v.h from v.l without forming h
    // (|v + l|^2 = 2 + 2 v.l); the node positions by multiplications.
    float a2 = alpha * alpha, k2 = 1.0 - a2;
    float gv0 = sqrt(NoV * NoV * k2 + a2), dvk = a2 * (0.5 / PRW_BRDF_PI), nov = dot(n, v);
    vec3 cp = c - p;
    float su_step = 2.0 / float(nu), sv_step = 2.0 / float(nv);
    float sum = 0.0, sum_voh = 0.0;
    float tv = tv0;
    for (int j = 0; j < nv; j++) {
        float sv = (float(j) + 0.5) * sv_step - 1.0;
        float wv = s * (1.0 + tv * tv) * dtv; // mapped: metres of the node along v
        vec3 rowv = mapped ? cp + ev * (xv + s * tv) : cp + dv * sv;
        float tu = tu0;
        for (int i = 0; i < nu; i++) {
            float su = (float(i) + 0.5) * su_step - 1.0;
            vec3 d = rowv + (mapped ? eu * (xu + s * tu) : du * su);
            float cw = mapped ? s * (1.0 + tu * tu) * dtu * wv : (shape == 2.0 ? step(sv, su) * (su == sv ? 0.5 : 1.0) : 1.0);
            tu = (tu + Tu) / (1.0 - tu * Tu);
            float d2 = max(dot(d, d), 1e-8);
            float rs = inversesqrt(d2);
            vec3 l = d * rs;
            float NoL = dot(n, l), cl = -dot(l, ln);
            if (NoL <= 0.0 || cl <= 0.0) continue;
            float vl = dot(v, l), rh = inversesqrt(max(2.0 + 2.0 * vl, 1e-12)); // 1 / |v + l|
            float NoH = prw_clamp01((nov + NoL) * rh), mi = min(NoL, 1.0);
            float dd = NoH * NoH * (a2 - 1.0) + 1.0;
            float g = max(mi * gv0 + NoV * sqrt(mi * mi * k2 + a2), 1e-12);
            float w = dvk * NoL * cl * cw * (rs * rs) / (dd * dd * g);
            sum += w;
            sum_voh += w * prw_clamp01((1.0 + vl) * rh);
        }
        tv = (tv + Tv) / (1.0 - tv * Tv);
    }
    if (!(sum > 0.0)) return vec3(0.0);
    float voh = sum_voh / sum;
    float m = prw_clamp01(metallic);
    float f_diel = prw_clamp01(specular) * prw_F_dielectric(voh);
    vec3 f = vec3((1.0 - m) * f_diel + m * prw_F_schlick(base.r, voh), (1.0 - m) * f_diel + m * prw_F_schlick(base.g, voh),
                  (1.0 - m) * f_diel + m * prw_F_schlick(base.b, voh));
    return f * (mapped ? sum : sum * 4.0 * (shape == 0.0 ? lu * lv : length(cross(du, dv))) / float(nu * nv));
}

// The rect light's single-scattering specular: the quadrature above; with PRW_RECT_LTC defined, linearly
// transformed cosines (ltc.glsl) instead: cheaper (one more polygon integral instead of up to 10 x 10
// lobe evaluations) but a single LTC does not follow the GGX lobe as closely as the quadrature
// (materials/tools/rect_quad_study.c prints both errors), so the quadrature is the default.
vec3 rect_specular_single(vec3 p, vec3 n, vec3 v, vec3 c, vec3 du, vec3 dv, vec3 ln, vec3 base, float metallic,
                          float roughness, float specular, float shape)
{
#ifdef PRW_RECT_LTC
    return rect_specular_ltc(p, n, v, c, du, dv, base, metallic, roughness, specular); // rectangles only
#else
    return rect_specular_quadrature(p, n, v, c, du, dv, ln, base, metallic, roughness, specular, shape);
#endif
}

// The fitted albedos (prw_ggx_fit.h) a surface point needs for every light: those of its roughness and
// of the view cosine (mo = min(max(n.v, 1e-4), 1); the fits take the same value for every cosine below
// 0.01, so this equals each light's own clamping), computed once per fragment.
// The 2-D fits' rows of the roughness (prw_ggx_fit.h) are kept for the lights' cosines: a light then
// costs 16 terms per fit instead of 256.
struct ggx_view {
    float ec_avg, ed_avg, ec_o, ed_o;
    prw_ggx_row ec_row, ed_row;
};

// The specular lobe's directional albedo along w for the GI terms (gi_env, gi_probe, gi_lightmap): the
// dielectric's, specular e_d + F_ms e_c (multiple scattering), and its cosine-weighted mean over the view
// directions; the metal's, F0 A + B + F_ms(F0) e_c with (A, B) the split-sum table at mu and roughness.
float ggx_dielectric_albedo(ggx_view w, float specular)
{
    float s = clamp(specular, 0.0, 1.0);
    return s * w.ed_o + prw_F_ms(s * PRW_DIELECTRIC_F_AVG, w.ec_avg) * w.ec_o;
}
float ggx_dielectric_albedo_avg(ggx_view w, float specular)
{
    float s = clamp(specular, 0.0, 1.0);
    return s * w.ed_avg + prw_F_ms(s * PRW_DIELECTRIC_F_AVG, w.ec_avg) * w.ec_avg;
}
vec3 ggx_metal_albedo(ggx_view w, vec3 base, vec2 ab)
{
    vec3 f0 = base + (1.0 - base) * (1.0 / 21.0);
    vec3 fms_m = vec3(prw_F_ms(f0.r, w.ec_avg), prw_F_ms(f0.g, w.ec_avg), prw_F_ms(f0.b, w.ec_avg));
    return base * ab.x + ab.y + fms_m * w.ec_o;
}

// ... from the rows and averages of the roughness (computed here, or by the CPU for a material whose
// roughness has no texture: material_gltf.glsl).
ggx_view ggx_view_from(float NoV, prw_ggx_row ec_row, prw_ggx_row ed_row, float ec_avg, float ed_avg)
{
    float mo = min(max(NoV, 1e-4), 1.0);
    ggx_view w;
    w.ec_row = ec_row;
    w.ed_row = ed_row;
    w.ec_avg = ec_avg;
    w.ed_avg = ed_avg;
    w.ec_o = prw_ggx_Ec_at(w.ec_row, mo);
    w.ed_o = prw_ggx_Ed_at(w.ed_row, mo);
    return w;
}

ggx_view ggx_view_at(float NoV, float roughness)
{
    return ggx_view_from(NoV, prw_ggx_Ec_row(roughness), prw_ggx_Ed_row(roughness), prw_ggx_Ec_avg(roughness),
                         prw_ggx_Ed_avg(roughness));
}

// ... and with one light's clamped cosine mi: the terms prw_brdf_*_terms take (shared by the three
// channels' lobes).
struct ggx_terms {
    float ec_avg, ed_avg, ec_o, ec_i, ed_o, ed_i;
};

ggx_terms ggx_terms_at(ggx_view w, float mi, float roughness)
{
    ggx_terms t;
    t.ec_avg = w.ec_avg;
    t.ed_avg = w.ed_avg;
    t.ec_o = w.ec_o;
    t.ec_i = prw_ggx_Ec_at(w.ec_row, mi);
    t.ed_o = w.ed_o;
    t.ed_i = prw_ggx_Ed_at(w.ed_row, mi);
    return t;
}

// prw_brdf_diffuse_channel per RGB channel (cosines > 0, clamped to 1 in t).
vec3 diffuse_rgb(ggx_terms t, vec3 base, float metallic, float specular)
{
    return vec3(prw_brdf_diffuse_terms(base.r, metallic, specular, t.ec_avg, t.ed_avg, t.ec_o, t.ec_i, t.ed_o, t.ed_i),
                prw_brdf_diffuse_terms(base.g, metallic, specular, t.ec_avg, t.ed_avg, t.ec_o, t.ec_i, t.ed_o, t.ed_i),
                prw_brdf_diffuse_terms(base.b, metallic, specular, t.ec_avg, t.ed_avg, t.ec_o, t.ec_i, t.ed_o, t.ed_i));
}

// Multiple-scattering specular (Kulla-Conty) per channel: a smooth, diffuse-like lobe.
vec3 specular_ms(ggx_terms t, vec3 base, float metallic, float specular)
{
    float ec_avg = t.ec_avg;
    float ms = prw_ggx_ms_terms(ec_avg, t.ec_o, t.ec_i);
    float m = prw_clamp01(metallic);
    float diel = prw_F_ms(prw_clamp01(specular) * PRW_DIELECTRIC_F_AVG, ec_avg);
    vec3 metal = vec3(prw_F_ms(base.r + (1.0 - base.r) * (1.0 / 21.0), ec_avg),
                      prw_F_ms(base.g + (1.0 - base.g) * (1.0 / 21.0), ec_avg),
                      prw_F_ms(base.b + (1.0 - base.b) * (1.0 / 21.0), ec_avg));
    return ms * ((1.0 - m) * diel + m * metal);
}

// The shared material model (prw_brdf.h, prw_brdf_channel) per RGB channel, from cosines.
vec3 brdf_cos(ggx_view w, float NoV, float NoL, float NoH, float VoH, vec3 base, float metallic, float roughness,
              float specular)
{
    if (NoL <= 0.0 || NoV <= 0.0) return vec3(0.0);
    float mo = min(NoV, 1.0), mi = min(NoL, 1.0);
    ggx_terms t = ggx_terms_at(w, mi, roughness);
    return diffuse_rgb(t, base, metallic, specular) +
           vec3(prw_brdf_specular_terms(mo, mi, NoH, VoH, base.r, metallic, roughness, specular, t.ec_avg, t.ec_o, t.ec_i),
                prw_brdf_specular_terms(mo, mi, NoH, VoH, base.g, metallic, roughness, specular, t.ec_avg, t.ec_o, t.ec_i),
                prw_brdf_specular_terms(mo, mi, NoH, VoH, base.b, metallic, roughness, specular, t.ec_avg, t.ec_o, t.ec_i));
}

vec3 brdf(ggx_view w, vec3 n, vec3 v, vec3 l, vec3 base, float metallic, float roughness, float specular)
{
    vec3 h = normalize(v + l);
    return brdf_cos(w, dot(n, v), dot(n, l), dot(n, h), dot(v, h), base, metallic, roughness, specular);
}

// A point, spot or directional light at p: the direction to it (l) and its irradiance factor on a
// surface facing it (E: 1 / d^2 with the range window and the spot cone; 1 for a directional light).
void punctual_incidence(prw_gpu_light L, int type, vec3 p, out vec3 l, out float E)
{
    if (type == PRW_GPU_LIGHT_DIRECTIONAL) {
        l = -L.dir_range.xyz;
        E = 1.0;
        return;
    }
    vec3 d = L.pos_type.xyz - p;
    float d2 = max(dot(d, d), 1e-8);
    l = d * inversesqrt(d2);
    E = 1.0 / d2;
    if (L.dir_range.w > 0.0) E *= prw_range_window(d2, L.dir_range.w);
    if (type == PRW_GPU_LIGHT_SPOT) {
        float cd = dot(-l, L.dir_range.xyz);
        E *= prw_spot_factor(cd, L.cone_shadow.x, L.cone_shadow.y);
    }
}

// The light slots of the globals are grouped by shading class (engine/render/shadow_plan.h) and the
// pipelines specialise these constants on the group sizes (engine/render/pipes.c): on lavapipe every
// instruction of a shader runs for every fragment whatever its branches decide (they become masks), so a
// loop over all lights with a branch per kind would pay for every kind's code (and the shadow lookups)
// per light.  Unspecialised (prw_lights_sorted false): one loop over g.params.x lights, kinds by branch.
layout(constant_id = PRW_SC_LIGHTS_SORTED) const bool prw_lights_sorted = false;
layout(constant_id = PRW_SC_N_RECT_SHADOWED) const int prw_n_rect_shadowed = 0;
layout(constant_id = PRW_SC_N_RECT) const int prw_n_rect = 0;
layout(constant_id = PRW_SC_N_PUNCTUAL_SHADOWED) const int prw_n_punctual_shadowed = 0;
layout(constant_id = PRW_SC_N_POINT_SHADOWED) const int prw_n_point_shadowed = 0;
layout(constant_id = PRW_SC_N_PUNCTUAL) const int prw_n_punctual = 0;

// The first PRW_UNROLLED slots are written out, one call site each whose kind and shadowing are constants
// after specialisation (lavapipe does not unroll a loop whose bound is a specialisation constant, and a
// light indexed by a loop counter costs it more than the light's shading); further lights go through a
// loop.  (Written out for every slot, the inlined copies made pipeline creation 4x slower.)
#define PRW_UNROLLED 4
#define PRW_UNROLLED_SLOTS(X) X(0) X(1) X(2) X(3)
#define PRW_N_LIGHTS (prw_n_rect_shadowed + prw_n_rect + prw_n_punctual_shadowed + prw_n_point_shadowed + prw_n_punctual)
#define PRW_SLOT_RECT(K) ((K) < prw_n_rect_shadowed + prw_n_rect)
#define PRW_N_BEFORE_POINT (prw_n_rect_shadowed + prw_n_rect + prw_n_punctual_shadowed)
#define PRW_SLOT_SHADOWED(K)                                                                                      \
    ((K) < prw_n_rect_shadowed || ((K) >= prw_n_rect_shadowed + prw_n_rect && (K) < PRW_N_BEFORE_POINT + prw_n_point_shadowed))
#define PRW_SLOT_CUBE(K) ((K) >= PRW_N_BEFORE_POINT && (K) < PRW_N_BEFORE_POINT + prw_n_point_shadowed)

// The corners of a rect light (camera-relative); a triangle (axis_u.w 2, an emissive mesh's) repeats the third,
// whose Lambert edge term is then 0.
void rect_corners(prw_gpu_light L, out vec3 q0, out vec3 q1, out vec3 q2, out vec3 q3)
{
    vec3 c = L.pos_type.xyz;
    q0 = c - L.axis_u.xyz - L.axis_v.xyz;
    q1 = c + L.axis_u.xyz - L.axis_v.xyz;
    q2 = c + L.axis_u.xyz + L.axis_v.xyz;
    q3 = L.axis_u.w == 2.0 ? q2 : c - L.axis_u.xyz + L.axis_v.xyz;
}

// The direct light of the rect light L at p (camera-relative; normal n, towards the eye v).
// shadow_offset: the receiver's normal offset for the shadow lookups, texels (shadows.glsl).
vec3 rect_light(prw_gpu_light L, bool shadowed, ggx_view w, vec3 p, vec3 n, vec3 v, vec3 base, float metallic,
                float roughness, float specular, float shadow_offset)
{
    vec3 c = L.pos_type.xyz;
    if (dot(p - c, L.dir_range.xyz) <= 0.0) return vec3(0.0); // one-sided emitter
    vec3 q0, q1, q2, q3, fdir;
    rect_corners(L, q0, q1, q2, q3);
    float E = quad_irradiance(p, n, q0, q1, q2, q3, fdir);
    if (E <= 0.0) return vec3(0.0);
    // Diffuse and the multiple-scattering specular (both smooth in the light direction): Lambert's
    // polygon formula E, exact for a constant lobe, with the cosine-dependent factors taken at the vector
    // form factor's direction.  Single-scattering specular: quadrature over the quad (rect_specular_single).
    float NoLd = max(dot(n, fdir), 1e-4);
    ggx_terms t = ggx_terms_at(w, min(NoLd, 1.0), roughness);
    vec3 fd = diffuse_rgb(t, base, metallic, specular) + specular_ms(t, base, metallic, specular);
    vec3 f = fd * E + rect_specular_single(p, n, v, c, L.axis_u.xyz, L.axis_v.xyz, L.dir_range.xyz, base, metallic,
                                           roughness, specular, L.axis_u.w);
    return f * L.radiance.rgb * (shadowed ? shadow_factor_rect(L, p, n, shadow_offset) : 1.0);
}

// The direct light of the point, spot or directional light L at p.
vec3 punctual_light(prw_gpu_light L, bool shadowed, bool may_be_cube, ggx_view w, vec3 p, vec3 n, vec3 v, vec3 base, float metallic,
                    float roughness, float specular, float shadow_offset)
{
    vec3 l;
    float E;
    punctual_incidence(L, int(L.pos_type.w), p, l, E);
    float NoL = dot(n, l);
    if (NoL <= 0.0 || E <= 0.0) return vec3(0.0);
    return brdf(w, n, v, l, base, metallic, roughness, specular) * L.radiance.rgb * (E * NoL) *
           (shadowed ? shadow_factor(L, p, n, shadow_offset, may_be_cube) : 1.0);
}

// Adds the direct light of every light at p (camera-relative; normal n, towards the eye v) to radiance;
// w: the fits at the roughness and n.v (ggx_view_at or the material's, material_gltf.glsl).
void prw_direct_light(inout vec3 radiance, ggx_view w, vec3 p, vec3 n, vec3 v, vec3 base, float metallic,
                      float roughness, float specular, float shadow_offset)
{
    if (prw_lights_sorted) {
#define PRW_L(K)                                                                                                  \
    if (K < PRW_N_LIGHTS)                                                                                         \
        radiance += PRW_SLOT_RECT(K) ? rect_light(g.lights[K], PRW_SLOT_SHADOWED(K), w, p, n, v, base, metallic,   \
                                                  roughness, specular, shadow_offset)                             \
                                     : punctual_light(g.lights[K], PRW_SLOT_SHADOWED(K), PRW_SLOT_CUBE(K), w, p, n, v,  \
                                                      base, metallic, roughness, specular, shadow_offset);
        PRW_UNROLLED_SLOTS(PRW_L)
#undef PRW_L
        if (PRW_N_LIGHTS > PRW_UNROLLED)
            for (int i = PRW_UNROLLED; i < PRW_N_LIGHTS; i++)
                radiance += PRW_SLOT_RECT(i) ? rect_light(g.lights[i], PRW_SLOT_SHADOWED(i), w, p, n, v, base, metallic,
                                                          roughness, specular, shadow_offset)
                                             : punctual_light(g.lights[i], PRW_SLOT_SHADOWED(i), PRW_SLOT_CUBE(i), w, p,
                                                              n, v, base, metallic, roughness, specular, shadow_offset);
        return;
    }
    int count = int(g.params.x);
    for (int i = 0; i < count; i++) {
        prw_gpu_light L = g.lights[i];
        bool shadowed = L.cone_shadow.z >= 0.0;
        if (int(L.pos_type.w) == PRW_GPU_LIGHT_RECT)
            radiance += rect_light(L, shadowed, w, p, n, v, base, metallic, roughness, specular, shadow_offset);
        else
            radiance += punctual_light(L, shadowed, true, w, p, n, v, base, metallic, roughness, specular, shadow_offset);
    }
}

#ifdef PRW_GLTF_COAT
// The coated model (prw_brdf.h, KHR_materials_clearcoat) per RGB channel: n the base's shading normal,
// nc the coat's normal; clearcoat 0 is brdf() (prw_brdf_coated_channel returns prw_brdf_channel).
vec3 brdf_coated(ggx_view w, vec3 n, vec3 nc, vec3 v, vec3 l, vec3 base, float metallic, float roughness,
                 float specular, float cc, float rc)
{
    vec3 h = normalize(v + l);
    float NoV = dot(n, v), NoL = dot(n, l), NoH = dot(n, h), VoH = dot(v, h);
    float NcV = dot(nc, v), NcL = dot(nc, l), NcH = dot(nc, h);
    // prw_brdf_coated_channel per channel: the coat's transmission and lobe are the same for all three
    vec3 f = brdf_cos(w, NoV, NoL, NoH, VoH, base, metallic, roughness, specular);
    float c = prw_clamp01(cc);
    if (c <= 0.0) return f;
    float t = prw_coat_transmission(NcV, c, rc) * prw_coat_transmission(NcL, c, rc);
    return c * prw_brdf_coat_lobe(NcV, NcL, NcH, VoH, rc) + t * f;
}

// The rect light L on a clear-coated surface (coat normal nc, weight cc, roughness rc): the base's terms
// as in rect_light, times the coat's transmission towards the viewer and towards the base's
// vector-form-factor direction (smooth over the light); the coat's single scattering by the same
// quadrature (rect_specular_single with the coat's normal and roughness, F = the dielectric's), its
// multiple scattering by Lambert's formula over the coat's hemisphere.
vec3 rect_light_coated(prw_gpu_light L, bool shadowed, ggx_view w, vec3 p, vec3 n, vec3 nc, vec3 v, vec3 base,
                       float metallic, float roughness, float specular, float cc, float rc, float shadow_offset)
{
    vec3 c = L.pos_type.xyz;
    if (dot(p - c, L.dir_range.xyz) <= 0.0) return vec3(0.0); // one-sided emitter
    vec3 q0, q1, q2, q3;
    rect_corners(L, q0, q1, q2, q3);
    vec3 f = vec3(0.0);
    vec3 fdir;
    float E = quad_irradiance(p, n, q0, q1, q2, q3, fdir);
    float NcV = max(dot(nc, v), 1e-4);
    if (E > 0.0) {
        float NoLd = max(dot(n, fdir), 1e-4);
        ggx_terms tb = ggx_terms_at(w, min(NoLd, 1.0), roughness);
        vec3 fd = diffuse_rgb(tb, base, metallic, specular) + specular_ms(tb, base, metallic, specular);
        float t = prw_coat_transmission(NcV, cc, rc) * prw_coat_transmission(dot(nc, fdir), cc, rc);
        f += t * (fd * E + rect_specular_single(p, n, v, c, L.axis_u.xyz, L.axis_v.xyz, L.dir_range.xyz, base,
                                                metallic, roughness, specular, L.axis_u.w));
    }
    vec3 fdir_c;
    float Ec = quad_irradiance(p, nc, q0, q1, q2, q3, fdir_c);
    if (Ec > 0.0) {
        float NcLd = max(dot(nc, fdir_c), 1e-4);
        float ms = prw_ggx_ms_shape(min(NcV, 1.0), min(NcLd, 1.0), rc) * prw_F_ms(PRW_DIELECTRIC_F_AVG, prw_ggx_Ec_avg(rc));
        f += cc * (vec3(ms * Ec) + rect_specular_single(p, nc, v, c, L.axis_u.xyz, L.axis_v.xyz, L.dir_range.xyz,
                                                        vec3(0.0), 0.0, rc, 1.0, L.axis_u.w));
    }
    return f * L.radiance.rgb * (shadowed ? shadow_factor_rect(L, p, n, shadow_offset) : 1.0);
}

vec3 punctual_light_coated(prw_gpu_light L, bool shadowed, bool may_be_cube, ggx_view w, vec3 p, vec3 n, vec3 nc, vec3 v, vec3 base,
                           float metallic, float roughness, float specular, float cc, float rc, float shadow_offset)
{
    vec3 l;
    float E;
    punctual_incidence(L, int(L.pos_type.w), p, l, E);
    float NoL = dot(n, l);
    if (NoL <= 0.0 || E <= 0.0) return vec3(0.0);
    return brdf_coated(w, n, nc, v, l, base, metallic, roughness, specular, cc, rc) * L.radiance.rgb * (E * NoL) *
           (shadowed ? shadow_factor(L, p, n, shadow_offset, may_be_cube) : 1.0);
}

// prw_direct_light for a clear-coated surface (coat normal nc, weight cc, roughness rc).
void prw_direct_light_coated(inout vec3 radiance, ggx_view w, vec3 p, vec3 n, vec3 nc, vec3 v, vec3 base,
                             float metallic, float roughness, float specular, float cc, float rc, float shadow_offset)
{
    if (!(cc > 0.0)) {
        prw_direct_light(radiance, w, p, n, v, base, metallic, roughness, specular, shadow_offset);
        return;
    }
    if (prw_lights_sorted) {
#define PRW_L(K)                                                                                                  \
    if (K < PRW_N_LIGHTS)                                                                                         \
        radiance += PRW_SLOT_RECT(K) ? rect_light_coated(g.lights[K], PRW_SLOT_SHADOWED(K), w, p, n, nc, v, base,  \
                                                         metallic, roughness, specular, cc, rc, shadow_offset)    \
                                     : punctual_light_coated(g.lights[K], PRW_SLOT_SHADOWED(K), PRW_SLOT_CUBE(K), w, p, \
                                                             n, nc, v, base, metallic, roughness, specular, cc, rc,      \
                                                             shadow_offset);
        PRW_UNROLLED_SLOTS(PRW_L)
#undef PRW_L
        if (PRW_N_LIGHTS > PRW_UNROLLED)
            for (int i = PRW_UNROLLED; i < PRW_N_LIGHTS; i++)
                radiance += PRW_SLOT_RECT(i) ? rect_light_coated(g.lights[i], PRW_SLOT_SHADOWED(i), w, p, n, nc, v,
                                                                 base, metallic, roughness, specular, cc, rc, shadow_offset)
                                             : punctual_light_coated(g.lights[i], PRW_SLOT_SHADOWED(i), PRW_SLOT_CUBE(i),
                                                                     w, p, n, nc, v, base, metallic, roughness, specular,
                                                                     cc, rc, shadow_offset);
        return;
    }
    int count = int(g.params.x);
    for (int i = 0; i < count; i++) {
        prw_gpu_light L = g.lights[i];
        bool shadowed = L.cone_shadow.z >= 0.0;
        if (int(L.pos_type.w) == PRW_GPU_LIGHT_RECT)
            radiance += rect_light_coated(L, shadowed, w, p, n, nc, v, base, metallic, roughness, specular, cc, rc,
                                          shadow_offset);
        else
            radiance += punctual_light_coated(L, shadowed, true, w, p, n, nc, v, base, metallic, roughness, specular, cc,
                                              rc, shadow_offset);
    }
}
#endif

#endif
