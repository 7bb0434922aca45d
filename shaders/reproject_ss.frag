#version 450
#extension GL_GOOGLE_include_directive : require
// Reprojection with a single-sample left depth (msaa 1): see reproject.glsl.
#include "reproject.glsl"
