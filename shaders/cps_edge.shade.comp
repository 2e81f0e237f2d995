#version 450
// Coarse pixel shading, pass 3 (indirect): pixels whose surface differs from their coarse
// pixel's shading sample get their own shade, pre-filtered at their tile's rate.
#extension GL_GOOGLE_include_directive : require
#include "fovea_frame.glsl"
#include "cps_common.glsl"
layout(local_size_x = CPS_GROUP_SIZE) in;
#include "fovea_host.glsl"
layout(set = 1, binding = 3, rgba16f) uniform writeonly image2D cps_color;  // persistent colour

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint n = min(cps_args.count[kCpsEdgeList], cps_push.edge_capacity);
    // One thread counts the pass's shades: no shared counter, no workgroup barrier.
    if (i == 0u && n > 0u) {
        atomicAdd(fovea_stats.shaded_samples, n);
        atomicAdd(fovea_stats.edge_samples, n);
    }
    if (i < n) {
        uint e = cps_edges.px[i];
        ivec2 p = ivec2(int(e & 0x7fffu), int((e >> 15) & 0x7fffu));
        float r = float(1u << (e >> 30));
        FoveaGSample g = fovea_load_gsample(p);
        FoveaFootprint fp = fovea_make_footprint(vec2(p) + vec2(0.5), r, g.distance,
                                                 fovea_normalized_rate(r));
        vec3 c = fovea_shade(g, fp);
        imageStore(cps_color, p, vec4(c, 1.0));
        uint ts = uint(fovea_frame.acuity.tile_size);
        cps_add_luminance(uint(p.y) / ts * cps_push.tiles_x + uint(p.x) / ts, c);
    }
}
