// lights.glsl — direct light of every light of the per-view globals at a surface point, in cd/m^2, with
// the shared material model (prw_brdf.h) and the shared falloff rules (prw_shading.h):
//  - point / spot / directional: f(n, v, l) E cos, E = intensity / d^2 (x range window, x spot cone) or
//    the directional illuminance, shadowed by shadows.glsl;
//  - rect area lights: diffuse (and the multiple-scattering specular) from Lambert's polygon formula
//    (exact irradiance, clipped to the receiver's hemisphere), single-scattering specular by a
//    lobe-resolving quadrature over the rectangle (rect_specular_single), visibility from one shadow map
//    at the rectangle's centre (hard shadows: the main remaining difference to the reference).
// Needs common.glsl, shadows.glsl, prw_brdf.h and prw_shading.h included before it.
#ifndef PRW_LIGHTS_GLSL
#define PRW_LIGHTS_GLSL

const float PI = 3.14159265358979323846;

// Irradiance per unit radiance from the quad q (camera-relative) at p with normal n, after clipping
// the quad to the hemisphere above p (Lambert's formula: E/L = 1/2 sum theta_i n.gamma_i).
// fdir receives the direction of the vector form factor (the irradiance-weighted mean direction).
float quad_irradiance(vec3 p, vec3 n, vec3 q[4], out vec3 fdir)
{
    fdir = n;
    vec3 poly[5];
    int cnt = 0;
    for (int i = 0; i < 4; i++) {
        vec3 a = q[i] - p, b = q[(i + 1) % 4] - p;
        float da = dot(n, a), db = dot(n, b);
        if (da > 0.0) poly[cnt++] = a;
        if ((da > 0.0) != (db > 0.0) && cnt < 5) poly[cnt++] = a + (b - a) * (da / (da - db));
    }
    if (cnt < 3) return 0.0;
    vec3 sum = vec3(0.0);
    for (int i = 0; i < cnt; i++) {
        vec3 v0 = normalize(poly[i]), v1 = normalize(poly[(i + 1) % cnt]);
        vec3 cr = cross(v0, v1);
        float l = length(cr);
        if (l > 1e-9) sum += atan(l, dot(v0, v1)) * (cr / l);
    }
    float e = dot(n, sum);
    if (e < 0.0) sum = -sum;
    float len = length(sum);
    if (len > 1e-12) fdir = sum / len;
    return 0.5 * abs(e);
}

// Single-scattering specular of a rect light (centre c, half axes du, dv, emitting towards +ln,
// radiance 1) at p: the D * V * cos factor is integrated by midpoint quadrature over the quad on a
// grid whose cells subtend at most half the GGX alpha (radians, seen from p), so the lobe is
// resolved (at most 32 x 32 cells: near-mirror surfaces reflecting a large light are then
// under-resolved, seen as a dotted reflection); Fresnel, which varies slowly over the light, is
// taken at the quadrature's D V-weighted mean cos(v, h).
vec3 rect_specular_single(vec3 p, vec3 n, vec3 v, vec3 c, vec3 du, vec3 dv, vec3 ln, vec3 base, float metallic,
                          float roughness, float specular)
{
    float alpha = prw_alpha_from_roughness(roughness);
    float dist = max(length(c - p), 1e-4);
    float lu = length(du), lv = length(dv);
    float cell = 0.5 * alpha * dist; // metres on the light per cell, at the light's distance
    int nu = int(clamp(ceil(2.0 * lu / cell), 1.0, 32.0));
    int nv = int(clamp(ceil(2.0 * lv / cell), 1.0, 32.0));
    float NoV = min(max(dot(n, v), 1e-4), 1.0);
    float sum = 0.0, sum_voh = 0.0;
    for (int j = 0; j < nv; j++) {
        float sv = (2.0 * (float(j) + 0.5)) / float(nv) - 1.0;
        for (int i = 0; i < nu; i++) {
            float su = (2.0 * (float(i) + 0.5)) / float(nu) - 1.0;
            vec3 d = c + du * su + dv * sv - p;
            float d2 = max(dot(d, d), 1e-8);
            vec3 l = d * inversesqrt(d2);
            float NoL = dot(n, l), cl = -dot(l, ln);
            if (NoL <= 0.0 || cl <= 0.0) continue;
            vec3 h = normalize(v + l);
            float w = prw_D_ggx(prw_clamp01(dot(n, h)), alpha) * prw_V_smith_ggx(NoV, min(NoL, 1.0), alpha) *
                      (NoL * cl / d2);
            sum += w;
            sum_voh += w * prw_clamp01(dot(v, h));
        }
    }
    if (!(sum > 0.0)) return vec3(0.0);
    float voh = sum_voh / sum;
    float m = prw_clamp01(metallic);
    float f_diel = prw_clamp01(specular) * prw_F_dielectric(voh);
    vec3 f = vec3((1.0 - m) * f_diel + m * prw_F_schlick(base.r, voh), (1.0 - m) * f_diel + m * prw_F_schlick(base.g, voh),
                  (1.0 - m) * f_diel + m * prw_F_schlick(base.b, voh));
    return f * (sum * 4.0 * lu * lv / float(nu * nv));
}

// The fitted albedos (prw_ggx_fit.h) of one roughness at the clamped cosines mo, mi: evaluated once per
// light and shared by the three channels' lobes (prw_brdf_*_terms: the per-channel functions' operations).
struct ggx_terms {
    float ec_avg, ed_avg, ec_o, ec_i, ed_o, ed_i;
};

ggx_terms ggx_terms_at(float mo, float mi, float roughness)
{
    ggx_terms t;
    t.ec_avg = prw_ggx_Ec_avg(roughness);
    t.ed_avg = prw_ggx_Ed_avg(roughness);
    t.ec_o = prw_ggx_Ec(mo, roughness);
    t.ec_i = prw_ggx_Ec(mi, roughness);
    t.ed_o = prw_ggx_Ed(mo, roughness);
    t.ed_i = prw_ggx_Ed(mi, roughness);
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
vec3 brdf_cos(float NoV, float NoL, float NoH, float VoH, vec3 base, float metallic, float roughness, float specular)
{
    if (NoL <= 0.0 || NoV <= 0.0) return vec3(0.0);
    float mo = min(NoV, 1.0), mi = min(NoL, 1.0);
    ggx_terms t = ggx_terms_at(mo, mi, roughness);
    return diffuse_rgb(t, base, metallic, specular) +
           vec3(prw_brdf_specular_terms(mo, mi, NoH, VoH, base.r, metallic, roughness, specular, t.ec_avg, t.ec_o, t.ec_i),
                prw_brdf_specular_terms(mo, mi, NoH, VoH, base.g, metallic, roughness, specular, t.ec_avg, t.ec_o, t.ec_i),
                prw_brdf_specular_terms(mo, mi, NoH, VoH, base.b, metallic, roughness, specular, t.ec_avg, t.ec_o, t.ec_i));
}

vec3 brdf(vec3 n, vec3 v, vec3 l, vec3 base, float metallic, float roughness, float specular)
{
    vec3 h = normalize(v + l);
    return brdf_cos(dot(n, v), dot(n, l), dot(n, h), dot(v, h), base, metallic, roughness, specular);
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

// Adds the direct light of every light at p (camera-relative; normal n, towards the eye v) to radiance.
// shadow_offset: the receiver's normal offset for the shadow lookups, texels (shadows.glsl).
void prw_direct_light(inout vec3 radiance, vec3 p, vec3 n, vec3 v, vec3 base, float metallic, float roughness,
                      float specular, float shadow_offset)
{
    int count = int(g.params.x);
    for (int i = 0; i < count; i++) {
        prw_gpu_light L = g.lights[i];
        int type = int(L.pos_type.w);
        vec3 rgb = L.radiance.rgb;
        if (type == PRW_GPU_LIGHT_RECT) {
            vec3 c = L.pos_type.xyz;
            if (dot(p - c, L.dir_range.xyz) <= 0.0) continue; // one-sided emitter
            vec3 q[4] = vec3[4](c - L.axis_u.xyz - L.axis_v.xyz, c + L.axis_u.xyz - L.axis_v.xyz,
                                c + L.axis_u.xyz + L.axis_v.xyz, c - L.axis_u.xyz + L.axis_v.xyz);
            vec3 fdir;
            float E = quad_irradiance(p, n, q, fdir);
            if (E <= 0.0) continue;
            // Diffuse and the multiple-scattering specular (both smooth in the light direction):
            // Lambert's polygon formula E, exact for a constant lobe, with the cosine-dependent
            // factors taken at the vector form factor's direction.  Single-scattering specular:
            // quadrature over the quad (rect_specular_single).
            float NoV = max(dot(n, v), 1e-4), NoLd = max(dot(n, fdir), 1e-4);
            ggx_terms t = ggx_terms_at(min(NoV, 1.0), min(NoLd, 1.0), roughness);
            vec3 fd = diffuse_rgb(t, base, metallic, specular) + specular_ms(t, base, metallic, specular);
            vec3 f = fd * E + rect_specular_single(p, n, v, c, L.axis_u.xyz, L.axis_v.xyz, L.dir_range.xyz, base,
                                                   metallic, roughness, specular);
            radiance += f * rgb * shadow_factor(L, p, n, shadow_offset);
            continue;
        }
        vec3 l;
        float E;
        punctual_incidence(L, type, p, l, E);
        float NoL = dot(n, l);
        if (NoL <= 0.0 || E <= 0.0) continue;
        radiance += brdf(n, v, l, base, metallic, roughness, specular) * rgb * (E * NoL) * shadow_factor(L, p, n, shadow_offset);
    }
}

#ifdef PRW_GLTF_COAT
// The coated model (prw_brdf.h, KHR_materials_clearcoat) per RGB channel: n the base's shading normal,
// nc the coat's normal; clearcoat 0 is brdf() (prw_brdf_coated_channel returns prw_brdf_channel).
vec3 brdf_coated(vec3 n, vec3 nc, vec3 v, vec3 l, vec3 base, float metallic, float roughness, float specular,
                 float cc, float rc)
{
    vec3 h = normalize(v + l);
    float NoV = dot(n, v), NoL = dot(n, l), NoH = dot(n, h), VoH = dot(v, h);
    float NcV = dot(nc, v), NcL = dot(nc, l), NcH = dot(nc, h);
    // prw_brdf_coated_channel per channel: the coat's transmission and lobe are the same for all three
    vec3 f = brdf_cos(NoV, NoL, NoH, VoH, base, metallic, roughness, specular);
    float c = prw_clamp01(cc);
    if (c <= 0.0) return f;
    float t = prw_coat_transmission(NcV, c, rc) * prw_coat_transmission(NcL, c, rc);
    return c * prw_brdf_coat_lobe(NcV, NcL, NcH, VoH, rc) + t * f;
}

// prw_direct_light for a clear-coated surface (coat normal nc, weight cc, roughness rc).  Rect lights:
// the base's terms as in prw_direct_light, times the coat's transmission towards the viewer and towards
// the base's vector-form-factor direction (smooth over the light); the coat's single scattering by the
// same quadrature (rect_specular_single with the coat's normal and roughness, F = the dielectric's),
// its multiple scattering by Lambert's formula over the coat's hemisphere.
void prw_direct_light_coated(inout vec3 radiance, vec3 p, vec3 n, vec3 nc, vec3 v, vec3 base, float metallic,
                             float roughness, float specular, float cc, float rc, float shadow_offset)
{
    if (!(cc > 0.0)) {
        prw_direct_light(radiance, p, n, v, base, metallic, roughness, specular, shadow_offset);
        return;
    }
    int count = int(g.params.x);
    for (int i = 0; i < count; i++) {
        prw_gpu_light L = g.lights[i];
        int type = int(L.pos_type.w);
        vec3 rgb = L.radiance.rgb;
        if (type == PRW_GPU_LIGHT_RECT) {
            vec3 c = L.pos_type.xyz;
            if (dot(p - c, L.dir_range.xyz) <= 0.0) continue; // one-sided emitter
            vec3 q[4] = vec3[4](c - L.axis_u.xyz - L.axis_v.xyz, c + L.axis_u.xyz - L.axis_v.xyz,
                                c + L.axis_u.xyz + L.axis_v.xyz, c - L.axis_u.xyz + L.axis_v.xyz);
            vec3 f = vec3(0.0);
            vec3 fdir;
            float E = quad_irradiance(p, n, q, fdir);
            float NcV = max(dot(nc, v), 1e-4);
            if (E > 0.0) {
                float NoV = max(dot(n, v), 1e-4), NoLd = max(dot(n, fdir), 1e-4);
                ggx_terms tb = ggx_terms_at(min(NoV, 1.0), min(NoLd, 1.0), roughness);
                vec3 fd = diffuse_rgb(tb, base, metallic, specular) + specular_ms(tb, base, metallic, specular);
                float t = prw_coat_transmission(NcV, cc, rc) * prw_coat_transmission(dot(nc, fdir), cc, rc);
                f += t * (fd * E + rect_specular_single(p, n, v, c, L.axis_u.xyz, L.axis_v.xyz, L.dir_range.xyz, base,
                                                        metallic, roughness, specular));
            }
            vec3 fdir_c;
            float Ec = quad_irradiance(p, nc, q, fdir_c);
            if (Ec > 0.0) {
                float NcLd = max(dot(nc, fdir_c), 1e-4);
                float ms = prw_ggx_ms_shape(min(NcV, 1.0), min(NcLd, 1.0), rc) *
                           prw_F_ms(PRW_DIELECTRIC_F_AVG, prw_ggx_Ec_avg(rc));
                f += cc * (vec3(ms * Ec) + rect_specular_single(p, nc, v, c, L.axis_u.xyz, L.axis_v.xyz, L.dir_range.xyz,
                                                                vec3(0.0), 0.0, rc, 1.0));
            }
            radiance += f * rgb * shadow_factor(L, p, n, shadow_offset);
            continue;
        }
        vec3 l;
        float E;
        punctual_incidence(L, type, p, l, E);
        float NoL = dot(n, l);
        if (NoL <= 0.0 || E <= 0.0) continue;
        radiance += brdf_coated(n, nc, v, l, base, metallic, roughness, specular, cc, rc) * rgb * (E * NoL) *
                    shadow_factor(L, p, n, shadow_offset);
    }
}
#endif

#endif
