#version 450
#extension GL_GOOGLE_include_directive : require
#ifdef PRW_MULTIVIEW
#extension GL_EXT_multiview : require
layout(std140, set = 2, binding = 0) uniform prw_mv_block { mat4 view_proj[2]; vec4 eye_rel[2]; } prw_mv;
#endif
#include "common.glsl"
#include "prw_brdf.h"
#include "prw_shading.h"
#include "shadows.glsl"
#include "lights.glsl"
#include "material_gltf.glsl"
#include "gi_lightmap.glsl"
#include "gi_env.glsl"
#include "gi_probe.glsl"

// Base pass: emission + direct light from every light (shadowed by shadow maps), in cd/m^2, for one
// material kind (material_gltf.glsl; variants by -D, shaders/CMakeLists.txt).  PRW_GBUFFER also writes
// the shading normal / roughness and the material id for later passes.  PRW_GLTF_EXT: the glTF
// extension features (uv set 1, texture transforms; MASK discards below the cutoff, BLEND writes
// alpha = coverage for the "over" blend of its pipeline); with PRW_GLTF_COAT the clear coat too.
// PRW_GI: + the light maps' indirect diffuse and rough surfaces' indirect glossy (gi_lightmap.glsl, which
// also gates the terms drawn).
// With an environment (PRW_SC_ENV): + the environment term (gi_env.glsl; not under a clear coat).
// With reflection probes (PRW_SC_PROBES): + the probe term (gi_probe.glsl; not under a clear coat).

layout(location = 0) in vec3 v_pos;
layout(location = 1) in vec3 v_normal;
layout(location = 2) in vec2 v_uv;
layout(location = 3) in vec4 v_tangent;
#ifdef PRW_GLTF_EXT
layout(location = 4) in vec2 v_uv1;
#endif

layout(location = 0) out vec4 o_color;
#ifdef PRW_GBUFFER
layout(location = 1) out vec4 o_normal; // camera-relative shading normal, roughness
layout(location = 2) out uint o_id;     // material slot + 1
#endif

void main()
{
#ifdef PRW_GLTF_EXT
    prw_surface S = prw_material_surface(v_uv, v_uv1, v_normal, v_tangent, gl_FrontFacing);
    int mode = int(mat.alpha.x);
    if (mode == PRW_GPU_ALPHA_MASK && !prw_alpha_mask_keeps(S.alpha, mat.alpha.y)) discard;
#else
    prw_surface S = prw_material_surface(v_uv, v_normal, v_tangent, gl_FrontFacing);
#endif
    vec3 n = S.n;
#ifdef PRW_MULTIVIEW
    vec3 v = normalize(prw_mv.eye_rel[gl_ViewIndex].xyz - v_pos);
#else
    vec3 v = normalize(g.eye_rel.xyz - v_pos);
#endif
    float bend = prw_normal_bend(dot(n, v));
    if (bend > 0.0) n = normalize(n + v * bend);

    // a mirror image (params.z = 1) leaves emission out: a light seen in a mirror is the direct term's
    vec3 radiance = S.emission * (1.0 - g.params.z);
    ggx_view w = prw_material_ggx_view(dot(n, v), S.roughness);
#ifdef PRW_GLTF_EXT
#ifdef PRW_GLTF_COAT
    vec3 nc = S.nc;
    float bend_c = prw_normal_bend(dot(nc, v));
    if (bend_c > 0.0) nc = normalize(nc + v * bend_c);
    prw_direct_light_coated(radiance, w, v_pos, n, nc, v, S.base, S.metallic, S.roughness, S.specular, S.clearcoat,
                            S.clearcoat_roughness, 1.5);
#else
    prw_direct_light(radiance, w, v_pos, n, v, S.base, S.metallic, S.roughness, S.specular, 1.5);
#endif
    radiance = prw_terms_radiance(radiance, w, S.base, S.metallic, S.roughness, S.specular, prw_mat_probed);
#ifndef PRW_GLTF_COAT
    radiance += prw_env_radiance(w, n, v, S.base, S.metallic, S.roughness, S.specular, prw_env_visibility(),
                                 prw_env_cone()) +
                prw_probe_radiance(w, v_pos, n, v, S.base, S.metallic, S.roughness, S.specular);
#endif
    o_color = vec4(radiance, mode == PRW_GPU_ALPHA_BLEND ? clamp(S.alpha, 0.0, 1.0) : 1.0);
#else
    prw_direct_light(radiance, w, v_pos, n, v, S.base, S.metallic, S.roughness, S.specular, 1.5);
    o_color = vec4(prw_terms_radiance(radiance, w, S.base, S.metallic, S.roughness, S.specular, prw_mat_probed) +
                       prw_env_radiance(w, n, v, S.base, S.metallic, S.roughness, S.specular, prw_env_visibility(),
                                        prw_env_cone()) +
                       prw_probe_radiance(w, v_pos, n, v, S.base, S.metallic, S.roughness, S.specular),
                   1.0);
#endif
#ifdef PRW_GBUFFER
    o_normal = vec4(n, S.roughness);
    o_id = uint(mat.extra.y);
#endif
}
