// ltc.glsl — the rect lights' single-scattering GGX specular by linearly transformed cosines (Heitz,
// Dupuy, Hill & Neubelt 2016; lights.glsl uses it with PRW_RECT_LTC defined): the table
// (materials/prw_ltc.h says its layout; fitted to prw_brdf.h's lobe by materials/tools/gen_ltc_fit.c)
// maps the lobe D V (n.l) at (roughness, n.v) to a clamped cosine, whose integral over the transformed
// rectangle is Lambert's polygon formula (polygon.glsl).
// materials/prw_ltc.c is the C twin of rect_specular_ltc (tests/render/test_ltc_gpu.c checks they agree).
// Needs prw_brdf.h and polygon.glsl included before it.  The table is a 2-layer array image with linear
// filtering and clamp to edge, at set PRW_LTC_SET, binding PRW_LTC_BINDING (the base pass: set 0, binding 3).
#ifndef PRW_LTC_GLSL
#define PRW_LTC_GLSL

#ifndef PRW_LTC_SET
#define PRW_LTC_SET 0
#define PRW_LTC_BINDING 3
#endif
layout(set = PRW_LTC_SET, binding = PRW_LTC_BINDING) uniform sampler2DArray prw_ltc_table;
#define PRW_LTC_TABLE_N 64.0 // PRW_LTC_N of materials/prw_ltc_table.h (asserted in materials/prw_ltc.c)

// Both layers of the table at (roughness, n.v in (0, 1]): m = M^-1's (m00, m02, m20, m22), f = (albedo,
// Schlick weight, dielectric Fresnel weight, 0).
void ltc_lookup(float roughness, float NoV, out vec4 m, out vec4 f)
{
    vec2 uv = vec2((prw_clamp01(roughness) * (PRW_LTC_TABLE_N - 1.0) + 0.5) / PRW_LTC_TABLE_N,
                   (sqrt(1.0 - prw_clamp01(NoV)) * (PRW_LTC_TABLE_N - 1.0) + 0.5) / PRW_LTC_TABLE_N);
    m = texture(prw_ltc_table, vec3(uv, 0.0));
    f = texture(prw_ltc_table, vec3(uv, 1.0));
}

// The single-scattering specular of a rect light (centre c, half axes du, dv; radiance 1) at p (normal
// n, towards the eye v), per RGB channel: A * LTC integral * ((1 - m) specular C + m (F0 + (1 - F0) B)).
vec3 rect_specular_ltc(vec3 p, vec3 n, vec3 v, vec3 c, vec3 du, vec3 dv, vec3 base, float metallic, float roughness,
                       float specular)
{
    float NoV = min(max(dot(n, v), 1e-4), 1.0);
    vec4 m, f;
    ltc_lookup(roughness, NoV, m, f);
    // the frame (t1, t2, n): t1 along v's part in the tangent plane (any tangent when v is along n,
    // where the lobe is symmetric about n)
    float nv = dot(n, v);
    vec3 t1 = v - n * nv;
    float l2 = dot(t1, t1);
    vec3 a = abs(n.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
    vec3 t0 = a - n * dot(a, n);
    t1 = l2 > 1e-12 ? t1 * (1.0 / sqrt(l2)) : t0 * (1.0 / sqrt(dot(t0, t0)));
    vec3 t2 = cross(n, t1);
    // the corners in the frame, through M^-1 = [[m.x, 0, m.y], [0, 1, 0], [m.z, 0, m.w]]
    vec3 d0 = c - du - dv - p, d1 = c + du - dv - p, d2 = c + du + dv - p, d3 = c - du + dv - p;
    vec3 x = vec3(dot(t1, d0), dot(t2, d0), dot(n, d0));
    vec3 q0 = vec3(m.x * x.x + m.y * x.z, x.y, m.z * x.x + m.w * x.z);
    x = vec3(dot(t1, d1), dot(t2, d1), dot(n, d1));
    vec3 q1 = vec3(m.x * x.x + m.y * x.z, x.y, m.z * x.x + m.w * x.z);
    x = vec3(dot(t1, d2), dot(t2, d2), dot(n, d2));
    vec3 q2 = vec3(m.x * x.x + m.y * x.z, x.y, m.z * x.x + m.w * x.z);
    x = vec3(dot(t1, d3), dot(t2, d3), dot(n, d3));
    vec3 q3 = vec3(m.x * x.x + m.y * x.z, x.y, m.z * x.x + m.w * x.z);
    vec3 sum;
    if (!quad_edge_sum(q0, q1, q2, q3, vec3(0.0, 0.0, 1.0), sum)) return vec3(0.0);
    float I = abs(sum.z) * (0.5 / PRW_BRDF_PI) * f.x;
    float mt = prw_clamp01(metallic);
    float diel = (1.0 - mt) * prw_clamp01(specular) * f.z;
    return I * (vec3(diel) + mt * (base + (vec3(1.0) - base) * f.y));
}

#endif
