#version 450
// A full-view triangle at the far plane: the sky where no geometry was drawn.
void main() {
    vec2 p = vec2(float((gl_VertexIndex << 1) & 2), float(gl_VertexIndex & 2));
    gl_Position = vec4(p * 2.0 - 1.0, 1.0, 1.0);
}
