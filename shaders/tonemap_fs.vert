#version 450
// One triangle covering the viewport (the full-screen fragment passes of the tone-mapping stage).
void main()
{
    vec2 q = vec2(float((gl_VertexIndex << 1) & 2), float(gl_VertexIndex & 2));
    gl_Position = vec4(q * 2.0 - 1.0, 0.0, 1.0);
}
