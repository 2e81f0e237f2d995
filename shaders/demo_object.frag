#version 450
// Object impostors: the exact shape intersected along the pixel's ray; misses are discarded and
// hits write their true depth, so silhouettes and intersections with the terrain are exact.
#extension GL_GOOGLE_include_directive : require
#define DEMO_RASTER_FRAGMENT
#include "demo_raster.glsl"
#include "demo_scene.glsl"

layout(location = 0) flat in vec4 centre_shape;
layout(location = 1) flat in vec4 half_index;

vec3 object_albedo(int i) {
    vec3 c[6] = vec3[](vec3(0.8, 0.25, 0.2), vec3(0.2, 0.5, 0.85), vec3(0.85, 0.75, 0.3),
                       vec3(0.3, 0.75, 0.4), vec3(0.75, 0.75, 0.78), vec3(0.6, 0.35, 0.7));
    return c[i % 6];
}

void main() {
    DemoView v = demo_view;
    vec3 ro = v.pos.xyz;
    vec3 rd = demo_pixel_ray(v, gl_FragCoord.xy);
    int shape = int(centre_shape.w + 0.5), i = int(half_index.w + 0.5);
    vec3 n;
    float t = demo_intersect_object(shape, centre_shape.xyz, half_index.xyz, ro, rd, n);
    if (t <= 0.0) discard;
    gl_FragDepth = kNear / (t * dot(rd, v.fwd.xyz));
    demo_write_surface(v, ro + t * rd, t, n, object_albedo(i),
                       vec4(2.0 + float(shape), 0.15 + 0.2 * float(i % 4), float(i % 3 == 0),
                            float(i)));
}
