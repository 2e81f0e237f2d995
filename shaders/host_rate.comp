#version 450
// Paths 3 and 4 (host-rendered frames): S_t per pixel from the acuity model, as the module's
// own methods would write it, so the post passes (TAA's variance LOD, contrast enhancement)
// treat the periphery as the rate image shaded it (path 3) or as the eye resolves it (path 4).
// Counts the samples the host shaded: every pixel (path 4) or 1/rate^2 of them (path 3, the
// fragment invocations the rate image implies).
#extension GL_GOOGLE_include_directive : require
#include "fovea_frame.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(push_constant) uniform HostRatePush {
    int count_rate;  // 1: path 3 (samples / rate^2), 0: path 4 (every pixel)
} hp;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = ivec2(fovea_frame.extent);
    float t = fovea_frame.acuity.tile_size;
    vec2 lo = floor(vec2(p) / t) * t;
    float r = fovea_tile_rate(fovea_frame.display, fovea_frame.acuity, lo,
                              min(lo + t, fovea_frame.extent), fovea_frame.gaze_px);
    if (gl_LocalInvocationIndex == 0u) {
        // The block's pixels; 8x8 blocks lie inside one rate tile (tile sizes are multiples of
        // 8 by default), so the leader's rate is the block's.
        ivec2 n = clamp(size - ivec2(gl_WorkGroupID.xy) * 8, ivec2(0), ivec2(8));
        float samples = float(n.x * n.y) / (hp.count_rate != 0 ? r * r : 1.0);
        atomicAdd(fovea_stats.shaded_samples, uint(samples + 0.5));
    }
    if (any(greaterThanEqual(p, size))) return;
    imageStore(fovea_out_rate, p, vec4(fovea_normalized_rate(r)));
}
