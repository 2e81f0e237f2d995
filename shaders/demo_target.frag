#version 450
// Test targets (zone plate, grating): the screen-facing plane one unit ahead; world xy are its
// coordinates.
#extension GL_GOOGLE_include_directive : require
#define DEMO_RASTER_FRAGMENT
#include "demo_raster.glsl"
#include "demo_scene.glsl"

void main() {
    DemoView v = demo_view;
    vec3 rd = demo_pixel_ray(v, gl_FragCoord.xy);
    float d = dot(rd, v.fwd.xyz);
    if (d <= 1e-6) {
        demo_write_background(rd);
        return;
    }
    float t = 1.0 / d;
    int scene = int(v.fwd.w + 0.5);
    demo_write_surface(v, v.pos.xyz + t * rd, t, -v.fwd.xyz, vec3(1.0),
                       vec4(scene == kZonePlateScene ? 10.0 : 11.0, 0.0, 0.0, 0.0));
}
