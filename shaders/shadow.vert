#version 450
// Depth-only pass into one layer of the shadow-map array (reversed Z).
layout(location = 0) in vec3 in_pos;
layout(push_constant) uniform prw_shadow_draw {
    mat4 mvp; // object -> light clip
} pc;
void main() { gl_Position = pc.mvp * vec4(in_pos, 1.0); }
