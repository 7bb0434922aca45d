#version 450

// Glossy planar reflector, the convolution (engine/render/pass_mirror.c, pass mirror_glossy): on the
// reduced grid (the view's times mirror_scale x glossy_scale), the mirror image convolved by the reflected
// GGX lobe (DESIGN.md §4); mirror_add.frag reads the result bilinearly at the view's pixels and weights
// it by the split-sum reflectance.  A half vector tilted by theta_h moves the reflected ray by
// ~2 theta_h, so the reflected point (z_r behind the reflection point along the ray, d_m its depth in
// the mirror image) moves by r = 2 z_r tan(theta_h), r f_px / d_m view pixels.  The taps draw
// tan(theta_h) from D_GGX cos (tan^2 = alpha^2 u / (1 - u)), u stratified over [0, 0.995): the cone
// holding 99.5 % of the lobe (tan = 14 alpha; DESIGN's 90 % cone, tan(beta) = 3 alpha, cuts GGX's long
// tail, which the reference shows), golden-angle azimuths (rotated per texel), the axis across the
// plane of incidence shortened by mu = n.v, equal weights, summed in float.  The reflector is planar
// (no normal texture): n is its plane's normal.  Texels whose bilinear reach holds none of the
// reflector's view pixels (G-buffer id) write 0 and skip the taps.

layout(set = 0, binding = 0) uniform sampler2D u_mirror;  // the mirrored view's radiance: its top-left part on this grid
layout(set = 0, binding = 1) uniform sampler2D u_mdepth;  // the mirrored view's depth (reversed infinite Z), the same
layout(set = 0, binding = 2) uniform usampler2D u_id;     // G-buffer of the view: material slot + 1

layout(push_constant) uniform prw_glossy_push {
    mat4 inv_view_proj; // clip -> camera-relative world of the real view
    vec4 plane;         // xyz: the reflector's unit normal, w: its material id (slot + 1)
    vec4 glossy;        // x: alpha, y: eye's distance to the plane, z: f_px (view pixels per unit tangent), w: taps
    vec4 fwd;           // xyz: unit view axis, w: near plane distance
    vec4 size;          // xy: the view's size in pixels, zw: this image's (the mirror image's part it covers)
} pc;

layout(location = 0) out vec4 o_color;

// camera-relative direction (unnormalised) of the ray through view pixel position xy
vec3 ray_dir(vec2 xy)
{
    vec4 q = pc.inv_view_proj * vec4(xy / pc.size.xy * 2.0 - 1.0, 1.0, 1.0);
    return q.xyz / q.w;
}

vec3 finite_or_zero(vec3 L) { return (any(isnan(L)) || any(isinf(L))) ? vec3(0.0) : L; }

void main()
{
    vec2 s = pc.size.xy / pc.size.zw;  // view pixels per texel
    vec2 xy = gl_FragCoord.xy * s;     // this texel's centre in view pixels
    // mask: a view pixel reads the texels within one texel of it (bilinear), so this texel is needed when
    // a reflector pixel lies within s view pixels of its centre: one gather (2 x 2 pixels) every 2 view
    // pixels over that reach, ceil(s) per axis (2 x 2 gathers at s = 2, the default presets' product of
    // mirror_scale and glossy_scale; fewer would leave a dark fringe at the reflector's edge below it)
    uvec4 id = uvec4(uint(pc.plane.w));
    bool hit = false;
    ivec2 ng = clamp(ivec2(ceil(s - 1e-3)), ivec2(1), ivec2(16));
    for (int j = 0; j < ng.y && !hit; j++)
        for (int i = 0; i < ng.x && !hit; i++) {
            vec2 o = vec2(float(2 * i + 1 - ng.x), float(2 * j + 1 - ng.y)) * (s / vec2(ng));
            hit = any(equal(textureGather(u_id, (xy + o) / pc.size.xy), id));
        }
    if (!hit) {
        o_color = vec4(0.0);
        return;
    }
    vec3 n = pc.plane.xyz;
    vec3 d = ray_dir(xy);
    float ld = length(d);
    vec3 v = ld > 1e-20 ? -d / ld : vec3(0.0, 0.0, 1.0);
    float mu = clamp(abs(dot(n, v)), 0.0, 1.0);
    float mdepth = texelFetch(u_mdepth, ivec2(gl_FragCoord.xy), 0).r;
    float cphi = max(dot(v, -pc.fwd.xyz), 1e-4);                 // ray against the view axis
    float ts = pc.glossy.y / max(mu, 1e-4);                      // eye to the reflection point
    float dm = mdepth > 0.0 ? pc.fwd.w / mdepth : 1e30;          // depth in the mirror image
    float zr = max(dm / cphi - ts, 0.0);
    float k = 2.0 * zr * pc.glossy.z / dm;                       // view pixels per unit tan(theta_h)
    float rmax = 0.25 * pc.size.y;
    int taps = max(int(pc.glossy.w), 1);
    // anisotropy: a half-vector tilt eps in the plane of incidence turns the reflected ray by 2 eps, one
    // across it by 2 eps mu; on screen the plane of incidence is the line through this point where the
    // rays stay in it (ray . b = 0, b its normal): g = grad(ray . b)
    vec3 b = cross(n, v);
    float lb = length(b);
    vec2 s_in = vec2(0.0, 1.0), s_across = vec2(1.0, 0.0);
    if (lb > 1e-6) {
        b /= lb;
        vec2 g = vec2(dot(normalize(ray_dir(xy + vec2(1.0, 0.0))), b), dot(normalize(ray_dir(xy + vec2(0.0, 1.0))), b));
        float lg = length(g);
        if (lg > 1e-12) s_across = g / lg, s_in = vec2(-s_across.y, s_across.x);
    }
    // view pixels -> the mirror image's texture coordinates, kept inside the part rendered
    vec2 to_tex = pc.size.zw / pc.size.xy, tex_max = pc.size.zw - 0.5, inv_msize = 1.0 / vec2(textureSize(u_mirror, 0));
    float rot = fract(52.9829189 * fract(dot(gl_FragCoord.xy, vec2(0.06711056, 0.00583715)))) * 6.2831853;
    vec3 sum = vec3(0.0);
    for (int i = 0; i < taps; i++) {
        float u = 0.995 * (float(i) + 0.5) / float(taps);
        float r = min(k * pc.glossy.x * sqrt(u / (1.0 - u)), rmax);
        float a = rot + 2.39996323 * float(i);
        vec2 q = clamp((xy + r * (cos(a) * s_in + mu * sin(a) * s_across)) * to_tex, vec2(0.5), tex_max) * inv_msize;
        sum += finite_or_zero(textureLod(u_mirror, q, 0.0).rgb);
    }
    o_color = vec4(sum / float(taps), 1.0);
}
