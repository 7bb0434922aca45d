// One-eye reprojection (issue 5, engine/render/pass_reproject.c): drawn with base.vert over the right
// eye's depth pre-pass (depth test GREATER_OR_EQUAL, no depth write), so only the visible surface is
// written.  Each fragment moves its surface point (camera-relative to the right eye, v_pos) into the
// left eye and writes the left eye's colour (and stencil 1) when the left eye saw the same surface
// there; otherwise it is discarded and stays a hole (stencil 0) that the right eye's base pass shades.
#ifndef PRW_REPROJECT_GLSL
#define PRW_REPROJECT_GLSL

layout(location = 0) in vec3 v_pos;
layout(location = 0) out vec4 o_color;

layout(std140, set = 2, binding = 0) uniform prw_reproject_block {
    mat4 left_view_proj; // right-eye camera-relative world -> left clip
    vec4 params;         // x: relative depth tolerance (< 0: reject all), y, z: left image size (px),
                         // w: alpha of reused pixels (1; 0 marks them for tests)
} rp;
layout(set = 2, binding = 1) uniform sampler2D left_color; // resolved linear HDR
#ifdef PRW_REPROJECT_MS
layout(set = 2, binding = 2) uniform sampler2DMS left_depth;
#define PRW_SAMPLES 4
#else
layout(set = 2, binding = 2) uniform sampler2D left_depth;
#define PRW_SAMPLES 1
#endif

// Mean depth of texel q and the spread (largest - smallest) of its samples.
float left_texel_depth(ivec2 q, out float spread)
{
#ifdef PRW_REPROJECT_MS
    float lo = 1e30, hi = -1e30, sum = 0.0;
    for (int s = 0; s < PRW_SAMPLES; s++) {
        float d = texelFetch(left_depth, q, s).r;
        lo = min(lo, d);
        hi = max(hi, d);
        sum += d;
    }
    spread = hi - lo;
    return sum / float(PRW_SAMPLES);
#else
    spread = 0.0;
    return texelFetch(left_depth, q, 0).r;
#endif
}

float minmod(float a, float b) { return a * b <= 0.0 ? 0.0 : (abs(a) < abs(b) ? a : b); }

// True (and the left colour in col) when the left eye saw this fragment's surface.
bool prw_reproject(out vec3 col)
{
    col = vec3(0.0);
    vec4 c = rp.left_view_proj * vec4(v_pos, 1.0);
    if (!(c.w > 0.0)) return false;
    vec2 size = rp.params.yz;
    vec2 px = (c.xy / c.w * 0.5 + 0.5) * size; // continuous left pixel coordinates
    float d = c.z / c.w;                      // reversed Z: znear / z
    if (!(px.x >= 0.0 && px.y >= 0.0 && px.x < size.x && px.y < size.y) || !(d > 0.0)) return false;
    float tol = rp.params.x;
    ivec2 isz = ivec2(size), q = min(ivec2(px), isz - 1);
    float spread, unused;
    float d0 = left_texel_depth(q, spread);
    if (!(d0 > 0.0)) return false; // nothing drawn there in the left eye
    float dxm = left_texel_depth(ivec2(max(q.x - 1, 0), q.y), unused);
    float dxp = left_texel_depth(ivec2(min(q.x + 1, isz.x - 1), q.y), unused);
    float dym = left_texel_depth(ivec2(q.x, max(q.y - 1, 0)), unused);
    float dyp = left_texel_depth(ivec2(q.x, min(q.y + 1, isz.y - 1)), unused);
    float sx = minmod(dxp - d0, d0 - dxm), sy = minmod(dyp - d0, d0 - dym);
    // MSAA edge texel: its samples spread more than a plane with the neighbours' slope would give
    // (the 4x sample positions span 0.75 px in x and y; 1 px allowed).  On a depth edge the minmod
    // slope is at most half the jump across it, so such a texel is normally rejected.
    if (!(spread <= tol * d0 + abs(sx) + abs(sy))) return false;
    vec2 off = px - (vec2(q) + 0.5);
    float dl = d0 + sx * off.x + sy * off.y;
    if (!(abs(dl - d) <= tol * d)) return false;
    col = texelFetch(left_color, q, 0).rgb;
    return true;
}

void main()
{
    vec3 col;
    if (!prw_reproject(col)) discard;
    o_color = vec4(col, rp.params.w);
}
#endif
