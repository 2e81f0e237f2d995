#version 450
// Indirect dispatch size for the compacted LP texel list; its texels enter the stats.
#extension GL_GOOGLE_include_directive : require
#include "fovea_frame.glsl"

layout(local_size_x = 1) in;
layout(std430, set = 1, binding = 0) buffer TexelList {
    uint dispatch[3];
    uint count;
} list;

void main() {
    list.dispatch[0] = (list.count + 63u) / 64u;
    list.dispatch[1] = 1u;
    list.dispatch[2] = 1u;
    atomicAdd(fovea_stats.shaded_samples, list.count);
}
