#version 450
// Stengel §5: a pixel is a shading sample when its fixed pseudo-random threshold is below the
// dilated P of its 2x2 block; samples are appended to a compacted list for the indirect shading
// dispatch. Also writes S_t for every pixel.
#extension GL_GOOGLE_include_directive : require
#include "fovea_frame.glsl"
#include "adaptive_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 1, binding = 0, r32f) uniform readonly image2D half_dilated;
layout(std430, set = 1, binding = 1) buffer SampleList {
    uint dispatch[3];
    uint count;
    uint items[];  // x | y << 16
} list;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, ivec2(fovea_frame.extent)))) return;
    float pr = imageLoad(half_dilated, min(p / 2, imageSize(half_dilated) - 1)).x;
    if (adaptive_threshold(p) < pr) {
        uint slot = atomicAdd(list.count, 1u);
        list.items[slot] = uint(p.x) | (uint(p.y) << 16u);
    }
    // Mean sample spacing 1/sqrt(P) pixels: S_t = log2(spacing) / 2 (1 at 4-pixel spacing).
    imageStore(fovea_out_rate, p, vec4(clamp(-log2(max(pr, 1e-6)) * 0.25, 0.0, 1.0)));
}
