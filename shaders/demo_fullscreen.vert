#version 450
// One triangle covering the view at depth 0 (reverse-Z: infinitely far), for the sky and the
// test targets.
void main() {
    vec2 p = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);
    gl_Position = vec4(2.0 * p - 1.0, 0.0, 1.0);
}
