#version 450
// The demo host's G-buffer pass (tools/demo): ray-casts demo_scene.glsl for one view (the full
// frame or a crop of it, with sub-pixel jitter) and writes the G-buffer contract of
// sdk/include/fovea/vk/gbuffer.hpp, including motion against the previous camera.
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 8, local_size_y = 8) in;
#include "demo_scene.glsl"

struct DemoView {
    vec4 pos;     // xyz camera, w time
    vec4 right;   // xyz, w tan(fov_x / 2)
    vec4 up;      // xyz, w tan(fov_y / 2)
    vec4 fwd;     // xyz, w scene kind
    vec4 crop;    // x0 y0 x1 y1 of the full frame, 0..1
    vec4 jitter;  // xy pixels of this view, zw view size
    vec4 prev_pos, prev_right, prev_up, prev_fwd;
};
layout(std430, set = 0, binding = 0) readonly buffer DemoViews { DemoView views[]; } demo_views;
layout(set = 0, binding = 1, rgba32f) uniform writeonly image2D g_position;
layout(set = 0, binding = 2, rgba16f) uniform writeonly image2D g_normal;
layout(set = 0, binding = 3, rgba8) uniform writeonly image2D g_albedo;
layout(set = 0, binding = 4, rgba16f) uniform writeonly image2D g_material;
layout(set = 0, binding = 5, r32f) uniform writeonly image2D g_depth;
layout(set = 0, binding = 6, rg16f) uniform writeonly image2D g_motion;
layout(push_constant) uniform Push { uint view; } pc;

const float kNear = 0.1;
const float kFar = 400.0;

// The object table, built once per workgroup: demo_object() evaluates the terrain under every
// object (five transcendentals each), which per pixel cost more than the whole intersection.
const int kObjects = kGridX * kGridZ;
shared vec4 s_centre_radius[kObjects];  // xyz centre, w bounding-sphere radius
shared vec4 s_half_shape[kObjects];     // xyz half size, w shape

vec3 object_albedo(int i) {
    vec3 c[6] = vec3[](vec3(0.8, 0.25, 0.2), vec3(0.2, 0.5, 0.85), vec3(0.85, 0.75, 0.3),
                       vec3(0.3, 0.75, 0.4), vec3(0.75, 0.75, 0.78), vec3(0.6, 0.35, 0.7));
    return c[i % 6];
}

void main() {
    DemoView v = demo_views.views[pc.view];
    int scene = int(v.fwd.w + 0.5);
    int local = int(gl_LocalInvocationIndex);
    if (local < kObjects) {
        vec3 c, hs;
        int shape;
        demo_object(local, c, hs, shape);
        s_centre_radius[local] = vec4(c, length(hs));
        s_half_shape[local] = vec4(hs, float(shape));
    }
    barrier();
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    vec2 size = v.jitter.zw;
    if (p.x >= int(size.x) || p.y >= int(size.y)) return;
    vec2 uv = (vec2(p) + vec2(0.5) + v.jitter.xy) / size;
    vec2 full = mix(v.crop.xy, v.crop.zw, uv);  // position in the full frame, 0..1
    vec3 ro = v.pos.xyz;
    vec3 rd = normalize(v.fwd.xyz + v.right.xyz * ((2.0 * full.x - 1.0) * v.right.w) +
                        v.up.xyz * ((1.0 - 2.0 * full.y) * v.up.w));

    float t = -1.0;
    vec3 n = vec3(0.0, 1.0, 0.0);
    vec3 albedo = vec3(0.0);
    vec4 material = vec4(0.0);
    if (scene == kDemoScene) {
        float best = kFar;
        for (int i = 0; i < kObjects; ++i) {
            // Bounding-sphere rejection first: a few multiply-adds instead of the exact test.
            vec3 oc = s_centre_radius[i].xyz - ro;
            float r = s_centre_radius[i].w;
            float along = dot(oc, rd);
            if (along + r <= 0.0 || along - r >= best || dot(oc, oc) - along * along > r * r)
                continue;
            vec3 on;
            float ti = demo_intersect_object(int(s_half_shape[i].w), s_centre_radius[i].xyz,
                                             s_half_shape[i].xyz, ro, rd, on);
            if (ti > 0.0 && ti < best) {
                best = ti;
                t = ti;
                n = on;
                albedo = object_albedo(i);
                material = vec4(2.0 + s_half_shape[i].w, 0.15 + 0.2 * float(i % 4), float(i % 3 == 0),
                                float(i));
            }
        }
        // Terrain: march the height field up to the nearest object, refine by bisection.
        // Start where the ray enters the slab below the terrain's highest point (1.17).
        float tt = kNear;
        if (ro.y > 1.25 && rd.y < 0.0) tt = max(kNear, (ro.y - 1.25) / -rd.y);
        float prev = tt;
        bool hit = false;
        for (int s = 0; s < 64 && tt < best; ++s) {
            vec3 q = ro + tt * rd;
            if (q.y > 1.25 && rd.y >= 0.0) break;  // above the terrain's highest point, rising
            float dh = q.y - demo_terrain_height(q.xz);
            if (dh < 0.0) { hit = true; break; }
            prev = tt;
            tt += max(0.03, 0.6 * dh) * (1.0 + 0.01 * tt);
        }
        if (hit) {
            float lo = prev, hi = tt;
            for (int s = 0; s < 8; ++s) {
                float mid = 0.5 * (lo + hi);
                vec3 q = ro + mid * rd;
                if (q.y - demo_terrain_height(q.xz) < 0.0) hi = mid; else lo = mid;
            }
            t = hi;
            vec3 q = ro + t * rd;
            n = demo_terrain_normal(q.xz);
            albedo = vec3(0.35, 0.42, 0.22);
            material = vec4(1.0, 0.8, 0.0, 0.0);
        }
    } else {
        // Screen-facing target plane one unit ahead: world xy = its coordinates.
        float d = dot(rd, v.fwd.xyz);
        if (d > 1e-6) {
            t = 1.0 / d;
            n = -v.fwd.xyz;
            albedo = vec3(1.0);
            material = vec4(scene == kZonePlateScene ? 10.0 : 11.0, 0.0, 0.0, 0.0);
        }
    }

    vec4 position = vec4(0.0);
    float depth = 1.0;
    vec2 motion = vec2(0.0);
    if (t > 0.0) {
        vec3 w = ro + t * rd;
        float dist = t;
        position = vec4(w, dist);
        depth = clamp(1.0 - kNear / max(dist, kNear), 0.0, 1.0);
        // Where this point was in the previous frame's view (static scene, moving camera).
        vec3 dp = w - v.prev_pos.xyz;
        float z = dot(dp, v.prev_fwd.xyz);
        if (z > 1e-4) {
            vec2 prev_full = vec2(0.5 + 0.5 * dot(dp, v.prev_right.xyz) / (z * v.right.w),
                                  0.5 - 0.5 * dot(dp, v.prev_up.xyz) / (z * v.up.w));
            vec2 prev_px = (prev_full - v.crop.xy) / (v.crop.zw - v.crop.xy) * size;
            motion = (vec2(p) + vec2(0.5)) - prev_px;
        }
    } else {
        n = rd;  // background: the view direction, for the environment lookup
    }
    imageStore(g_position, p, position);
    imageStore(g_normal, p, vec4(n, 0.0));
    imageStore(g_albedo, p, vec4(albedo, 1.0));
    imageStore(g_material, p, material);
    imageStore(g_depth, p, vec4(depth));
    imageStore(g_motion, p, vec4(motion, 0.0, 0.0));
}
