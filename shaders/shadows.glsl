// shadows.glsl — visibility of a light from the shadow atlas (pass_shadow.c, shadow_plan.h): the
// layer of the light (a point light's cube face by the major axis), a receiver offset along the normal
// of 1.5 texels at the receiver's distance, 3x3 PCF with reversed Z (lit where the receiver's depth is
// >= the stored occluder depth).  Needs common.glsl (the globals) declared before it.
#ifndef PRW_SHADOWS_GLSL
#define PRW_SHADOWS_GLSL

layout(set = 0, binding = 1) uniform sampler2DArrayShadow shadow_map;

float shadow_factor(prw_gpu_light L, vec3 p, vec3 n)
{
    int first = int(L.cone_shadow.z);
    if (first < 0) return 1.0;
    int layer = first;
    vec3 d = p - L.pos_type.xyz;
    if (int(L.cone_shadow.w) == 6) {
        vec3 a = abs(d);
        if (a.x >= a.y && a.x >= a.z) layer += d.x > 0.0 ? 0 : 1;
        else if (a.y >= a.z) layer += d.y > 0.0 ? 2 : 3;
        else layer += d.z > 0.0 ? 4 : 5;
    }
    int type = int(L.pos_type.w);
    float texel = L.shadow.x * (type == PRW_GPU_LIGHT_DIRECTIONAL ? 1.0 : length(d));
    vec3 po = p + n * (1.5 * texel);
    vec4 c = g.shadow_mats[layer] * vec4(po, 1.0);
    if (c.w <= 0.0) return 1.0;
    c.xyz /= c.w;
    vec2 uv = c.xy * 0.5 + 0.5;
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return 1.0;
    // 3x3 PCF; reversed Z: lit where the receiver's depth >= the stored occluder depth.
    float inv = 1.0 / g.params.y;
    float sum = 0.0;
    for (int y = -1; y <= 1; y++)
        for (int x = -1; x <= 1; x++)
            sum += texture(shadow_map, vec4(uv + vec2(x, y) * inv, float(layer), c.z));
    return sum / 9.0;
}

#endif
