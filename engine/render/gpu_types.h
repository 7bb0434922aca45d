/* gpu_types — the C mirrors of the shaders' uniform blocks (std140), checked against the GLSL layout
 * rules and the shared constants (shaders/prw_constants.h) at compile time. */
#ifndef PRW_GPU_TYPES_H
#define PRW_GPU_TYPES_H

#include <stddef.h>

#include "prw_brdf.h" /* prw_ggx_row */
#include "prw_constants.h"
#include "prw_math.h"
#include "prw_scene.h"

/* shaders/common.glsl: struct prw_gpu_light */
typedef struct prw_gpu_light {
    float pos_type[4];
    float dir_range[4];
    float radiance[4];
    float cone_shadow[4];
    float axis_u[4];
    float axis_v[4];
    float shadow[4];
} prw_gpu_light;

/* shaders/common.glsl: uniform prw_globals (set 0, binding 0) */
typedef struct prw_gpu_globals {
    prw_mat4 view_proj;
    float eye_rel[4];
    float params[4];
    prw_gpu_light lights[PRW_MAX_LIGHTS];
    prw_mat4 shadow_mats[PRW_MAX_SHADOW_VIEWS];
    float origin[4]; /* the frame's origin, world (gi_probe.glsl) */
} prw_gpu_globals;

/* shaders/material_gltf.glsl: uniform prw_material_block (set 1, binding 0); the shaders without
 * PRW_GLTF_EXT read the first four members and the ggx ones only. */
typedef struct prw_gpu_material {
    float base_color[4];
    float emission[4]; /* w: normal scale */
    float mr[4];       /* metallic, roughness, double sided, has normal map */
    float extra[4];    /* x: specular, y: material slot + 1 (G-buffer id) */
    float alpha[4];    /* x: alpha mode (PRW_GPU_ALPHA_*), y: cutoff */
    float coat[4];     /* x: clearcoat, y: clearcoat roughness, z: coat normal scale, w: has coat normal map */
    float xf[2 * PRW_GPU_SLOTS][4]; /* per slot: (offset u, v, cos r, sin r), (scale u, v, uv set, 0) */
    prw_ggx_row ggx_ec, ggx_ed; /* prw_ggx_Ec_row, prw_ggx_Ed_row of the factor roughness */
    float ggx_avg[4];           /* Ec_avg, Ed_avg, 0, 0 */
} prw_gpu_material;

/* std140: vec4 members 16-byte aligned, arrays of structs padded to 16, mat4 = 64 bytes */
_Static_assert(sizeof(prw_mat4) == 64, "mat4 is 64 bytes");
_Static_assert(PRW_SC_N_RECT_SHADOWED == PRW_SC_LIGHT_CLASS0 + PRW_LIGHT_CLASS_RECT_SHADOWED &&
                   PRW_SC_N_RECT == PRW_SC_LIGHT_CLASS0 + PRW_LIGHT_CLASS_RECT &&
                   PRW_SC_N_PUNCTUAL_SHADOWED == PRW_SC_LIGHT_CLASS0 + PRW_LIGHT_CLASS_PUNCTUAL_SHADOWED &&
                   PRW_SC_N_POINT_SHADOWED == PRW_SC_LIGHT_CLASS0 + PRW_LIGHT_CLASS_POINT_SHADOWED &&
                   PRW_SC_N_PUNCTUAL == PRW_SC_LIGHT_CLASS0 + PRW_LIGHT_CLASS_PUNCTUAL,
               "specialisation constants of the light classes");
_Static_assert(PRW_SC_SOFT_SHADOWS == PRW_SC_MAT + 1 && PRW_SC_TERMS == PRW_SC_SOFT_SHADOWS + 1,
               "the base shaders' specialisation constants follow each other (pipes.c checks the limit)");
_Static_assert(PRW_SC_MAT == PRW_SC_LIGHT_CLASS0 + PRW_LIGHT_CLASSES, "the material constant follows the light classes");
_Static_assert(PRW_GPU_MAT_MASK == (1 << PRW_GPU_MAT_BITS) - 1 && PRW_GPU_MAT_BITS + 6 <= 32,
               "PRW_GPU_MAT_* fit the pipeline features and slot flags");
_Static_assert(PRW_MAX_LIGHTS < 32 && 5 * PRW_LIGHT_CLASSES <= 32, "light class sizes fit 5 bits each (prw_pipe_key.light_classes)");
_Static_assert(sizeof(prw_gpu_light) == 7 * 16, "prw_gpu_light: 7 vec4");
_Static_assert(offsetof(prw_gpu_globals, eye_rel) == 64, "globals.eye_rel");
_Static_assert(offsetof(prw_gpu_globals, params) == 80, "globals.params");
_Static_assert(offsetof(prw_gpu_globals, lights) == 96, "globals.lights");
_Static_assert(offsetof(prw_gpu_globals, shadow_mats) == 96 + PRW_MAX_LIGHTS * 7 * 16, "globals.shadow_mats");
_Static_assert(sizeof(prw_gpu_globals) == 96 + PRW_MAX_LIGHTS * 7 * 16 + PRW_MAX_SHADOW_VIEWS * 64 + 16, "globals size");
_Static_assert(offsetof(prw_gpu_material, alpha) == 64, "material block: the core part is 4 vec4");
_Static_assert(sizeof(prw_gpu_material) == (6 + 2 * PRW_GPU_SLOTS + 9) * 16, "material block: 6 + 2 x slots + 9 vec4");
_Static_assert(offsetof(prw_gpu_material, ggx_ec) == (6 + 2 * PRW_GPU_SLOTS) * 16 &&
                   offsetof(prw_gpu_material, ggx_ed) == (10 + 2 * PRW_GPU_SLOTS) * 16 &&
                   offsetof(prw_gpu_material, ggx_avg) == (14 + 2 * PRW_GPU_SLOTS) * 16,
               "material block: the ggx rows after xf (std140: a struct of 16 floats is 64 bytes)");
_Static_assert(PRW_GPU_ALPHA_OPAQUE == PRW_ALPHA_OPAQUE && PRW_GPU_ALPHA_MASK == PRW_ALPHA_MASK &&
                   PRW_GPU_ALPHA_BLEND == PRW_ALPHA_BLEND,
               "alpha modes: shaders/prw_constants.h and prw_alpha_mode agree");
_Static_assert(PRW_GPU_SLOTS == PRW_TEX_SLOT_COUNT && PRW_GPU_SLOT_BASE == PRW_TEX_BASE_COLOR &&
                   PRW_GPU_SLOT_METAL_ROUGH == PRW_TEX_METAL_ROUGH && PRW_GPU_SLOT_NORMAL == PRW_TEX_NORMAL &&
                   PRW_GPU_SLOT_EMISSIVE == PRW_TEX_EMISSIVE && PRW_GPU_SLOT_CLEARCOAT == PRW_TEX_CLEARCOAT &&
                   PRW_GPU_SLOT_CLEARCOAT_ROUGHNESS == PRW_TEX_CLEARCOAT_ROUGHNESS &&
                   PRW_GPU_SLOT_CLEARCOAT_NORMAL == PRW_TEX_CLEARCOAT_NORMAL,
               "texture slots: shaders/prw_constants.h and prw_tex_slot agree");
_Static_assert(PRW_GPU_LIGHT_POINT == PRW_LIGHT_POINT && PRW_GPU_LIGHT_SPOT == PRW_LIGHT_SPOT &&
                   PRW_GPU_LIGHT_DIRECTIONAL == PRW_LIGHT_DIRECTIONAL && PRW_GPU_LIGHT_RECT == PRW_LIGHT_RECT,
               "light types: shaders/prw_constants.h and prw_light_type agree");
_Static_assert(PRW_VERTEX_FLOATS == 12, "vertex layout: position, normal, uv, tangent");

#endif
