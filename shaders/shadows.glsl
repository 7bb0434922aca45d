// shadows.glsl — visibility of a light from the shadow atlas (pass_shadow.c, shadow_plan.h): the
// layer of the light (a point light's cube face by the major axis), a receiver offset along the normal
// (texels at the receiver's distance), fully dark when the occluder is more than a texel in front, else
// 3x3 PCF of bilinear compares with reversed Z (lit where the receiver's depth is >= the stored occluder
// depth), computed from gathered depths (binding 2) as a compare sampler would filter them; for rect
// lights, soft shadows with the quality knob soft_shadows (shadow_factor_soft, below).  Needs common.glsl
// (the globals) declared before it.
#ifndef PRW_SHADOWS_GLSL
#define PRW_SHADOWS_GLSL

layout(set = 0, binding = 1) uniform sampler2DArrayShadow shadow_map;
layout(set = 0, binding = 2) uniform sampler2DArray shadow_depth; // the same atlas: nearest, border depth 0

// The 4 x 4 texels around the bilinear footprint of uv in a size x size layer: rows r0..r3 are texel rows
// i0.y - 1 .. i0.y + 2, each over the columns i0.x - 1 .. i0.x + 2 (i0 = floor(uv size - 0.5): the
// footprint's lower-left texel, f its bilinear weights).  textureGather at the corner between texels
// k - 1 and k returns (x: (k-1, k), y: (k, k), z: (k, k-1), w: (k-1, k-1)) as (column, row).
void shadow_texels(vec2 uv, float layer, float size, out vec4 r0, out vec4 r1, out vec4 r2, out vec4 r3, out vec2 f)
{
    vec2 st = uv * size - 0.5;
    vec2 i0 = floor(st);
    f = st - i0;
    float inv = 1.0 / size;
    vec4 a = textureGather(shadow_depth, vec3(i0 * inv, layer));
    vec4 b = textureGather(shadow_depth, vec3((i0 + vec2(2.0, 0.0)) * inv, layer));
    vec4 c = textureGather(shadow_depth, vec3((i0 + vec2(0.0, 2.0)) * inv, layer));
    vec4 d = textureGather(shadow_depth, vec3((i0 + vec2(2.0, 2.0)) * inv, layer));
    r0 = vec4(a.w, a.z, b.w, b.z);
    r1 = vec4(a.x, a.y, b.x, b.y);
    r2 = vec4(c.w, c.z, d.w, d.z);
    r3 = vec4(c.x, c.y, d.x, d.y);
}

// One texel row's compare results (reversed Z: 1 where ref >= the stored depth, the compare sampler's
// GREATER_OR_EQUAL) lerped horizontally for the taps whose footprints start at columns 0, 1, 2.
vec3 shadow_row(float ref, vec4 r, float fx)
{
    vec4 m = vec4(greaterThanEqual(vec4(ref), r));
    return mix(m.xyz, m.yzw, fx);
}

// The bilinear compare of the centre tap (footprint rows 1, 2, columns 1, 2).
float shadow_centre_tap(float ref, vec4 r1, vec4 r2, vec2 f)
{
    vec2 m1 = vec2(greaterThanEqual(vec2(ref), r1.yz)), m2 = vec2(greaterThanEqual(vec2(ref), r2.yz));
    return mix(mix(m1.x, m1.y, f.x), mix(m2.x, m2.y, f.x), f.y);
}

// offset: the receiver's normal offset in texels (base.frag: 1.5).  may_be_cube: false (a constant at
// the call) for a light known to have one layer (rect, spot, directional: lights.glsl's classes), whose
// layer is then the same for every fragment: lavapipe then loads its matrices once instead of per
// fragment, and drops the face selection.
float shadow_factor(prw_gpu_light L, vec3 p, vec3 n, float offset, bool may_be_cube)
{
    int first = int(L.cone_shadow.z);
    if (first < 0) return 1.0;
    int layer = first;
    vec3 d = p - L.pos_type.xyz;
    if (may_be_cube && int(L.cone_shadow.w) == 6) {
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
    // The 4 x 4 texels under the ten bilinear taps below (the hardware PCF taps of a compare sampler, here
    // from four gathers and compares in the shader: on lavapipe each filtered lookup costs about as much
    // as a gather, and there were twenty).
    vec4 r0, r1, r2, r3;
    vec2 f;
    shadow_texels(uv, float(layer), g.params.y, r0, r1, r2, r3, f);
    // Deep in the shadow: a point 1 texel nearer to the light on the ray to it is still occluded at this
    // texel, so the occluder is well in front: no filtering.  Otherwise the PCF taps of a receiver at the
    // silhouette of closed geometry (an inside corner of a room seen from the sun) reach past it and
    // let light in, which at 1e15 lux is visible however small the weight.
    vec3 to_light = type == PRW_GPU_LIGHT_DIRECTIONAL ? -L.dir_range.xyz : normalize(L.pos_type.xyz - po);
    vec4 cd = g.shadow_mats[layer] * vec4(po + to_light * (1.0 * texel), 1.0);
    if (cd.w > 0.0 && shadow_centre_tap(cd.z / cd.w, r1, r2, f) == 0.0) return 0.0;
    // 3x3 PCF; reversed Z: lit where the receiver's depth >= the stored occluder depth.  When the
    // receiver's own texel is occluded, a tap past the outer silhouette of the scene (nothing stored:
    // the clear value 0) lights nothing: the receiver is at the rim of closed geometry, not in a
    // penumbra (ground and other receivers are in the map themselves, so this never applies to them).
    // h*: per texel row, the horizontal lerps of the compare results for the taps x = -1, 0, 1.
    vec3 h0 = shadow_row(c.z, r0, f.x), h1 = shadow_row(c.z, r1, f.x), h2 = shadow_row(c.z, r2, f.x),
         h3 = shadow_row(c.z, r3, f.x);
    vec3 lit_m = mix(h0, h1, f.y), lit_0 = mix(h1, h2, f.y), lit_p = mix(h2, h3, f.y); // tap rows y = -1, 0, 1
    bool occluded = lit_0.y < 1.0;
    if (occluded) {
        // the taps' share of stored texels (depth > 0, i.e. not "0 >= depth")
        vec3 e0 = shadow_row(0.0, r0, f.x), e1 = shadow_row(0.0, r1, f.x), e2 = shadow_row(0.0, r2, f.x),
             e3 = shadow_row(0.0, r3, f.x);
        lit_m *= vec3(1.0) - mix(e0, e1, f.y);
        lit_0 *= vec3(1.0) - mix(e1, e2, f.y);
        lit_p *= vec3(1.0) - mix(e2, e3, f.y);
    }
    vec3 rows = lit_m + lit_0 + lit_p;
    return (rows.x + rows.y + rows.z) / 9.0;
}

// Soft shadows of a rect light (the quality knob soft_shadows: N = prw_soft_shadows > 0, else 0).  The map
// is the one rendered from the rectangle's centre; with ndc depth d = near / z (reversed, infinite far), a
// point at depth d_i whose map position differs from the receiver's by duv lies between the receiver
// (depth d_r) and some point of the rectangle exactly when duv = J (s, t) (d_i - d_r) with |s|, |t| <= 1,
// J's columns being the light's half axes in uv per unit of depth difference (0.5 (M axis).xy / near):
// the map's view of the pyramid between the receiver and the light.  PCSS in those terms:
//  1. blocker search: N rings of N gathers over J [-1, 1]^2 D (D: blockers up to a quarter of the
//     receiver's distance, at most PRW_SOFT_SEARCH_UV wide), keeping the smallest depth difference k of
//     the texels inside the pyramid (so the receiver's own plane and the floor at a wall's foot, which
//     are not between it and the light, are not blockers);
//  2. filter: the rectangle's points (s, t) on an M x M grid (M = max(2, N - 1)), each at uv + J (s, t) k (where the ray to
//     (s, t) crosses the depth d_r + k: exact for a blocker plane parallel to the light), a bilinear
//     compare against d_r + k max(|s|, |t|): the texel counts when it is inside the pyramid.  k is the
//     blocker nearest the receiver, not the mean: the map holds a solid's face towards the light, while
//     the rays from the receiver cross it nearer to the receiver (on the demo's sphere the mean's wider
//     filter lost the umbra: direct-light FLIP 0.050 against 0.042 at N = 4).
// The footprint is at least PRW_SOFT_MIN_TEXELS texels a side (today's 3x3 PCF) so that contact shadows
// stay filtered.
layout(constant_id = PRW_SC_SOFT_SHADOWS) const int prw_soft_shadows = 0;
// search rings (and gathers per ring) and filter taps a side: the search decides the quality (on the demo
// N x N search gathers with (N - 1)^2 filter taps err as little as N x N of each)
const int prw_soft_search = prw_soft_shadows;
const int prw_soft_filter = prw_soft_shadows > 3 ? prw_soft_shadows - 1 : 2;
#define PRW_SOFT_SEARCH_UV 0.04
#define PRW_SOFT_MIN_TEXELS 1.5

float shadow_factor_soft(prw_gpu_light L, vec3 p, vec3 n, float offset)
{
    int layer = int(L.cone_shadow.z);
    if (layer < 0) return 1.0;
    vec3 d = p - L.pos_type.xyz;
    float texel = L.shadow.x * length(d);
    vec3 po = p + n * (offset * texel);
    mat4 M = g.shadow_mats[layer];
    vec4 c = M * vec4(po, 1.0);
    if (c.w <= 0.0) return 1.0;
    float near = c.z; // reversed infinite perspective: clip z is the near distance
    float dr = c.z / c.w;
    vec2 uv = c.xy / c.w * 0.5 + 0.5;
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return 1.0;
    float size = g.params.y, inv = 1.0 / size;
    vec2 ju = (M * vec4(L.axis_u.xyz, 0.0)).xy * (0.5 / near), jv = (M * vec4(L.axis_v.xyz, 0.0)).xy * (0.5 / near);
    float det = ju.x * jv.y - ju.y * jv.x;
    if (abs(det) < 1e-20) return shadow_factor(L, p, n, offset, false);
    mat2 Jinv = mat2(jv.y, -ju.y, -jv.x, ju.x) / det; // columns: J^-1 = (1/det) [jv.y -jv.x; -ju.y ju.x]
    vec2 ext = abs(ju) + abs(jv);                    // uv half-extent of J [-1, 1]^2
    float D = min(3.0 * dr, PRW_SOFT_SEARCH_UV / max(ext.x, ext.y));
    float step_n = 2.0 / float(prw_soft_filter);
    // 1. blocker search: N square rings (max(|s|, |t|) = r) of N gathers each, the radii geometric from
    // about PRW_SOFT_MIN_TEXELS texels to D (a near blocker is inside the pyramid only close to the
    // receiver's own texel), each ring turned by half a step against the previous one
    float k = 1e30; // the smallest depth difference of a blocker inside the pyramid
    float r0 = clamp(PRW_SOFT_MIN_TEXELS * inv / (max(ext.x, ext.y) * D), 0.02, 1.0);
    float grow = prw_soft_search > 1 ? pow(1.0 / r0, 1.0 / float(prw_soft_search - 1)) : 1.0;
    float r = prw_soft_search > 1 ? r0 : 1.0;
    // directions by rotation (the angles are constants after specialisation: no sin / cos per fragment)
    float a_step = 6.28318531 / float(prw_soft_search);
    mat2 rot = mat2(cos(a_step), sin(a_step), -sin(a_step), cos(a_step));
    mat2 half_rot = mat2(cos(0.5 * a_step), sin(0.5 * a_step), -sin(0.5 * a_step), cos(0.5 * a_step));
    vec2 ring_dir = vec2(0.70710678);
    vec2 sx = Jinv[0] * inv, sy = Jinv[1] * inv; // (s, t) per texel step in x and y
    for (int j = 0; j < prw_soft_search; j++, r *= grow, ring_dir = half_rot * ring_dir) {
        vec2 dir = ring_dir;
        for (int i = 0; i < prw_soft_search; i++, dir = rot * dir) {
            vec2 st = dir * (r / max(abs(dir.x), abs(dir.y)));
            vec2 gp = uv + (ju * st.x + jv * st.y) * D;
            vec2 i0 = floor(gp * size - 0.5);
            vec4 z4 = textureGather(shadow_depth, vec3((i0 + 1.0) * inv, float(layer)));
            // the gathered texels' centres relative to uv: x (i0.x, i0.y + 1), y (+1, +1), z (+1, i0.y), w (i0)
            vec2 o = (i0 + 0.5) * inv - uv;
            vec2 s0 = Jinv * o;
            vec4 mx = vec4(max(abs(s0 + sy).x, abs(s0 + sy).y), max(abs(s0 + sx + sy).x, abs(s0 + sx + sy).y),
                           max(abs(s0 + sx).x, abs(s0 + sx).y), max(abs(s0).x, abs(s0).y));
            vec4 dz = z4 - vec4(dr);
            vec4 inside = vec4(greaterThan(dz, mx)) * vec4(greaterThan(dz, vec4(0.0)));
            vec4 dzi = mix(vec4(1e30), dz, inside);
            k = min(k, min(min(dzi.x, dzi.y), min(dzi.z, dzi.w)));
        }
    }
    bool blocked = k < 1e30;
    // 2. filter over the rectangle's points
    float kf = max(k, PRW_SOFT_MIN_TEXELS * inv / max(ext.x, ext.y));
    float lit = 0.0;
    // a loop bound that is 0 for fully lit fragments: lavapipe runs a loop while any fragment of the
    // SIMD group is still in it, so groups without blockers skip the filter (a branch would not)
    int rows = blocked ? prw_soft_filter : 0;
    for (int j = 0; j < rows; j++)
        for (int i = 0; i < prw_soft_filter; i++) {
            vec2 st = vec2(float(i) + 0.5, float(j) + 0.5) * step_n - 1.0;
            vec2 tp = uv + (ju * st.x + jv * st.y) * kf;
            lit += texture(shadow_map, vec4(tp, float(layer), dr + kf * max(abs(st.x), abs(st.y))));
        }
    return blocked ? lit / float(prw_soft_filter * prw_soft_filter) : 1.0;
}

// A rect light's visibility: soft when the knob is on (a specialisation constant: the other branch is
// compiled out), else the hard lookup.
float shadow_factor_rect(prw_gpu_light L, vec3 p, vec3 n, float offset)
{
    return prw_soft_shadows > 0 ? shadow_factor_soft(L, p, n, offset) : shadow_factor(L, p, n, offset, false);
}

#endif
