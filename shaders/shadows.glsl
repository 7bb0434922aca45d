// shadows.glsl — visibility of a light from the shadow atlas (pass_shadow.c, shadow_plan.h): the
// layer of the light (a point light's cube face by the major axis), a receiver offset along the normal
// (texels at the receiver's distance), fully dark when the occluder is more than a texel in front, else
// 3x3 PCF with reversed Z (lit where the receiver's depth is >= the stored occluder depth).  Needs common.glsl (the globals) declared before it.
#ifndef PRW_SHADOWS_GLSL
#define PRW_SHADOWS_GLSL

layout(set = 0, binding = 1) uniform sampler2DArrayShadow shadow_map;

// offset: the receiver's normal offset in texels (base.frag: 1.5).
float shadow_factor(prw_gpu_light L, vec3 p, vec3 n, float offset)
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
    vec3 po = p + n * (offset * texel);
    vec4 c = g.shadow_mats[layer] * vec4(po, 1.0);
    if (c.w <= 0.0) return 1.0;
    c.xyz /= c.w;
    vec2 uv = c.xy * 0.5 + 0.5;
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return 1.0;
    // Deep in the shadow: a point 1 texel nearer to the light on the ray to it is still occluded at this
    // texel, so the occluder is well in front: no filtering.  Otherwise the PCF taps of a receiver at the
    // silhouette of closed geometry (an inside corner of a room seen from the sun) reach past it and
    // let light in, which at 1e15 lux is visible however small the weight.
    vec3 to_light = type == PRW_GPU_LIGHT_DIRECTIONAL ? -L.dir_range.xyz : normalize(L.pos_type.xyz - po);
    vec4 cd = g.shadow_mats[layer] * vec4(po + to_light * (1.0 * texel), 1.0);
    if (cd.w > 0.0 && texture(shadow_map, vec4(uv, float(layer), cd.z / cd.w)) == 0.0) return 0.0;
    // 3x3 PCF; reversed Z: lit where the receiver's depth >= the stored occluder depth.  When the
    // receiver's own texel is occluded, a tap past the outer silhouette of the scene (nothing stored:
    // the clear value 0) lights nothing: the receiver is at the rim of closed geometry, not in a
    // penumbra (ground and other receivers are in the map themselves, so this never applies to them).
    float inv = 1.0 / g.params.y;
    bool occluded = texture(shadow_map, vec4(uv, float(layer), c.z)) < 1.0;
    float sum = 0.0;
    for (int y = -1; y <= 1; y++)
        for (int x = -1; x <= 1; x++) {
            vec2 t = uv + vec2(x, y) * inv;
            float lit = texture(shadow_map, vec4(t, float(layer), c.z));
            if (occluded && lit > 0.0) lit *= 1.0 - texture(shadow_map, vec4(t, float(layer), 0.0));
            sum += lit;
        }
    return sum / 9.0;
}

#endif
