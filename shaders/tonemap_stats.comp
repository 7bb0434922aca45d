#version 450
// Tone-mapping statistics, stage 1 (pass_tonemap.c "tm_stats"): see tonemap_stats.glsl.
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 16, local_size_y = 16) in;
#include "tonemap_common.glsl"
#include "tonemap_stats.glsl"
