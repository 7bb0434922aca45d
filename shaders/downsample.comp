#version 450
// N x N supersampling for stills: each output pixel is the box-filtered mean of its N x N
// internal pixels, in linear HDR (the pixel-square box filter of DESIGN.md §5).
layout(local_size_x = 8, local_size_y = 8) in;
// The radiance images are half or float32 (knob radiance_bits): PRW_RGBA32F selects the format qualifier.
#ifdef PRW_RGBA32F
layout(set = 0, binding = 0, rgba32f) uniform readonly image2D src;
layout(set = 0, binding = 1, rgba32f) uniform writeonly image2D dst;
#else
layout(set = 0, binding = 0, rgba16f) uniform readonly image2D src;
layout(set = 0, binding = 1, rgba16f) uniform writeonly image2D dst;
#endif
layout(push_constant) uniform prw_downsample_pc {
    uint factor;
    uint width, height; // output size
} pc;

void main()
{
    uvec2 p = gl_GlobalInvocationID.xy;
    if (p.x >= pc.width || p.y >= pc.height) return;
    vec4 sum = vec4(0.0);
    for (uint y = 0; y < pc.factor; y++)
        for (uint x = 0; x < pc.factor; x++)
            sum += imageLoad(src, ivec2(p * pc.factor + uvec2(x, y)));
    imageStore(dst, ivec2(p), sum / float(pc.factor * pc.factor));
}
