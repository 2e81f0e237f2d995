#version 450
// Stengel §5: shade only the listed samples (indirect dispatch over the compacted list) into
// level 0 of the pull-push pyramid (alpha 1 = sample, level 0 was cleared to alpha 0).
#extension GL_GOOGLE_include_directive : require
#include "fovea_frame.glsl"
#include "fovea_host.glsl"

layout(local_size_x = 64) in;
layout(std430, set = 1, binding = 0) readonly buffer SampleList {
    uint dispatch[3];
    uint count;
    uint items[];
} list;
layout(set = 1, binding = 1, rgba16f) uniform writeonly image2D level0;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= list.count) return;
    uint packed = list.items[i];
    ivec2 p = ivec2(int(packed & 0xffffu), int(packed >> 16u));
    FoveaGSample g = fovea_load_gsample(p);
    vec3 c = fovea_shade(g, fovea_make_footprint(vec2(p) + 0.5, 1.0, g.distance, 0.0));
    // One NaN or inf (above the half-float range) would spread over a whole pull-push block
    // (0 · inf = NaN in the fill): keep samples finite.
    c = min(mix(c, vec3(0.0), isnan(c)), vec3(65504.0));
    imageStore(level0, p, vec4(c, 1.0));
}
