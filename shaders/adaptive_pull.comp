#version 450
// Pull (Gortler et al. 1996): each coarser texel is the weight-averaged colour of its 2x2
// children, weight min(1, Σw). Level 0 holds the shaded samples (w = 1) and holes (w = 0).
#extension GL_GOOGLE_include_directive : require
#include "fovea_frame.glsl"
#include "adaptive_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 1, binding = 0, rgba16f) uniform readonly image2D fine;
layout(set = 1, binding = 1, rgba16f) uniform writeonly image2D coarse;

void main() {
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(t, imageSize(coarse)))) return;
    ivec2 fs = imageSize(fine) - 1;
    vec3 sum = vec3(0.0);
    float w = 0.0;
    for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
            vec4 c = imageLoad(fine, min(2 * t + ivec2(dx, dy), fs));
            sum += c.rgb * c.a;
            w += c.a;
        }
    imageStore(coarse, t, w > 0.0 ? vec4(sum / w, min(w, 1.0)) : vec4(0.0));
}
