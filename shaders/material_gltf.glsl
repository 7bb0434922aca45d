// material_gltf.glsl — the glTF metallic-roughness material kind (material kind 0, set 1 of the base
// layout; C mirror prw_gpu_material in engine/render/gpu_types.h): the surface a fragment shades with,
// from the material factors, its textures and the interpolated frame, by the shared rules of
// prw_shading.h (channels, normal-map decode, double-sided flip).  Needs prw_shading.h.
// PRW_GLTF_EXT (the pipelines of materials with glTF extension features, engine/render/scene_gpu.h):
// alpha (MASK / BLEND), a uv set and KHR_texture_transform per texture slot, and with PRW_GLTF_COAT
// KHR_materials_clearcoat; without it the material is exactly the core one (no transform, uv set 0,
// no coat).  prw_material_ggx_view when lights.glsl is included before it.
#ifndef PRW_MATERIAL_GLTF_GLSL
#define PRW_MATERIAL_GLTF_GLSL

#include "prw_brdf.h" /* prw_ggx_row (the block's fit rows) */

layout(std140, set = 1, binding = 0) uniform prw_material_block {
    vec4 base_color;
    vec4 emission;   // rgb cd/m^2, w: normal scale
    vec4 mr;         // x: metallic, y: roughness, z: double sided, w: has normal map
    vec4 extra;      // x: specular (dielectric F0 scale), y: material slot + 1 (G-buffer id)
    vec4 alpha;      // x: mode (PRW_GPU_ALPHA_*), y: cutoff  (read with PRW_GLTF_EXT only)
    vec4 coat;       // x: clearcoat factor, y: clearcoat roughness factor, z: coat normal scale, w: has coat normal map
    vec4 xf[2 * PRW_GPU_SLOTS]; // per slot: (offset u, offset v, cos r, sin r), (scale u, scale v, uv set, 0)
    prw_ggx_row ggx_ec, ggx_ed; // the fits' rows at the factor roughness (std140: 16 floats each)
    vec4 ggx_avg;               // x: Ec_avg, y: Ed_avg at the factor roughness
} mat;
layout(set = 1, binding = 1) uniform sampler2D tex_base;      // sRGB decoded by the sampler
layout(set = 1, binding = 2) uniform sampler2D tex_mr;        // G roughness, B metallic
layout(set = 1, binding = 3) uniform sampler2D tex_normal;    // tangent space
layout(set = 1, binding = 4) uniform sampler2D tex_emissive;  // sRGB decoded
#ifdef PRW_GLTF_EXT
layout(set = 1, binding = 5) uniform sampler2D tex_coat;           // R: clear coat weight
layout(set = 1, binding = 6) uniform sampler2D tex_coat_roughness; // G: clear coat roughness
layout(set = 1, binding = 7) uniform sampler2D tex_coat_normal;    // tangent space
#endif

// What the slot lacks (PRW_GPU_MAT_*, prw_constants.h), specialised per pipeline (engine/render/pipes.c):
// on lavapipe a branch on a uniform still runs both sides, a constant removes the code.
layout(constant_id = PRW_SC_MAT) const int prw_mat_lacks = 0;
const bool prw_no_base_tex = (prw_mat_lacks & PRW_GPU_MAT_NO_BASE_TEX) != 0;
const bool prw_no_mr_tex = (prw_mat_lacks & PRW_GPU_MAT_NO_MR_TEX) != 0;
const bool prw_no_normal_tex = (prw_mat_lacks & PRW_GPU_MAT_NO_NORMAL_TEX) != 0;
const bool prw_no_emissive_tex = (prw_mat_lacks & PRW_GPU_MAT_NO_EMISSIVE_TEX) != 0;
const bool prw_no_metal = (prw_mat_lacks & PRW_GPU_MAT_NO_METAL) != 0;
const bool prw_all_metal = (prw_mat_lacks & PRW_GPU_MAT_ALL_METAL) != 0;
const bool prw_mat_probed = (prw_mat_lacks & PRW_GPU_MAT_PROBE) != 0; // gi_probe.glsl

#ifdef PRW_LIGHTS_GLSL
// The fits at the surface's roughness and n.v (lights.glsl): from the block when the roughness is the
// factor (the CPU computed the rows with the same float operations), else here.
ggx_view prw_material_ggx_view(float NoV, float roughness)
{
    if (!prw_no_mr_tex) return ggx_view_at(NoV, roughness);
    return ggx_view_from(NoV, mat.ggx_ec, mat.ggx_ed, mat.ggx_avg.x, mat.ggx_avg.y);
}
#endif

// metallic as the material gives it (factor x texel), as a constant where it is one: the lobes it
// weights by 0 then fold away (the same value: 0 x a finite texel is 0, 1 x white is 1).
float prw_metallic(float texel_b)
{
    return prw_no_metal ? 0.0 : prw_all_metal ? 1.0 : prw_metallic_from(mat.mr.x, texel_b);
}

// The slot's textures, or what their fallbacks give (white; texture() of the 1 x 1 white is exactly 1).
vec4 prw_tex_base(vec2 uv) { return prw_no_base_tex ? vec4(1.0) : texture(tex_base, uv); }
vec4 prw_tex_mr(vec2 uv) { return prw_no_mr_tex ? vec4(1.0) : texture(tex_mr, uv); }
vec3 prw_tex_emissive(vec2 uv) { return prw_no_emissive_tex ? vec3(1.0) : texture(tex_emissive, uv).rgb; }
bool prw_has_normal_map() { return !prw_no_normal_tex && mat.mr.w > 0.5; }

struct prw_surface {
    vec3 base;
    float metallic, roughness, specular;
    vec3 n;        // shading normal (not yet bent towards the viewer)
    vec3 emission; // cd/m^2
    bool double_sided;
#ifdef PRW_GLTF_EXT
    float alpha;   // base_color.a x texel.a
    float clearcoat, clearcoat_roughness;
    vec3 nc;       // the clear coat's normal (not yet bent)
#endif
};

#ifndef PRW_GLTF_EXT
prw_surface prw_material_surface(vec2 uv, vec3 normal, vec4 tangent, bool front_facing)
{
    prw_surface S;
    vec4 base4 = mat.base_color * prw_tex_base(uv);
    S.base = base4.rgb;
    vec4 mrt = prw_tex_mr(uv);
    S.roughness = prw_roughness_from(mat.mr.y, mrt.g);
    S.metallic = prw_metallic(mrt.b);
    S.specular = mat.extra.x;
    S.double_sided = mat.mr.z > 0.5;

    vec3 n = normalize(normal);
    if (prw_normal_flips(mat.mr.z > 0.5, front_facing)) n = -n;
    if (prw_has_normal_map()) {
        vec3 t = tangent.xyz - n * dot(n, tangent.xyz);
        float tl = length(t);
        if (tl > 1e-8) {
            t /= tl;
            vec3 b = cross(n, t) * (tangent.w < 0.0 ? -1.0 : 1.0);
            vec3 tt = texture(tex_normal, uv).xyz;
            vec3 tn = vec3(prw_normal_texel(tt.x, mat.emission.w), prw_normal_texel(tt.y, mat.emission.w),
                           tt.z * 2.0 - 1.0);
            n = normalize(t * tn.x + b * tn.y + n * tn.z);
        }
    }
    S.n = n;
    S.emission = mat.emission.rgb * prw_tex_emissive(uv);
    return S;
}
#else
// The uv of texture slot `slot`: its uv set, then its transform (prw_shading.h).
vec2 prw_slot_uv(int slot, vec2 uv0, vec2 uv1)
{
    vec4 a = mat.xf[2 * slot], b = mat.xf[2 * slot + 1];
    vec2 uv = b.z > 0.5 ? uv1 : uv0;
    return vec2(prw_uv_xf_u(uv.x, uv.y, a.x, a.z, a.w, b.x, b.y), prw_uv_xf_v(uv.x, uv.y, a.y, a.z, a.w, b.x, b.y));
}

// The base colour's alpha alone (the shadow pass's cut-out test).
float prw_material_alpha(vec2 uv0, vec2 uv1)
{
    return prw_alpha_from(mat.base_color.a, texture(tex_base, prw_slot_uv(PRW_GPU_SLOT_BASE, uv0, uv1)).a);
}

// A normal map's texel tt (slot `slot`, xy scale `scale`) applied to n in the interpolated tangent frame.
vec3 prw_apply_normal_map(vec3 n, vec4 tangent, vec3 tt, float scale, int slot)
{
    vec3 t = tangent.xyz - n * dot(n, tangent.xyz);
    float tl = length(t);
    if (!(tl > 1e-8)) return n;
    t /= tl;
    vec3 b = cross(n, t) * (tangent.w < 0.0 ? -1.0 : 1.0);
    vec3 tn = vec3(prw_normal_texel(tt.x, scale), prw_normal_texel(tt.y, scale), tt.z * 2.0 - 1.0);
    vec4 a = mat.xf[2 * slot], s = mat.xf[2 * slot + 1];
    float xt = prw_normal_xf_t(tn.x, tn.y, a.z, a.w, s.x, s.y), yb = prw_normal_xf_b(tn.x, tn.y, a.z, a.w, s.x, s.y);
    return normalize(t * xt + b * yb + n * tn.z);
}

prw_surface prw_material_surface(vec2 uv, vec2 uv1, vec3 normal, vec4 tangent, bool front_facing)
{
    prw_surface S;
    vec4 base4 = mat.base_color * prw_tex_base(prw_slot_uv(PRW_GPU_SLOT_BASE, uv, uv1));
    S.base = base4.rgb;
    S.alpha = base4.a;
    vec4 mrt = prw_tex_mr(prw_slot_uv(PRW_GPU_SLOT_METAL_ROUGH, uv, uv1));
    S.roughness = prw_roughness_from(mat.mr.y, mrt.g);
    S.metallic = prw_metallic(mrt.b);
    S.specular = mat.extra.x;
    S.double_sided = mat.mr.z > 0.5;

    vec3 n = normalize(normal);
    if (prw_normal_flips(mat.mr.z > 0.5, front_facing)) n = -n;
    S.nc = n;
    if (prw_has_normal_map())
        n = prw_apply_normal_map(n, tangent, texture(tex_normal, prw_slot_uv(PRW_GPU_SLOT_NORMAL, uv, uv1)).xyz,
                                 mat.emission.w, PRW_GPU_SLOT_NORMAL);
    S.n = n;
    S.emission = mat.emission.rgb * prw_tex_emissive(prw_slot_uv(PRW_GPU_SLOT_EMISSIVE, uv, uv1));
    S.clearcoat = 0.0;
    S.clearcoat_roughness = 0.0;
#ifdef PRW_GLTF_COAT
    if (mat.coat.x > 0.0) {
        S.clearcoat = prw_clearcoat_from(mat.coat.x, texture(tex_coat, prw_slot_uv(PRW_GPU_SLOT_CLEARCOAT, uv, uv1)).r);
        S.clearcoat_roughness = prw_clearcoat_roughness_from(
            mat.coat.y, texture(tex_coat_roughness, prw_slot_uv(PRW_GPU_SLOT_CLEARCOAT_ROUGHNESS, uv, uv1)).g);
        if (mat.coat.w > 0.5)
            S.nc = prw_apply_normal_map(
                S.nc, tangent, texture(tex_coat_normal, prw_slot_uv(PRW_GPU_SLOT_CLEARCOAT_NORMAL, uv, uv1)).xyz,
                mat.coat.z, PRW_GPU_SLOT_CLEARCOAT_NORMAL);
    }
#endif
    return S;
}
#endif

#endif
