#version 450
// Objects of the rasterized demo G-buffer: each object's bounding box (36 vertices, object =
// gl_VertexIndex / 36) as a proxy; demo_object.frag intersects the exact shape.
#extension GL_GOOGLE_include_directive : require
#include "demo_raster.glsl"
#include "demo_scene.glsl"

layout(location = 0) flat out vec4 centre_shape;  // xyz centre, w shape
layout(location = 1) flat out vec4 half_index;    // xyz half size, w object index

// Two triangles per face, counter-clockwise seen from outside.
const ivec3 kBox[36] = ivec3[](
    ivec3(1, -1, -1), ivec3(1, 1, -1), ivec3(1, 1, 1), ivec3(1, -1, -1), ivec3(1, 1, 1), ivec3(1, -1, 1),
    ivec3(-1, -1, -1), ivec3(-1, -1, 1), ivec3(-1, 1, 1), ivec3(-1, -1, -1), ivec3(-1, 1, 1), ivec3(-1, 1, -1),
    ivec3(-1, 1, -1), ivec3(-1, 1, 1), ivec3(1, 1, 1), ivec3(-1, 1, -1), ivec3(1, 1, 1), ivec3(1, 1, -1),
    ivec3(-1, -1, -1), ivec3(1, -1, -1), ivec3(1, -1, 1), ivec3(-1, -1, -1), ivec3(1, -1, 1), ivec3(-1, -1, 1),
    ivec3(-1, -1, 1), ivec3(1, -1, 1), ivec3(1, 1, 1), ivec3(-1, -1, 1), ivec3(1, 1, 1), ivec3(-1, 1, 1),
    ivec3(-1, -1, -1), ivec3(-1, 1, -1), ivec3(1, 1, -1), ivec3(-1, -1, -1), ivec3(1, 1, -1), ivec3(1, -1, -1));

void main() {
    DemoView v = demo_view;
    int i = gl_VertexIndex / 36;
    vec3 c, hs;
    int shape;
    demo_object(i, c, hs, shape);
    centre_shape = vec4(c, float(shape));
    half_index = vec4(hs, float(i));
    // Slightly larger than the shape's bounds so rasterization never trims its silhouette.
    gl_Position = demo_clip_position(v, c + vec3(kBox[gl_VertexIndex % 36]) * hs * 1.01);
}
