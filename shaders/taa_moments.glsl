// TAA pass 1: first two raw moments of the tone-mapped YCoCg colour over 3×3 (Patney §4.2),
// pre-filtered straight to mip level 1 of the moment chain: one invocation per level-1 texel t
// averages the 3×3 windows of level-0 texels 2t and 2t + 1 (Vulkan mip sizes never clamp those:
// a 1-pixel-wide image is constant along that axis), i.e. the 4×4 colour footprint with weights
// (1, 2, 2, 1)/6 per axis. Level 0 is never stored: the resolve computes a pixel's own 3×3
// window where LOD = 4·S_t < 1 reads it (the fovea only). No shared memory and no barriers,
// which are costly on a CPU device. TAA_FORMAT is rgba16f or rgba32f (the wrapper files).
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, rgba16f) uniform readonly image2D color_in;
layout(set = 0, binding = 1, TAA_FORMAT) uniform writeonly image2D m1_level1;
layout(set = 0, binding = 2, TAA_FORMAT) uniform writeonly image2D m2_level1;

#include "taa_common.glsl"

void main() {
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(t, imageSize(m1_level1)))) return;
    ivec2 hi = imageSize(color_in) - 1;
    const float w[4] = float[4](1.0, 2.0, 2.0, 1.0);
    vec3 m1 = vec3(0.0);
    vec3 m2 = vec3(0.0);
    for (int j = 0; j < 4; ++j) {
        vec3 r1 = vec3(0.0);
        vec3 r2 = vec3(0.0);
        for (int i = 0; i < 4; ++i) {
            ivec2 q = clamp(2 * t + ivec2(i - 1, j - 1), ivec2(0), hi);
            vec3 c = taa_rgb_to_ycocg(taa_tonemap(imageLoad(color_in, q).rgb));
            r1 += w[i] * c;
            r2 += w[i] * (c * c);
        }
        m1 += w[j] * r1;
        m2 += w[j] * r2;
    }
    imageStore(m1_level1, t, vec4(m1 * (1.0 / 36.0), 0.0));
    imageStore(m2_level1, t, vec4(m2 * (1.0 / 36.0), 0.0));
}
