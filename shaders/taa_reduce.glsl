// TAA pass 2: 2×2 box reduction of both moment images, level l -> l + 1 (Vulkan mip sizes; a
// 1-texel-wide source repeats its texel): moments are linear, so the mean of moments is the
// moment of the larger window (Patney §4.3).
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, TAA_FORMAT) uniform readonly image2D m1_src;
layout(set = 0, binding = 1, TAA_FORMAT) uniform readonly image2D m2_src;
layout(set = 0, binding = 2, TAA_FORMAT) uniform writeonly image2D m1_dst;
layout(set = 0, binding = 3, TAA_FORMAT) uniform writeonly image2D m2_dst;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, imageSize(m1_dst)))) return;
    ivec2 last = imageSize(m1_src) - 1;
    ivec2 a = min(2 * p, last);
    ivec2 b = min(2 * p + ivec2(1, 0), last);
    ivec2 c = min(2 * p + ivec2(0, 1), last);
    ivec2 d = min(2 * p + ivec2(1, 1), last);
    imageStore(m1_dst, p, 0.25 * (imageLoad(m1_src, a) + imageLoad(m1_src, b) +
                                  imageLoad(m1_src, c) + imageLoad(m1_src, d)));
    imageStore(m2_dst, p, 0.25 * (imageLoad(m2_src, a) + imageLoad(m2_src, b) +
                                  imageLoad(m2_src, c) + imageLoad(m2_src, d)));
}
