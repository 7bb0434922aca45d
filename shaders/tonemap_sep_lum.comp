#version 450
// Separable local tone mapping, step 1: scaled luminance L = key / log-average * Y into layer 0.
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 16, local_size_y = 16) in;
#include "tonemap_common.glsl"
#include "tonemap_sep.glsl"

void main()
{
    ivec2 p = sep_pixel(4);
    if (p.x >= int(pc.width) || p.y >= int(pc.height)) return;
    float scale = P.op1.y / max(tm_log_avg(), LOG_DELTA);
    imageStore(scratch, ivec3(p, 0), vec4(scale * lum3(san3(texelFetch(src, p, 0).rgb))));
}
