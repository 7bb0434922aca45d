#version 450
// The test passes' additive term: out += weight * f(in0, in1, in2) (tests/render/graph_passes).
//  mode 0: in0 (a texture of the pass, or another pass's image: the glossy term of a mirror image)
//  mode 1: in0 where in1 (a depth buffer) is 0, i.e. nothing was drawn (environment)
//  mode 2: |in0.xyz| (normals) * in1 depth > 0 * in2.r (an ISM atlas), a stand-in for an SSDO bounce
layout(set = 0, binding = 0) uniform sampler2D in0;
#ifdef TP_MS
layout(set = 0, binding = 1) uniform sampler2DMS in1;
#else
layout(set = 0, binding = 1) uniform sampler2D in1;
#endif
layout(set = 0, binding = 2) uniform sampler2D in2;
layout(push_constant) uniform tp_push {
    vec4 w;      // x: weight, zw: target size (pixels)
    ivec4 mode;  // x: mode
} pc;
layout(location = 0) out vec4 o;
void main()
{
    vec2 uv = gl_FragCoord.xy / pc.w.zw;
    vec4 a = texture(in0, uv);
#ifdef TP_MS
    float d = texelFetch(in1, ivec2(uv * vec2(textureSize(in1))), 0).r;
#else
    float d = texture(in1, uv).r;
#endif
    float c = texture(in2, uv).r;
    vec3 v = a.rgb;
    if (pc.mode.x == 1) v = d > 0.0 ? vec3(0.0) : a.rgb;
    else if (pc.mode.x == 2) v = abs(a.xyz) * (d > 0.0 ? 1.0 : 0.0) * (0.5 + c);
    o = vec4(pc.w.x * v, 0.0);
}
