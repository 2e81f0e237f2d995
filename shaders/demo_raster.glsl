// The demo host's rasterized G-buffer (tools/demo/scene.cpp): the view table shared by every
// stage, the projection of a world point into a view (a crop of the full frame with sub-pixel
// jitter, reverse-Z depth) and the ray through a pixel, which the fragment stages use to produce
// exactly what a ray-cast through the pixel centre would. Depth is reverse-Z (near / view z:
// 1 at the near plane, 0 at infinity) for float precision far away; the G-buffer's own depth
// image keeps the contract's 1 - near / distance.
#ifndef FOVEA_DEMO_RASTER_GLSL
#define FOVEA_DEMO_RASTER_GLSL

struct DemoView {
    vec4 pos;     // xyz camera, w time
    vec4 right;   // xyz, w tan(fov_x / 2)
    vec4 up;      // xyz, w tan(fov_y / 2)
    vec4 fwd;     // xyz, w scene kind
    vec4 crop;    // x0 y0 x1 y1 of the full frame, 0..1
    vec4 jitter;  // xy pixels of this view, zw view size
    vec4 prev_pos, prev_right, prev_up, prev_fwd;
};
// This draw's view: a uniform block bound at the view's dynamic offset, so every load is at a
// constant offset (llvmpipe loads those once per call; a storage buffer it loads lane by lane).
layout(std140, set = 0, binding = 0) uniform DemoViewBlock { DemoView demo_view; };

const float kNear = 0.1;

// Clip-space position of world point w. Linear in the camera-space point, so the rasterizer's
// pixel centre p + 0.5 lands on its ray (demo_pixel_ray): full-frame uv = mix(crop, (p + 0.5 +
// jitter) / size).
vec4 demo_clip_position(DemoView v, vec3 w) {
    vec3 d = w - v.pos.xyz;
    float x = dot(d, v.right.xyz), y = dot(d, v.up.xyz), z = dot(d, v.fwd.xyz);
    vec2 full_z = vec2(0.5 * z + 0.5 * x / v.right.w, 0.5 * z - 0.5 * y / v.up.w);  // full * z
    vec2 px_z = (full_z - v.crop.xy * z) / (v.crop.zw - v.crop.xy) * v.jitter.zw - v.jitter.xy * z;
    return vec4(2.0 * px_z / v.jitter.zw - z, kNear, z);  // depth near / z; z < near is clipped
}

// Unit ray direction through the framebuffer position (gl_FragCoord.xy, a pixel centre).
vec3 demo_pixel_ray(DemoView v, vec2 frag) {
    vec2 full = mix(v.crop.xy, v.crop.zw, (frag + v.jitter.xy) / v.jitter.zw);
    return normalize(v.fwd.xyz + v.right.xyz * ((2.0 * full.x - 1.0) * v.right.w) +
                     v.up.xyz * ((1.0 - 2.0 * full.y) * v.up.w));
}

#ifdef DEMO_RASTER_FRAGMENT
#include "fovea_gbuffer.glsl"
// The G-buffer images (sdk/include/fovea/vk/gbuffer.hpp) as colour attachments.
layout(location = 0) out vec4 g_position;
layout(location = 1) out uvec4 g_surface;
layout(location = 2) out float g_depth;
layout(location = 3) out vec2 g_motion;

void demo_write_surface(DemoView v, vec3 w, float dist, vec3 n, vec3 albedo, vec4 material) {
    g_position = vec4(w, dist);
    g_surface = fovea_pack_surface(n, albedo, 1.0, material);
    g_depth = clamp(1.0 - kNear / max(dist, kNear), 0.0, 1.0);
    // Where this point was in the previous frame's view (static scene, moving camera).
    g_motion = vec2(0.0);
    vec3 dp = w - v.prev_pos.xyz;
    float z = dot(dp, v.prev_fwd.xyz);
    if (z > 1e-4) {
        vec2 prev_full = vec2(0.5 + 0.5 * dot(dp, v.prev_right.xyz) / (z * v.right.w),
                              0.5 - 0.5 * dot(dp, v.prev_up.xyz) / (z * v.up.w));
        vec2 prev_px = (prev_full - v.crop.xy) / (v.crop.zw - v.crop.xy) * v.jitter.zw;
        g_motion = gl_FragCoord.xy - prev_px;
    }
}

// Background: no surface; the normal carries the view direction for the environment lookup.
void demo_write_background(vec3 rd) {
    g_position = vec4(0.0);
    g_surface = fovea_pack_surface(rd, vec3(0.0), 1.0, vec4(0.0));
    g_depth = 1.0;
    g_motion = vec2(0.0);
}
#endif

#endif
