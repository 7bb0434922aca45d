#version 450
// Selective tone mapping, step 1 (pass_tonemap.c "tm_stats" for the selective operator): the
// statistics pass fused with the Sobel classification -- each 16 x 16 block's largest gradient of
// log10(delta + Y) (tonemap_stats.glsl); tonemap_compact.comp marks the tiles whose largest block
// gradient exceeds the threshold.  Mirror of prw_tm_stats_image + prw_tm_classify (tonemap_ops.c).
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 16, local_size_y = 16) in;
#include "tonemap_common.glsl"
#define TM_CLASSIFY 1
#include "tonemap_stats.glsl"
