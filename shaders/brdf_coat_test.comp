#version 450
#extension GL_GOOGLE_include_directive : require
#include "prw_brdf.h"
// Evaluates the coated model of the shared material header (prw_brdf_coated_channel) on the GPU for the
// CPU-vs-GPU equality test.
layout(local_size_x = 64) in;
struct prw_coat_case { float NoV, NoL, NoH, VoH, NcV, NcL, NcH, base, metallic, roughness, specular, clearcoat, rc; };
layout(std430, set = 0, binding = 0) readonly buffer In { prw_coat_case cases[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Out { float results[]; };
layout(push_constant) uniform PC { uint count; } pc;
void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    prw_coat_case c = cases[i];
    results[i] = prw_brdf_coated_channel(c.NoV, c.NoL, c.NoH, c.VoH, c.NcV, c.NcL, c.NcH, c.base, c.metallic,
                                         c.roughness, c.specular, c.clearcoat, c.rc);
}
