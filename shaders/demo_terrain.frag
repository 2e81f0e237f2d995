#version 450
// Terrain fragments: the interpolated mesh point lies on the pixel's ray; the normal is the
// analytic height field's.
#extension GL_GOOGLE_include_directive : require
#define DEMO_RASTER_FRAGMENT
#include "demo_raster.glsl"
#include "demo_scene.glsl"

layout(location = 0) in vec3 world;

void main() {
    DemoView v = demo_view;
    demo_write_surface(v, world, distance(world, v.pos.xyz), demo_terrain_normal(world.xz),
                       vec3(0.35, 0.42, 0.22), vec4(1.0, 0.8, 0.0, 0.0));
}
