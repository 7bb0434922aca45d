// gi_probe.glsl — the base pass's reflection-probe term (issue 16; engine/render/prw_probe_gpu.h,
// engine/bake/prw_probe.h): the radiance that the surfaces around a curved glossy object send towards it
// (the probe's maps: what leaves them minus their emission, gathered at the object's centre) reflected by
// the fragment's specular lobes to the eye — the reference's indirect-glossy-last term — by the split sum
// with our material model, the formula of gi_env.glsl's specular part:
//   L = (1 - m) E_ds(mu) P(r, d) + m E_m(mu) P(r, d)
// P: the probe's prefiltered levels, linear in roughness; d: the mirror direction R corrected by box
// parallax (the point where the ray from the fragment along R leaves the scene's bounding box, seen from
// the probe's centre).  A fragment uses the first probe whose material slot is its own and whose
// influence box holds it; none: no term.  Specialisation PRW_SC_PROBES = 0 (no probes): nothing.
// Needs common.glsl (g.origin), lights.glsl (ggx_view), material_gltf.glsl (mat), gi_lightmap.glsl
// (prw_terms) and prw_constants.h.
#ifndef PRW_GI_PROBE_GLSL
#define PRW_GI_PROBE_GLSL

layout(constant_id = PRW_SC_PROBES) const int prw_probes_on = 0;

layout(std430, set = 0, binding = 8) readonly buffer prw_probe_block {
    vec4 head; // count, levels K, level height H, 0
    vec4 pmin; // the parallax box (world)
    vec4 pmax;
    vec4 p[3 * PRW_GPU_MAX_PROBES]; // per probe: (centre, material slot + 1), (box min, 0), (box max, 0)
} prw_probe;
layout(set = 0, binding = 9) uniform sampler2DArray prw_probe_levels; // layer p K + k, 2H x H, equirect (world)
layout(set = 0, binding = 10) uniform sampler2DArray prw_probe_dfg;   // x: mu, y: roughness; (A, B)

vec3 prw_probe_radiance(ggx_view w, vec3 pos, vec3 n, vec3 v, vec3 base, float metallic, float roughness,
                        float specular)
{
    if (prw_probes_on == 0 || (prw_terms & PRW_TERM_PROBES) == 0) return vec3(0.0);
    if (!prw_mat_probed) return vec3(0.0); // only the probed materials' pipelines keep the code
    vec3 wp = pos + g.origin.xyz;
    int count = int(prw_probe.head.x), found = -1;
    for (int i = 0; i < count && found < 0; i++)
        if (abs(prw_probe.p[3 * i].w - mat.extra.y) < 0.5 && all(greaterThanEqual(wp, prw_probe.p[3 * i + 1].xyz)) &&
            all(lessThanEqual(wp, prw_probe.p[3 * i + 2].xyz)))
            found = i;
    if (found < 0) return vec3(0.0);
    float nv = dot(n, v);
    float mu = clamp(nv, 1e-4, 1.0);
    vec3 r = normalize(2.0 * nv * n - v);
    // box parallax: the exit point of wp + t r from the box, seen from the centre
    vec3 rs = mix(r, vec3(1e-6), lessThan(abs(r), vec3(1e-6)));
    vec3 tf = max((prw_probe.pmax.xyz - wp) / rs, (prw_probe.pmin.xyz - wp) / rs);
    float t = max(min(min(tf.x, tf.y), tf.z), 0.0);
    vec3 d = wp + t * r - prw_probe.p[3 * found].xyz;
    d = dot(d, d) > 1e-12 ? normalize(d) : r;
    float K = prw_probe.head.y, H = prw_probe.head.z;
    float rr = clamp(roughness, 0.0, 1.0);
    float k = rr * (K - 1.0);
    float k0 = floor(k), k1 = min(k0 + 1.0, K - 1.0), l0 = float(found) * K;
    float u = 0.5 + atan(d.x, -d.z) * (1.0 / 6.28318530717959);
    float vv = clamp(acos(clamp(d.y, -1.0, 1.0)) * (1.0 / 3.14159265358979), 0.5 / H, 1.0 - 0.5 / H);
    vec3 P = mix(textureLod(prw_probe_levels, vec3(u, vv, l0 + k0), 0.0).rgb,
                 textureLod(prw_probe_levels, vec3(u, vv, l0 + k1), 0.0).rgb, k - k0);
    float m = clamp(metallic, 0.0, 1.0);
    float e_ds = ggx_dielectric_albedo(w, specular);
    float n_dfg = float(textureSize(prw_probe_dfg, 0).x);
    vec2 ab = textureLod(prw_probe_dfg, vec3(mu, (rr * (n_dfg - 1.0) + 0.5) / n_dfg, 0.0), 0.0).rg;
    vec3 e_m = ggx_metal_albedo(w, base, ab);
    return ((1.0 - m) * e_ds + m * e_m) * P;
}
#endif
