// material_gltf.glsl — the glTF metallic-roughness material kind (material kind 0, set 1 of the base
// layout; C mirror prw_gpu_material in engine/render/gpu_types.h): the surface a fragment shades with,
// from the material factors, its textures and the interpolated frame, by the shared rules of
// prw_shading.h (channels, normal-map decode, double-sided flip).  Needs prw_shading.h.
#ifndef PRW_MATERIAL_GLTF_GLSL
#define PRW_MATERIAL_GLTF_GLSL

layout(std140, set = 1, binding = 0) uniform prw_material_block {
    vec4 base_color;
    vec4 emission;   // rgb cd/m^2, w: normal scale
    vec4 mr;         // x: metallic, y: roughness, z: double sided, w: has normal map
    vec4 extra;      // x: specular (dielectric F0 scale), y: material slot + 1 (G-buffer id)
} mat;
layout(set = 1, binding = 1) uniform sampler2D tex_base;      // sRGB decoded by the sampler
layout(set = 1, binding = 2) uniform sampler2D tex_mr;        // G roughness, B metallic
layout(set = 1, binding = 3) uniform sampler2D tex_normal;    // tangent space
layout(set = 1, binding = 4) uniform sampler2D tex_emissive;  // sRGB decoded

struct prw_surface {
    vec3 base;
    float metallic, roughness, specular;
    vec3 n;        // shading normal (not yet bent towards the viewer)
    vec3 emission; // cd/m^2
    bool double_sided;
};

prw_surface prw_material_surface(vec2 uv, vec3 normal, vec4 tangent, bool front_facing)
{
    prw_surface S;
    vec4 base4 = mat.base_color * texture(tex_base, uv);
    S.base = base4.rgb;
    vec4 mrt = texture(tex_mr, uv);
    S.roughness = prw_roughness_from(mat.mr.y, mrt.g);
    S.metallic = prw_metallic_from(mat.mr.x, mrt.b);
    S.specular = mat.extra.x;
    S.double_sided = mat.mr.z > 0.5;

    vec3 n = normalize(normal);
    if (prw_normal_flips(mat.mr.z > 0.5, front_facing)) n = -n;
    if (mat.mr.w > 0.5) {
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
    S.emission = mat.emission.rgb * texture(tex_emissive, uv).rgb;
    return S;
}

#endif
