#version 450
// Samples a texture into v[slot*4 .. slot*4+3]: texel (3,2) of mip 0, then (when the view has
// 4 mips) texel (0,0) of mip 1, and the centre of mips 2 and 3 with linear filtering.
layout(local_size_x = 1) in;
layout(set = 0, binding = 0) uniform sampler2D tex;
layout(std430, set = 0, binding = 1) writeonly buffer Out { vec4 v[]; };
layout(push_constant) uniform Push { uint slot; uint mips; } pc;
void main()
{
    uint o = pc.slot * 4u;
    v[o + 0u] = texelFetch(tex, ivec2(3, 2), 0);
    if (pc.mips >= 4u) {
        v[o + 1u] = texelFetch(tex, ivec2(0, 0), 1);
        v[o + 2u] = textureLod(tex, vec2(0.5), 2.0);
        v[o + 3u] = textureLod(tex, vec2(0.5), 3.0);
    }
}
