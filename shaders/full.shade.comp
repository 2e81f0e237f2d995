#version 450
// Method "full": the full-rate reference. One host shade per pixel, S_t = 0.
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 8, local_size_y = 8) in;
#include "fovea_frame.glsl"
#include "fovea_host.glsl"

void main() {
    ivec2 ext = ivec2(fovea_frame.extent);
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (gl_LocalInvocationIndex == 0u) {
        // Each workgroup counts the in-bounds pixels it shades.
        ivec2 origin = ivec2(gl_WorkGroupID.xy) * 8;
        ivec2 n = clamp(ext - origin, ivec2(0), ivec2(8));
        atomicAdd(fovea_stats.shaded_samples, uint(n.x * n.y));
    }
    if (p.x >= ext.x || p.y >= ext.y) return;
    FoveaGSample g = fovea_load_gsample(p);
    FoveaFootprint fp = fovea_make_footprint(vec2(p) + vec2(0.5), 1.0, g.distance, 0.0);
    imageStore(fovea_out_color, p, vec4(fovea_shade(g, fp), 1.0));
    imageStore(fovea_out_rate, p, vec4(0.0));
}
