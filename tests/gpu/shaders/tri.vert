#version 450
// One triangle covering the top-left half of the target: its long edge is the anti-diagonal,
// which passes through the centres of the diagonal pixels (half of their samples covered).
void main()
{
    const vec2 p[3] = vec2[](vec2(-1.0, -1.0), vec2(1.0, -1.0), vec2(-1.0, 1.0));
    gl_Position = vec4(p[gl_VertexIndex], 0.5, 1.0);
}
