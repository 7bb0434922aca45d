#version 450
// Writes v[i] = i*i + add for i < n.
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) writeonly buffer Out { uint v[]; };
layout(push_constant) uniform Push { uint n; uint add; } pc;
void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i < pc.n) v[i] = i * i + pc.add;
}
