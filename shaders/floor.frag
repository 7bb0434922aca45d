#version 450
// The floor of the base pass (engine/render/pass_floor.c): a constant colour, no inputs, no
// descriptors, so that its time is what the base pass costs without any shading: the same render
// pass, attachments, pipeline state, vertex shader and draws.  PRW_GBUFFER: the G-buffer outputs too.
layout(location = 0) out vec4 o_color;
#ifdef PRW_GBUFFER
layout(location = 1) out vec4 o_normal;
layout(location = 2) out uint o_id;
#endif

void main()
{
    o_color = vec4(0.18, 0.18, 0.18, 1.0);
#ifdef PRW_GBUFFER
    o_normal = vec4(0.0, 0.0, 1.0, 1.0);
    o_id = 1u;
#endif
}
