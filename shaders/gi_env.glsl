// gi_env.glsl — the base pass's environment term (issue 16; engine/render/prw_env_gpu.h,
// materials/env/prw_env_file.h): the environment light reaching the surface directly and leaving it
// towards the eye after one scattering (the reference's environment-direct paths), by the split sum
// with our material model, exactly the formula prw_env_file.h states:
//   L = V [ (1 - m) ( b (1 - E_ds(mu)) E_irr(n) / pi + E_ds(mu) P(r, R) ) + m E_m(mu) P(r, R) ]
// E_irr: the SH9 irradiance; P: the prefiltered levels, linear in roughness; E_ds: the dielectric
// specular albedo from prw_brdf.h's fits (the same terms the direct light's lobes use, ggx_view);
// E_m = F0 A + B + F_ms(F0 + (1 - F0) / 21) Ec with A, B the split-sum table.  V: the baked
// environment visibility of the light maps (prw_gi.h: the unoccluded fraction of the environment's
// irradiance) where the surface is light-mapped, else 1 (dynamic and unbaked surfaces are not occluded).
// The specular part takes instead the part of the specular lobe (about R, 90 % of it within
// 2 atan(3 alpha)) that the baked open cone (about b, half-angle asin(sqrt(f)), prw_gi.h) lets through,
// both as Gaussians in angle (prw_env_specular_visible), read in that part's direction at its
// roughness, times the cone's occupancy (the open solid angle over that of the cap the open directions
// spread over: below 1 where the opening is not one disc); where there is no cone, V.
// Specialisation PRW_SC_ENV = 0 (no environment): nothing.
// Mirror images (globals params.z = 1, pass_mirror.c) draw the term only in the light-map variants: a
// static surface drawn there without its visibility would show the unoccluded environment.
// Needs lights.glsl (ggx_view), gi_lightmap.glsl (prw_terms) and prw_constants.h.
#ifndef PRW_GI_ENV_GLSL
#define PRW_GI_ENV_GLSL

layout(constant_id = PRW_SC_ENV) const int prw_env_on = 0;

#include "env_lookup.glsl"

vec3 prw_env_irradiance(vec3 n)
{
    vec3 m = prw_env_to_map(n);
    float x = m.x, y = m.y, z = m.z;
    const float pi = 3.14159265358979;
    vec3 e = pi * 0.282094792 * prw_env.sh[0].rgb;
    e += (2.0 * pi / 3.0) * 0.488602512 * (prw_env.sh[1].rgb * y + prw_env.sh[2].rgb * z + prw_env.sh[3].rgb * x);
    e += (pi / 4.0) * (1.092548431 * (prw_env.sh[4].rgb * (x * y) + prw_env.sh[5].rgb * (y * z) + prw_env.sh[7].rgb * (x * z)) +
                       0.315391565 * prw_env.sh[6].rgb * (3.0 * z * z - 1.0) + 0.546274215 * prw_env.sh[8].rgb * (x * x - y * y));
    return max(e, vec3(0.0));
}

// P(r, R): the levels interpolated linearly in roughness.
vec3 prw_env_prefiltered(vec3 r_dir, float roughness)
{
    float k = clamp(roughness, 0.0, 1.0) * (prw_env.rot.z - 1.0);
    float k0 = floor(k), k1 = min(k0 + 1.0, prw_env.rot.z - 1.0);
    vec2 uv = prw_env_uv(r_dir); // once for both levels
    return mix(textureLod(prw_env_levels, vec3(uv, k0), 0.0).rgb, textureLod(prw_env_levels, vec3(uv, k1), 0.0).rgb,
               k - k0);
}

// V at the fragment: the light map's where there is one.
float prw_env_visibility()
{
#ifdef PRW_GI
    return prw_gi_lookup().a;
#else
    return 1.0;
#endif
}

vec4 prw_env_cone()
{
#ifdef PRW_GI
    return prw_gi_cone();
#else
    return vec4(0.0, 0.0, 0.0, -1.0);
#endif
}

// The specular lobe's visible part (see the top): the lobe about r taken as a Gaussian in angle of
// variance s2 (90 % inside ts = 2 atan(3 alpha): s2 = ts^2 / (2 ln 10)), the open cone as a Gaussian of
// variance tv^2 / 2 about b.  Their product is where the environment is seen; the occlusion is the
// lobe's mass in a disc of radius tv, (1 - exp(-tv^2 / (2 s2))) (exact with r on the axis), times
// exp(-max(d - tv, 0)^2 / (2 s2)) for r at angle d from b (a hard edge for a sharp lobe, the Gaussian's
// fall-off for a wide one); the product's centre the direction to read the prefiltered levels in, its spread the roughness to
// read them at (never above the surface's).  Out: dir (xyz), occlusion (w); *r_read the roughness.
vec4 prw_env_specular_visible(vec4 cone, vec3 n, vec3 r, float roughness, float vis, out float r_read)
{
    r_read = roughness;
    if (cone.w < 0.0) return vec4(r, vis);
    float lb = length(cone.xyz);
    if (lb < 1e-5 || cone.w <= 0.0) return vec4(r, 0.0);
    vec3 b = cone.xyz / lb;
    // how much of the bounding cone of the open directions is open: the cap about b whose uniform mean
    // cosine is the open rays' |b| / f, against the open solid angle (the cosine-weighted fraction f,
    // tilted by b.n); 1 for one disc-like opening, less for a ring (a window partly hidden by an
    // object) or scattered openings, whose holes the disc would let through
    float rbar = clamp(lb / cone.w, 0.0, 1.0);
    float cap_f = 1.0 - sqrt(1.0 - min(cone.w / max(dot(b, n), 0.05), 1.0)); // 1 - cos asin(sqrt(f / b.n))
    float q = clamp(cap_f / max(2.0 - 2.0 * rbar, 1e-6), 0.0, 1.0);
    float tv = asin(sqrt(min(cone.w, 1.0)));
    float ts = min(2.0 * atan(3.0 * prw_alpha_from_roughness(roughness)), 1.5707963);
    float s2 = ts * ts * (1.0 / 4.6051702), c2 = 0.5 * tv * tv;
    float d = acos(clamp(dot(b, r), -1.0, 1.0));
    float lo = abs(tv - ts), hi = tv + ts; // Oat & Sander's smooth cone-cone overlap
    float inter = 1.0 - smoothstep(0.0, 1.0, clamp((d - lo) / max(hi - lo, 1e-4), 0.0, 1.0));
    float occ = inter * (1.0 - cos(min(tv, ts))) / max(1.0 - cos(ts), 1e-6);
    vec3 dir = normalize(mix(r, b, s2 / (s2 + c2)) + 1e-6 * r);
    float te = sqrt(s2 * c2 / (s2 + c2) * 4.6051702); // the product's 90 % angle
    r_read = min(roughness, sqrt(tan(0.5 * te) * (1.0 / 3.0)));
    return vec4(dir, clamp(occ * q, 0.0, 1.0));
}

vec3 prw_env_radiance(ggx_view w, vec3 n, vec3 v, vec3 base, float metallic, float roughness, float specular, float vis,
                      vec4 cone)
{
    if (prw_env_on == 0 || (prw_terms & PRW_TERM_ENVIRONMENT) == 0) return vec3(0.0);
#ifndef PRW_GI
    if (g.params.z > 0.5) return vec3(0.0);
#endif
    float nv = dot(n, v);
    float mu = clamp(nv, 1e-4, 1.0);
    vec3 r_dir = 2.0 * nv * n - v;
    float m = clamp(metallic, 0.0, 1.0);
    float e_ds = ggx_dielectric_albedo(w, specular);
    float n_dfg = float(textureSize(prw_env_dfg, 0).x);
    float rr = clamp(roughness, 0.0, 1.0);
    vec2 ab = textureLod(prw_env_dfg, vec3(mu, (rr * (n_dfg - 1.0) + 0.5) / n_dfg, 0.0), 0.0).rg;
    vec3 e_m = ggx_metal_albedo(w, base, ab);
    float r_read;
    vec4 sv = prw_env_specular_visible(cone, n, normalize(r_dir), rr, vis, r_read);
    vec3 p = prw_env_prefiltered(sv.xyz, r_read) * sv.w;
    return (1.0 - m) * (vis * base * (1.0 - e_ds) * prw_env_irradiance(n) * (1.0 / 3.14159265358979) + e_ds * p) +
           m * e_m * p;
}
#endif
