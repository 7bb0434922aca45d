// gi_lightmap.glsl — the base pass's terms (spec constant PRW_SC_TERMS) and, in the PRW_GI variants,
// the baked indirect diffuse of the light maps (engine/render/prw_lightmap.h, engine/bake/prw_gi.h):
//   L_idl = (1 - metallic) base / pi x (1 - e(mu_o)) / (1 - e_avg) x E_ind,
// which is prw_brdf_diffuse_terms (materials/prw_brdf.h) with the incoming direction's albedo terms 0
// (e(mu_i) = 0): the same float code as the direct light's diffuse lobe, not a second derivation.
// Rough glossy indirect (PRW_TERM_INDIRECT_GLOSSY): on a surface rougher than PRW_GI_GLOSSY_MIN_ROUGHNESS
// whose material has no probe, the dielectric specular lobe's share of the same light,
//   L_igr = (1 - metallic) E_ds(mu_o) E_ind / (pi (1 - e_avg)),   E_ds = specular e_d(mu_o) + F_ms e_c(mu_o)
// (the dielectric specular albedo of gi_env.glsl / gi_probe.glsl; e_avg its cosine-weighted mean, as in
// prw_brdf_diffuse_terms): the incoming indirect radiance taken as uniform over the lobe, which a wide lobe
// averages anyway; then the baked E_ind, weighted by 1 - e(mu_i) (prw_gi.h), is (1 - e_avg) times the
// plain irradiance.  Below that roughness the probes (<= 0.5) carry the lobe's indirect light on the
// probed curved objects and the planar reflectors on planes up to glossy_max_roughness (default 0.3);
// planes between that and 0.5 and curved objects without a probe get none of it (a known gap), and a
// plane above 0.5 with glossy_max_roughness > 0.5 gets it twice.  Metals are left out (their albedo
// needs the split-sum table, bound only with an environment).
// E_ind: ATLAS mode by a bicubic B-spline over the atlas layer (four bilinear taps, Sigg & Hadwiger
// 2005; the baker dilates 2 texels around every chart, the reach of the B-spline), VERTEX mode
// interpolated from the vertices.  Needs lights.glsl (ggx_view) and prw_constants.h.
#ifndef PRW_GI_LIGHTMAP_GLSL
#define PRW_GI_LIGHTMAP_GLSL

layout(constant_id = PRW_SC_TERMS) const int prw_terms = PRW_TERM_ALL;

#ifdef PRW_GI
layout(set = 0, binding = 4) uniform sampler2DArray prw_gi_atlas; // RGBA32F, one layer per atlas
layout(location = 5) in vec4 v_gi; // ATLAS: (u, v, layer, 0) normalised to the layer; VERTEX: (E_ind, 1 + vis)
layout(location = 6) in vec4 v_gi_cone; // VERTEX: the open cone (b, f); ATLAS: unused

vec4 prw_gi_bicubic(vec2 uv, float layer)
{
    vec2 size = vec2(textureSize(prw_gi_atlas, 0).xy);
    vec2 t = uv * size - 0.5;
    vec2 i = floor(t);
    vec2 f = t - i;
    vec2 f2 = f * f, f3 = f2 * f;
    vec2 w0 = (1.0 - 3.0 * f + 3.0 * f2 - f3) / 6.0;
    vec2 w1 = (4.0 - 6.0 * f2 + 3.0 * f3) / 6.0;
    vec2 w2 = (1.0 + 3.0 * f + 3.0 * f2 - 3.0 * f3) / 6.0;
    vec2 w3 = f3 / 6.0;
    vec2 g0 = w0 + w1, g1 = w2 + w3;
    vec2 h0 = (i - 0.5 + w1 / g0) / size; // texel centre i - 1 + w1 / g0, as a coordinate
    vec2 h1 = (i + 1.5 + w3 / g1) / size;
    vec4 a = texture(prw_gi_atlas, vec3(h0.x, h0.y, layer));
    vec4 b = texture(prw_gi_atlas, vec3(h1.x, h0.y, layer));
    vec4 c = texture(prw_gi_atlas, vec3(h0.x, h1.y, layer));
    vec4 d = texture(prw_gi_atlas, vec3(h1.x, h1.y, layer));
    return g0.y * (g0.x * a + g1.x * b) + g1.y * (g0.x * c + g1.x * d);
}

// E_ind and (w) the environment visibility (prw_lightmap.h: the atlas's alpha; VERTEX: v_gi.w = 1 + vis)
vec4 prw_gi_lookup()
{
    if (v_gi.w > 0.5) return vec4(max(v_gi.rgb, vec3(0.0)), clamp(v_gi.w - 1.0, 0.0, 1.0));
    vec4 t = prw_gi_bicubic(v_gi.xy, floor(v_gi.z + 0.5));
    return vec4(max(t.rgb, vec3(0.0)), clamp(t.a, 0.0, 1.0));
}

vec3 prw_gi_irradiance() { return prw_gi_lookup().rgb; }

// The open cone (b, f) of the environment visibility (prw_gi.h): ATLAS bilinear from the cone layers (the
// atlas's second half), VERTEX interpolated; (0, 0, 0, -1): none.
vec4 prw_gi_cone()
{
    if (v_gi.w > 0.5) return v_gi_cone;
    float n = float(textureSize(prw_gi_atlas, 0).z / 2);
    return texture(prw_gi_atlas, vec3(v_gi.xy, floor(v_gi.z + 0.5) + n));
}
#endif

// The radiance the pipeline's terms draw: direct (emission + direct light, computed by the caller)
// and, in the PRW_GI variants, the light map's indirect diffuse seen along w (the view's fits) and the
// rough unprobed surfaces' indirect glossy (probed: the material has a reflection probe).
#define PRW_GI_GLOSSY_MIN_ROUGHNESS 0.5
vec3 prw_terms_radiance(vec3 direct, ggx_view w, vec3 base, float metallic, float roughness, float specular,
                        bool probed)
{
    vec3 r = (prw_terms & PRW_TERM_DIRECT) != 0 ? direct : vec3(0.0);
#ifdef PRW_GI
    if ((prw_terms & (PRW_TERM_INDIRECT_DIFFUSE | PRW_TERM_INDIRECT_GLOSSY)) != 0) {
        vec3 E = prw_gi_irradiance();
        if ((prw_terms & PRW_TERM_INDIRECT_DIFFUSE) != 0) {
            float k = prw_brdf_diffuse_terms(1.0, metallic, specular, w.ec_avg, w.ed_avg, w.ec_o, 0.0, w.ed_o, 0.0);
            r += k * base * E;
        }
        if ((prw_terms & PRW_TERM_INDIRECT_GLOSSY) != 0 && !probed && roughness > PRW_GI_GLOSSY_MIN_ROUGHNESS) {
            float e_ds = ggx_dielectric_albedo(w, specular), e_avg = ggx_dielectric_albedo_avg(w, specular);
            r += (1.0 - clamp(metallic, 0.0, 1.0)) * e_ds / (3.14159265358979 * max(1.0 - e_avg, 1e-3)) * E;
        }
    }
#endif
    return r;
}
#endif
