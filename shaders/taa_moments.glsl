// TAA pass 1: first two raw moments of the tone-mapped YCoCg colour over 3×3 (Patney §4.2),
// level 0 of the moment mip chain. TAA_FORMAT is rgba16f or rgba32f (the wrapper files).
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, rgba16f) uniform readonly image2D color_in;
layout(set = 0, binding = 1, TAA_FORMAT) uniform writeonly image2D m1_out;
layout(set = 0, binding = 2, TAA_FORMAT) uniform writeonly image2D m2_out;

#include "taa_common.glsl"

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(color_in);
    if (any(greaterThanEqual(p, size))) return;
    vec3 m1 = vec3(0.0);
    vec3 m2 = vec3(0.0);
    for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
            ivec2 q = clamp(p + ivec2(dx, dy), ivec2(0), size - 1);
            vec3 c = taa_rgb_to_ycocg(taa_tonemap(imageLoad(color_in, q).rgb));
            m1 += c;
            m2 += c * c;
        }
    }
    imageStore(m1_out, p, vec4(m1 * (1.0 / 9.0), 0.0));
    imageStore(m2_out, p, vec4(m2 * (1.0 / 9.0), 0.0));
}
