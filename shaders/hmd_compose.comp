#version 450
// HMD panel composition (issue 5): side-by-side eye images -> one panel image, either plain
// side-by-side (debug view) or with barrel pre-distortion and per-channel chromatic-aberration
// pre-correction.  Mirrors prw_compose_source / prw_compose_sample (engine/view/hmd.c) in float:
// bilinear with pixel centres at +0.5, clamped to the edge inside the eye image, 0 outside.
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0) uniform sampler2D eye_img[2];
layout(set = 0, binding = 1, rgba32f) uniform writeonly image2D dst;
layout(push_constant) uniform prw_compose_pc {
    ivec4 size;   // mode (0 side-by-side, 1 hmd), out_w, out_h, eye_w
    ivec4 size2;  // eye_h, -, -, -
    vec4 screen;  // screen_w, screen_h, lens_unit, eye_to_screen
    vec4 k;       // k1..k4
    vec4 ca;      // red: ca0 + ca1 r^2; blue: ca2 + ca3 r^2
    vec4 tan0;    // left eye: left, right, bottom, top
    vec4 tan1;    // right eye
    vec4 lens_x;  // lens centres (metres from the panel centre), -, -
} pc;

float sample_eye(int eye, int c, vec2 uv)
{
    int w = pc.size.w, h = pc.size2.x;
    if (!(uv.x >= 0.0 && uv.y >= 0.0 && uv.x <= float(w) && uv.y <= float(h))) return 0.0;
    vec2 xy = uv - 0.5;
    vec2 f0 = floor(xy);
    vec2 f = xy - f0;
    ivec2 p0 = clamp(ivec2(f0), ivec2(0), ivec2(w - 1, h - 1));
    ivec2 p1 = clamp(ivec2(f0) + 1, ivec2(0), ivec2(w - 1, h - 1));
    float a, b, cc, d;
    if (eye == 0) {
        a = texelFetch(eye_img[0], ivec2(p0.x, p0.y), 0)[c];
        b = texelFetch(eye_img[0], ivec2(p1.x, p0.y), 0)[c];
        cc = texelFetch(eye_img[0], ivec2(p0.x, p1.y), 0)[c];
        d = texelFetch(eye_img[0], ivec2(p1.x, p1.y), 0)[c];
    } else {
        a = texelFetch(eye_img[1], ivec2(p0.x, p0.y), 0)[c];
        b = texelFetch(eye_img[1], ivec2(p1.x, p0.y), 0)[c];
        cc = texelFetch(eye_img[1], ivec2(p0.x, p1.y), 0)[c];
        d = texelFetch(eye_img[1], ivec2(p1.x, p1.y), 0)[c];
    }
    return (a * (1.0 - f.x) + b * f.x) * (1.0 - f.y) + (cc * (1.0 - f.x) + d * f.x) * f.y;
}

void main()
{
    ivec2 ij = ivec2(gl_GlobalInvocationID.xy);
    int out_w = pc.size.y, out_h = pc.size.z, eye_w = pc.size.w, eye_h = pc.size2.x;
    if (ij.x >= out_w || ij.y >= out_h) return;
    int half_w = out_w / 2;
    int eye = ij.x >= half_w ? 1 : 0;
    float x = float(ij.x - (eye == 1 ? half_w : 0)) + 0.5, y = float(ij.y) + 0.5;
    vec3 rgb;
    if (pc.size.x == 0) {
        vec2 uv = vec2(x / float(half_w) * float(eye_w), y / float(out_h) * float(eye_h));
        for (int c = 0; c < 3; c++) rgb[c] = sample_eye(eye, c, uv);
    } else {
        float X = (float(ij.x) + 0.5) / float(out_w) * pc.screen.x - 0.5 * pc.screen.x;
        float Y = 0.5 * pc.screen.y - y / float(out_h) * pc.screen.y;
        vec2 p = vec2((X - pc.lens_x[eye]) / pc.screen.z, Y / pc.screen.z);
        float r2 = dot(p, p);
        float dd = 1.0 + r2 * (pc.k.x + r2 * (pc.k.y + r2 * (pc.k.z + r2 * pc.k.w)));
        vec4 t = eye == 0 ? pc.tan0 : pc.tan1;
        for (int c = 0; c < 3; c++) {
            float s = c == 0 ? pc.ca.x + pc.ca.y * r2 : (c == 2 ? pc.ca.z + pc.ca.w * r2 : 1.0);
            vec2 tt = p * (dd * s * pc.screen.z / pc.screen.w);
            vec2 uv = vec2((tt.x - t.x) / (t.y - t.x) * float(eye_w), (t.w - tt.y) / (t.w - t.z) * float(eye_h));
            rgb[c] = sample_eye(eye, c, uv);
        }
    }
    imageStore(dst, ij, vec4(rgb, 1.0));
}
