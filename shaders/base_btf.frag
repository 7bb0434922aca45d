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
#include "gi_lightmap.glsl"
#include "gi_env.glsl"

// Base pass of the BTF material kind (prw_material.btf_file): emission + direct light of every light
// through the BTF (btf_lights.glsl), with an environment its term (btf_env.glsl), with the path tracer's frame and texel mapping (engine/reference
// ref_trace.c btf_frame, prw_scene.h): the triangle's dP/du, dP/dv (uv set 0, here from the screen
// derivatives of the interpolated position and uv: exact for a triangle's affine mapping) give x = dP/du
// made tangent to the shading normal, y = n x x turned towards dP/dv, texel (u |dP/du|, v |dP/dv|) /
// texel size.  The material's words are in the scene's BTF buffer (set 1 binding 8, prw_btf_gpu.h).

layout(location = 0) in vec3 v_pos;
layout(location = 1) in vec3 v_normal;
layout(location = 2) in vec2 v_uv;
layout(location = 3) in vec4 v_tangent;

// the leading members of the material block (engine/render/gpu_types.h prw_gpu_material); the BTF kind's
// alpha.z: word offset of the material in the BTF buffer (its bits), alpha.w: 1 / texel size (1/m),
// alpha.y: 1 when base_color.rgb, mr.xy (metallic, roughness) and extra.x (specular) hold the file's
// fitted average BRDF (the scale rule)
layout(std140, set = 1, binding = 0) uniform prw_material_block {
    vec4 base_color;
    vec4 emission;
    vec4 mr;    // z: double sided
    vec4 extra; // y: material slot + 1
    vec4 alpha;
} mat;
layout(std430, set = 1, binding = 8) readonly buffer prw_btf_words { uint btf_blob[]; };
#define PRW_BTF_BLOB(i) btf_blob[i]
// the same words as 4 x 32-bit texels: 8 halves of an RGB block in one vector fetch (a storage-buffer
// load is a loop over the lanes on lavapipe)
layout(set = 1, binding = 9) uniform usamplerBuffer btf_block_texels;
#define PRW_BTF_BLOCK(e) texelFetch(btf_block_texels, int(e))
// the slot's codec and component count (prw_btf_gpu_spec, engine/render/scene_gpu.c puts it where the
// glTF kind's PRW_SC_MAT says what it lacks): (codec - 1) | (components + 1) << 2, or just the codec
// (components + 1 = 0: read from the words)
layout(constant_id = PRW_SC_MAT) const uint prw_btf_sc = 0u;
#define PRW_BTF_CODEC ((prw_btf_sc & 3u) + 1u)
#define PRW_BTF_K1 (prw_btf_sc >> 2u)
#include "btf_eval.glsl"
#include "btf_lights.glsl"
#include "btf_env.glsl"

layout(location = 0) out vec4 o_color;
#ifdef PRW_GBUFFER
layout(location = 1) out vec4 o_normal; // camera-relative shading normal, roughness
layout(location = 2) out uint o_id;     // material slot + 1
#endif

void main()
{
    vec3 n = normalize(v_normal);
    if (prw_normal_flips(mat.mr.z > 0.5, gl_FrontFacing)) n = -n;
#ifdef PRW_MULTIVIEW
    vec3 v = normalize(prw_mv.eye_rel[gl_ViewIndex].xyz - v_pos);
#else
    vec3 v = normalize(g.eye_rel.xyz - v_pos);
#endif
    float bend = prw_normal_bend(dot(n, v));
    if (bend > 0.0) n = normalize(n + v * bend);

    // dP/du, dP/dv from the derivatives (x, y: screen axes)
    vec3 p1 = dFdx(v_pos), p2 = dFdy(v_pos);
    vec2 u1 = dFdx(v_uv), u2 = dFdy(v_uv);
    float det = u1.x * u2.y - u2.x * u1.y;
    vec3 dpu = (p1 * u2.y - p2 * u1.y) / det, dpv = (p2 * u1.x - p1 * u2.x) / det;
    float lu = length(dpu), lv = length(dpv);
    btf_frame F;
    F.n = n;
    F.xy = vec2(0.5);
    vec3 t = dpu - n * dot(dpu, n);
    float tl = length(t);
    if (abs(det) > 0.0 && lu > 0.0 && lv > 0.0 && !isinf(lu) && !isinf(lv) && !isnan(lu + lv) && tl > 1e-6 * lu) {
        F.t = t / tl;
        F.b = cross(n, F.t);
        if (dot(F.b, dpv) < 0.0) F.b = -F.b;
        // wrapped into one tile in float (the BTF tiles; prw_btf_interp_texel wraps again)
        vec2 xy = v_uv * vec2(lu, lv) * mat.alpha.w;
        F.xy = xy;
    } else { // no usable uv mapping: an arbitrary frame, texel (0.5, 0.5), as the path tracer
        vec3 a = abs(n.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
        F.t = normalize(a - n * dot(a, n));
        F.b = cross(n, F.t);
    }
    vec3 radiance = mat.emission.rgb;
    // The scale rule (the path tracer's with btf_scale_rule, ref_trace.c setup_shade): where the pixel
    // footprint across the ray (the pinhole's tangent spread per pixel x distance) exceeds the texel x
    // |cos theta_v|, the file's fitted average BRDF (material_gltf.glsl's model) instead of the BTF.
#ifdef PRW_MULTIVIEW
    mat4 vp = prw_mv.view_proj[gl_ViewIndex];
    vec3 eye = prw_mv.eye_rel[gl_ViewIndex].xyz;
#else
    mat4 vp = g.view_proj;
    vec3 eye = g.eye_rel.xyz;
#endif
    vec4 clip = vp * vec4(v_pos, 1.0);
    float p11 = length(vec3(vp[0][1], vp[1][1], vp[2][1])); // 1 / tan(half fov): clip y = p11 x view y
    float px_m = abs(dFdy(clip.y / clip.w)) / p11 * length(v_pos - eye);
    // The terms (gi_lightmap.glsl's PRW_SC_TERMS): direct = emission + direct light; with an environment
    // (PRW_SC_ENV) + the environment term: the average BRDF's (gi_env.glsl) or the BTF's (btf_env.glsl),
    // occluded by the light maps' visibility in the PRW_GI variant.  No indirect diffuse from the light
    // maps on either (the BTF's response to it is not built; the average alone would jump at the switch).
    if ((prw_terms & PRW_TERM_DIRECT) == 0) radiance = vec3(0.0);
    if (mat.alpha.y > 0.5 && px_m * mat.alpha.w > abs(dot(n, v))) {
        float rough = prw_roughness_from(mat.mr.y, 1.0);
        ggx_view w = ggx_view_at(dot(n, v), rough);
        if ((prw_terms & PRW_TERM_DIRECT) != 0)
            prw_direct_light(radiance, w, v_pos, n, v, mat.base_color.rgb, mat.mr.x, rough, mat.extra.x, 1.5);
        radiance += prw_env_radiance(w, n, v, mat.base_color.rgb, mat.mr.x, rough, mat.extra.x, prw_env_visibility(),
                                     prw_env_cone());
    } else {
        uint m = floatBitsToUint(mat.alpha.z);
        btf_px X = btf_setup(m, F.xy, btf_to_local(F, v)); // the view's directions and the texels: once
        if ((prw_terms & PRW_TERM_DIRECT) != 0) prw_btf_direct_light_px(radiance, X, F, v_pos, 1.5);
        radiance += prw_btf_env_light(X, F, m, prw_env_visibility());
    }
    o_color = vec4(radiance, 1.0);
#ifdef PRW_GBUFFER
    o_normal = vec4(n, 1.0);
    o_id = uint(mat.extra.y);
#endif
}
