#version 450
#extension GL_GOOGLE_include_directive : require
// The alpha test of a cut-out shadow caster (pass_shadow.c, shadow_mask.vert): MASK keeps the fragment
// where the base colour's alpha reaches the cutoff (prw_shading.h), as the base pass does; a BLEND
// material casts the shadow of its alpha at 0.5 (a shadow map holds no partial coverage: the
// rasterizer's documented approximation of the path tracer's 1 - alpha transmission).  No colour output.
#define PRW_GLTF_EXT 1
#include "prw_constants.h"
#include "prw_shading.h"
#include "material_gltf.glsl"
layout(location = 2) in vec2 v_uv;
layout(location = 4) in vec2 v_uv1;
void main()
{
    float a = prw_material_alpha(v_uv, v_uv1);
    float cutoff = int(mat.alpha.x) == PRW_GPU_ALPHA_MASK ? mat.alpha.y : 0.5;
    if (!prw_alpha_mask_keeps(a, cutoff)) discard;
}
