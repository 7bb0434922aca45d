#version 450
#extension GL_GOOGLE_include_directive : require
// Reprojection with a 4x MSAA left depth: see reproject.glsl.
#define PRW_REPROJECT_MS
#include "reproject.glsl"
