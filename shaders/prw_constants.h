/* prw_constants.h — constants shared by the shaders (GLSL) and the C code that fills their inputs.
 * Only #defines of integer literals: the file is included by GLSL 4.50 and C17 alike.  The C mirrors
 * of the uniform blocks (engine/render/gpu_types.h) check their std140 layout with _Static_assert
 * against these numbers, and the light types against prw_light_type (engine/scene/prw_scene.h). */
#ifndef PRW_CONSTANTS_H
#define PRW_CONSTANTS_H

#define PRW_MAX_LIGHTS 16       /* lights in the per-view globals block */
#define PRW_MAX_SHADOW_VIEWS 32 /* layers of the shadow atlas (a point light takes 6) */

#define PRW_GPU_LIGHT_POINT 0
#define PRW_GPU_LIGHT_SPOT 1
#define PRW_GPU_LIGHT_DIRECTIONAL 2
#define PRW_GPU_LIGHT_RECT 3

/* Shading classes of the lights in the globals block, in slot order (engine/render/shadow_plan.h); the
 * base fragment shaders' specialisation constants: PRW_SC_LIGHTS_SORTED (bool: the slots are grouped)
 * and PRW_SC_LIGHT_CLASS0 + class (int: the group's size). */
#define PRW_LIGHT_CLASS_RECT_SHADOWED 0
#define PRW_LIGHT_CLASS_RECT 1
#define PRW_LIGHT_CLASS_PUNCTUAL_SHADOWED 2 /* spot, directional: one shadow layer */
#define PRW_LIGHT_CLASS_POINT_SHADOWED 3    /* point: six layers, a cube face per fragment */
#define PRW_LIGHT_CLASS_PUNCTUAL 4
#define PRW_LIGHT_CLASSES 5
#define PRW_SC_LIGHTS_SORTED 0
#define PRW_SC_LIGHT_CLASS0 1
#define PRW_SC_N_RECT_SHADOWED 1 /* = PRW_SC_LIGHT_CLASS0 + PRW_LIGHT_CLASS_RECT_SHADOWED, and so on */
#define PRW_SC_N_RECT 2
#define PRW_SC_N_PUNCTUAL_SHADOWED 3
#define PRW_SC_N_POINT_SHADOWED 4
#define PRW_SC_N_PUNCTUAL 5
/* The base fragment shaders' material specialisation (int, PRW_GPU_MAT_* bits): what the material slot
 * does not have, so the shader neither fetches the fallback texture, nor computes what the CPU has put
 * into the material block, nor evaluates lobes of weight 0 (material_gltf.glsl).  0: everything from
 * the textures and the shader. */
#define PRW_SC_MAT 6
/* The base fragment shaders' soft-shadow specialisation (int, the quality knob soft_shadows): 0 = the rect
 * lights' hard shadow, N = their soft shadow with N x N search and filter taps (shadows.glsl). */
#define PRW_SC_SOFT_SHADOWS 7
/* The base fragment shaders' terms (int, PRW_TERM_* bits; gi_lightmap.glsl, engine/render/prw_lightmap.h):
 * PRW_TERM_ALL draws what the shaders drew before the light maps; the others are for term-by-term tests. */
#define PRW_SC_TERMS 8
#define PRW_TERM_DIRECT 1           /* emission + direct light */
#define PRW_TERM_INDIRECT_DIFFUSE 2 /* the light maps' indirect diffuse (PRW_GI variants only) */
#define PRW_TERM_ENVIRONMENT 4      /* the environment light seen by one bounce (gi_env.glsl, with PRW_SC_ENV) */
#define PRW_TERM_PROBES 8           /* the reflection probes' indirect glossy (gi_probe.glsl, with PRW_SC_PROBES) */
#define PRW_TERM_INDIRECT_GLOSSY 16 /* the light maps' E_ind through the dielectric specular lobe of rough, unprobed
                                       surfaces (gi_lightmap.glsl, PRW_GI variants only) */
#define PRW_TERM_ALL 31
/* The base fragment shaders' environment term (int, 0/1; gi_env.glsl, engine/render/prw_env_gpu.h): 1 when
 * the renderer has an environment.  Unset (0): the shaders of before. */
#define PRW_SC_ENV 9
/* The base fragment shaders' reflection probes (int, 0/1; gi_probe.glsl, engine/render/prw_probe_gpu.h): 1 when
 * the renderer has probes.  Unset (0): the shaders of before. */
#define PRW_SC_PROBES 10
#define PRW_GPU_MAX_PROBES 8
#define PRW_GPU_MAT_NO_BASE_TEX 1     /* the base colour is the factor (white fallback texture) */
#define PRW_GPU_MAT_NO_MR_TEX 2       /* metallic and roughness are the factors; the block's ggx rows are theirs */
#define PRW_GPU_MAT_NO_NORMAL_TEX 4   /* no normal map */
#define PRW_GPU_MAT_NO_EMISSIVE_TEX 8 /* the emission is the factor */
#define PRW_GPU_MAT_NO_METAL 16       /* metallic is 0 (factor 0): the metal lobes drop out */
#define PRW_GPU_MAT_ALL_METAL 32      /* metallic is 1 (factor 1, no texture): the dielectric and diffuse lobes drop out */
#define PRW_GPU_MAT_PROBE 64       /* not a lack: the slot's material has a reflection probe (gi_probe.glsl; set by the
                                      renderer only when it has probes, so other scenes keep their pipelines) */
#define PRW_GPU_MAT_BITS 7
#define PRW_GPU_MAT_MASK 127 /* all PRW_GPU_MAT_* bits */

/* Vertex layout of every drawable: position 3, normal 3, uv 2, tangent 4 (xyz, w = handedness). */
#define PRW_VERTEX_FLOATS 12
/* The glTF-extension pipelines (PRW_GLTF_EXT) read uv set 1 at location 4: from a second stream of 2
 * floats per vertex (binding 1, the scene's meshes), or from binding 0's uv (drawables without uv set 1). */
#define PRW_UV1_FLOATS 2

/* glTF material features on the GPU (shaders/material_gltf.glsl with PRW_GLTF_EXT): alpha modes as
 * prw_alpha_mode, texture slots as prw_tex_slot (engine/scene/prw_scene.h; checked in gpu_types.h). */
#define PRW_GPU_ALPHA_OPAQUE 0
#define PRW_GPU_ALPHA_MASK 1
#define PRW_GPU_ALPHA_BLEND 2
#define PRW_GPU_SLOT_BASE 0
#define PRW_GPU_SLOT_METAL_ROUGH 1
#define PRW_GPU_SLOT_NORMAL 2
#define PRW_GPU_SLOT_EMISSIVE 3
#define PRW_GPU_SLOT_CLEARCOAT 4
#define PRW_GPU_SLOT_CLEARCOAT_ROUGHNESS 5
#define PRW_GPU_SLOT_CLEARCOAT_NORMAL 6
#define PRW_GPU_SLOTS 7

/* Push constants of the base pass's draws, bytes: model (mat4) + normal matrix (3 x vec4); the clip-plane
 * variant (PRW_CLIP_PLANE) reads a vec4 plane right after them, pushed once per pass. */
#define PRW_DRAW_PUSH_BYTES 112
#define PRW_CLIP_PUSH_OFFSET 112
#define PRW_BASE_PUSH_BYTES 128

#endif
