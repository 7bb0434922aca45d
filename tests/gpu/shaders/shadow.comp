#version 450
// Compares reference depths against a depth image through the shadow sampler.
layout(local_size_x = 1) in;
layout(set = 0, binding = 0) uniform sampler2DShadow shadow;
layout(std430, set = 0, binding = 1) writeonly buffer Out { float v[]; };
void main()
{
    v[0] = texture(shadow, vec3(0.5, 0.5, 0.1));  // farther than the stored 0.25: shadowed
    v[1] = texture(shadow, vec3(0.5, 0.5, 0.5));
    v[2] = texture(shadow, vec3(2.0, 2.0, 0.1));  // outside: border depth 0 (far)
    v[3] = texture(shadow, vec3(0.5, 0.5, 0.25)); // equal passes GREATER_OR_EQUAL
}
