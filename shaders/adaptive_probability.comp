#version 450
// Stengel Eq. 12 for each 2x2 pixel block, written to a half-resolution map (the first half of
// the cheap 5x5 dilation): P = max(F_M, F_O, F_H, F_S) · S, floored at ω_p. The block reads its
// 3x3-pixel neighbourhood once; F_S and F_O are the largest steps between adjacent pixels in it
// (which also covers the steps to the right and lower neighbour blocks), F_H the largest
// highlight of its 4 pixels, F_M and S are taken at the block centre. Straight-line code: llvmpipe
// executes both sides of every branch.
#extension GL_GOOGLE_include_directive : require
#include "fovea_frame.glsl"
#include "adaptive_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 1, binding = 0, rgba16f) uniform readonly image2D prev_low;
layout(std430, set = 1, binding = 1) readonly buffer Exposure {
    float exposure;
    float l_avg;
    float pad[2];
} ex;
layout(set = 1, binding = 2, r32f) uniform writeonly image2D half_p;

// Silhouette and texture response between two adjacent pixels.
vec2 step_response(vec4 pa, vec3 na, vec3 aa, vec4 pb, vec3 nb, vec3 ab) {
    float bga = pa.w > 0.0 ? 0.0 : 1.0;
    float bgb = pb.w > 0.0 ? 0.0 : 1.0;
    float depth = abs(pa.w - pb.w) / max(min(pa.w, pb.w), 1e-6) * ad.gain_depth;
    float crease = (1.0 - dot(na, nb)) * ad.gain_normal;
    // Background against geometry is a full silhouette; two background pixels are none.
    float f_s = max(abs(bga - bgb), (1.0 - max(bga, bgb)) * max(depth, crease));
    vec3 da = abs(aa - ab);
    return vec2(f_s, max(da.r, max(da.g, da.b)) * ad.gain_albedo);
}

void main() {
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(t, imageSize(half_p)))) return;
    ivec2 hi = ivec2(fovea_frame.extent) - 1;
    vec4 pos[9];
    vec3 nrm[9];
    vec3 alb[9];
    for (int i = 0; i < 9; ++i) {
        ivec2 q = clamp(2 * t + ivec2(i % 3, i / 3), ivec2(0), hi);
        pos[i] = imageLoad(fovea_g_position, q);
        uvec4 surface = imageLoad(fovea_g_surface, q);
        nrm[i] = fovea_unpack_normal(surface);
        alb[i] = fovea_unpack_albedo(surface).rgb;
    }
    vec2 so = vec2(0.0);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 2; ++x) {
            int a = y * 3 + x;
            so = max(so, step_response(pos[a], nrm[a], alb[a], pos[a + 1], nrm[a + 1], alb[a + 1]));
            int b = x * 3 + y;  // vertical pairs: (y, x) transposed
            so = max(so, step_response(pos[b], nrm[b], alb[b], pos[b + 3], nrm[b + 3], alb[b + 3]));
        }

    // F_H (Eq. 8) for the directional light, the largest of the block's 4 pixels.
    float f_h = 0.0;
    for (int i = 0; i < 4; ++i) {
        int k = (i / 2) * 3 + (i % 2);
        vec3 view = normalize(pos[k].xyz - fovea_frame.camera_pos.xyz);
        float h = pow(max(dot(ad.light.xyz, reflect(view, nrm[k])), 0.0), ad.gamma) * ad.light.w;
        f_h = max(f_h, pos[k].w > 0.0 ? h : 0.0);
    }

    // F_M (Eq. 4–5) at the block centre: retinal speed of the surface against the eye. Motion
    // runs from the unjittered pixel centre to the jittered sample's previous position (the
    // contract TAA reads), so the sample's own flow is motion + jitter.
    ivec2 c = clamp(2 * t + ivec2(1), ivec2(0), hi);
    vec2 pc = vec2(2 * t) + 1.0;
    vec2 motion = imageLoad(fovea_g_motion, c).xy;
    float deg_per_px = fovea_pixel_size_deg(fovea_frame.display, pc);
    float v = length(motion + fovea_frame.jitter_px - ad.eye_motion_px) * deg_per_px /
              max(ad.dt, 1e-4);
    float f_m = adaptive_acuity(pc) * adaptive_motion_gain(v);

    // S (Eq. 11) from last frame's low-resolution colour at this frame's exposure.
    ivec2 lt = clamp(ivec2(pc * vec2(imageSize(prev_low)) / fovea_frame.extent), ivec2(0),
                     imageSize(prev_low) - 1);
    float s = adaptive_brightness_scale(
        adaptive_tonemap(adaptive_luminance(imageLoad(prev_low, lt).rgb), ex.exposure));
    s = ad.has_history != 0 ? s : 1.0;

    so *= ad.features;
    f_h *= ad.features;
    float pr = clamp(max(max(f_m, so.y), max(f_h, so.x)) * s, 0.0, 1.0);
    // The ω_p floor also after S: a region that went dark must still be sampled to notice a
    // change (the literal Eq. 12 can reach 0 there and never recover).
    imageStore(half_p, t, vec4(max(pr, ad.omega_p)));
}
