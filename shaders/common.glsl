// Shared GLSL declarations: the per-view globals block and light records, mirrored by
// engine/render/render_types.h (std140).  Keep both in step.
#ifndef PRW_COMMON_GLSL
#define PRW_COMMON_GLSL

#define PRW_MAX_LIGHTS 16
#define PRW_MAX_SHADOW_VIEWS 32

#define PRW_LIGHT_POINT 0
#define PRW_LIGHT_SPOT 1
#define PRW_LIGHT_DIRECTIONAL 2
#define PRW_LIGHT_RECT 3

struct prw_gpu_light {
    vec4 pos_type;     // xyz: camera-relative position, w: type
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
    vec4 params;              // x: light count, y: shadow map size, z: shadow normal offset (m/texel), w: -
    prw_gpu_light lights[PRW_MAX_LIGHTS];
    mat4 shadow_mats[PRW_MAX_SHADOW_VIEWS]; // camera-relative world -> light clip
} g;

#endif
