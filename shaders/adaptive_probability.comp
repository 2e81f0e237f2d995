#version 450
// Stengel Eq. 12 per pixel, written max-reduced over 2x2 pixels into a half-resolution map (the
// first half of the cheap 5x5 dilation): P = max(F_M, F_O, F_H, F_S) · S, floored at ω_p.
#extension GL_GOOGLE_include_directive : require
#include "fovea_frame.glsl"
#include "adaptive_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 1, binding = 0, rgba16f) uniform readonly image2D prev_low;
layout(std430, set = 1, binding = 1) readonly buffer Exposure { float exposure; float l_avg; float pad[2]; } ex;
layout(set = 1, binding = 2, r32f) uniform writeonly image2D half_p;

ivec2 clamp_px(ivec2 p) { return clamp(p, ivec2(0), ivec2(fovea_frame.extent) - 1); }

float probability(ivec2 p) {
    vec2 pc = vec2(p) + 0.5;
    vec4 pos = imageLoad(fovea_g_position, p);
    vec3 n = imageLoad(fovea_g_normal, p).xyz;
    vec3 alb = imageLoad(fovea_g_albedo, p).rgb;
    vec2 motion = imageLoad(fovea_g_motion, p).xy;

    // F_M (Eq. 4–5): retinal speed = the pixel's screen motion relative to the eye's.
    float deg_per_px = fovea_pixel_size_deg(fovea_frame.display, pc);
    // Motion runs from the unjittered pixel centre to the jittered sample's previous position
    // (the contract TAA reads): the sample's own flow is motion + jitter.
    float v = length(motion + fovea_frame.jitter_px - ad.eye_motion_px) * deg_per_px /
              max(ad.dt, 1e-4);
    float f_m = adaptive_acuity(pc) * adaptive_motion_gain(v);

    // F_S and F_O: depth / normal / albedo steps against the 4 neighbours.
    const ivec2 kN[4] = ivec2[](ivec2(1, 0), ivec2(-1, 0), ivec2(0, 1), ivec2(0, -1));
    float f_s = 0.0, f_o = 0.0;
    bool bg = !(pos.w > 0.0);
    for (int i = 0; i < 4; ++i) {
        ivec2 q = clamp_px(p + kN[i]);
        float dq = imageLoad(fovea_g_position, q).w;
        bool bgq = !(dq > 0.0);
        if (bg != bgq) {
            f_s = 1.0;
        } else if (!bg) {
            f_s = max(f_s, abs(pos.w - dq) / max(min(pos.w, dq), 1e-6) * ad.gain_depth);
            f_s = max(f_s, (1.0 - dot(n, imageLoad(fovea_g_normal, q).xyz)) * ad.gain_normal);
        }
        vec3 da = abs(alb - imageLoad(fovea_g_albedo, q).rgb);
        f_o = max(f_o, max(da.r, max(da.g, da.b)) * ad.gain_albedo);
    }

    // F_H (Eq. 8) for the directional light.
    float f_h = 0.0;
    if (!bg) {
        vec3 view = normalize(pos.xyz - fovea_frame.camera_pos.xyz);
        vec3 r = reflect(view, n);
        f_h = pow(max(dot(ad.light.xyz, r), 0.0), ad.gamma) * ad.light.w;
    }

    // S (Eq. 11) from last frame's low-resolution colour at this frame's exposure.
    float s = 1.0;
    if (ad.has_history != 0) {
        ivec2 t = clamp(ivec2(pc * vec2(imageSize(prev_low)) / fovea_frame.extent), ivec2(0),
                        imageSize(prev_low) - 1);
        s = adaptive_brightness_scale(
            adaptive_tonemap(adaptive_luminance(imageLoad(prev_low, t).rgb), ex.exposure));
    }
    float pr = clamp(max(max(f_m, f_o), max(f_h, f_s)) * s, 0.0, 1.0);
    // The ω_p floor also after S: a region that went dark must still be sampled to notice a
    // change (the literal Eq. 12 can reach 0 there and never recover).
    return max(pr, ad.omega_p);
}

void main() {
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(t, imageSize(half_p)))) return;
    float m = 0.0;
    for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) m = max(m, probability(clamp_px(2 * t + ivec2(dx, dy))));
    imageStore(half_p, t, vec4(m));
}
