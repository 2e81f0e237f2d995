#version 450
// A field of tilted quads receding from the camera, generated from gl_VertexIndex.
layout(push_constant) uniform P { mat4 view_proj; } pc;
layout(location = 0) out vec3 world;
const vec2 kCorner[6] = vec2[](vec2(0, 0), vec2(1, 0), vec2(0, 1), vec2(1, 0), vec2(1, 1), vec2(0, 1));
void main() {
    int quad = gl_VertexIndex / 6;
    vec2 c = kCorner[gl_VertexIndex % 6];
    vec2 cell = vec2(quad % 12, quad / 12);
    world = vec3((cell.x - 5.5) * 0.7 + c.x * 0.5, (cell.y - 1.5) * 0.45 + c.y * 0.35,
                 -2.0 - cell.y * 1.5 - c.x * 0.3);
    gl_Position = pc.view_proj * vec4(world, 1.0);
}
