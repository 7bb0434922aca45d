#version 450
// Depth-only pass into one layer of the shadow-map array (reversed Z) for cut-out casters: the uvs the
// alpha test of mask.frag needs (uv set 1 at location 4, as base.vert with PRW_GLTF_EXT).
layout(location = 0) in vec3 in_pos;
layout(location = 2) in vec2 in_uv;
layout(location = 4) in vec2 in_uv1;
layout(push_constant) uniform prw_shadow_draw {
    mat4 mvp; // object -> light clip
} pc;
layout(location = 2) out vec2 v_uv;
layout(location = 4) out vec2 v_uv1;
void main()
{
    v_uv = in_uv;
    v_uv1 = in_uv1;
    gl_Position = pc.mvp * vec4(in_pos, 1.0);
}
