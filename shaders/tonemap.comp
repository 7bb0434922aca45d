#version 450
// Provisional tone map (issue 6 replaces it): photometric exposure, clamp, sRGB OETF.
// exposure = 1 / (1.2 * 2^EV100): the luminance 1.2 * 2^EV100 cd/m^2 maps to display white.
// Non-finite input is written as 0 so no NaN/Inf reaches the output.
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, rgba16f) uniform readonly image2D src;
layout(set = 0, binding = 1, rgba8) uniform writeonly image2D dst;
layout(push_constant) uniform prw_tonemap_pc {
    float exposure;
    uint width, height;
} pc;

float srgb_oetf(float x)
{
    return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055;
}

void main()
{
    uvec2 p = gl_GlobalInvocationID.xy;
    if (p.x >= pc.width || p.y >= pc.height) return;
    vec3 c = imageLoad(src, ivec2(p)).rgb * pc.exposure;
    vec3 o;
    for (int i = 0; i < 3; i++) {
        float x = c[i];
        o[i] = (isnan(x) || isinf(x)) ? 0.0 : srgb_oetf(clamp(x, 0.0, 1.0));
    }
    imageStore(dst, ivec2(p), vec4(o, 1.0));
}
