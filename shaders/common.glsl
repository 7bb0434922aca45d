// Shared GLSL declarations: the per-view globals block and light records.  Their C mirrors are in
// engine/render/gpu_types.h (std140, checked there by _Static_assert); the constants are shared
// through prw_constants.h.
#ifndef PRW_COMMON_GLSL
#define PRW_COMMON_GLSL

#include "prw_constants.h"

struct prw_gpu_light {
    vec4 pos_type;     // xyz: camera-relative position, w: type (PRW_GPU_LIGHT_*)
    vec4 dir_range;    // xyz: unit emission direction (node -Z), w: range (0 = infinite)
    vec4 radiance;     // rgb: colour * intensity (cd | lux | cd/m^2), w: unused
    vec4 cone_shadow;  // x: cos inner, y: cos outer, z: first shadow layer (-1: none), w: shadow layer count
    vec4 axis_u;       // rect: xyz half-width axis (metres)
    vec4 axis_v;       // rect: xyz half-height axis (metres)
    vec4 shadow;       // x: world size of one shadow texel (directional) or per metre of distance (local)
};

layout(std140, set = 0, binding = 0) uniform prw_globals {
    mat4 view_proj;           // camera-relative world -> clip
    vec4 eye_rel;             // eye position in the camera-relative frame
    vec4 params;              // x: light count, y: shadow map size, z: 1 drops emission (mirror images), w: unused (0)
    prw_gpu_light lights[PRW_MAX_LIGHTS];
    mat4 shadow_mats[PRW_MAX_SHADOW_VIEWS]; // camera-relative world -> light clip
    vec4 origin;              // xyz: the camera-relative frame's origin in world coordinates (reflection probes)
} g;

#endif
