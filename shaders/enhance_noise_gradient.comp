#version 450
// Noise pass 1 (after enhance_luma + enhance_reduce built the Gaussian pyramid G0..G3): one
// invocation per level-3 texel writes (Sobel gx, Sobel gy, min, max): the orientation field on
// G3 and the level-3 min/max pyramid texel, i.e. the min/max over the 2×2×2 reduction tree of
// its footprint in G0 with each level's clamp-to-edge (mirrors noise_parameters() and
// min_pyramid()/max_pyramid() in sdk/src/vk/post/enhance_model.cpp).
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, r32f) uniform readonly image2D g0;
layout(set = 0, binding = 1, r32f) uniform readonly image2D g3;
layout(set = 0, binding = 2, rgba32f) uniform writeonly image2D field;

float g3_at(ivec2 q) { return imageLoad(g3, clamp(q, ivec2(0), imageSize(g3) - 1)).x; }

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, imageSize(g3)))) return;
    float gx = (g3_at(p + ivec2(1, -1)) + 2.0 * g3_at(p + ivec2(1, 0)) + g3_at(p + ivec2(1, 1))) -
               (g3_at(p + ivec2(-1, -1)) + 2.0 * g3_at(p + ivec2(-1, 0)) + g3_at(p + ivec2(-1, 1)));
    float gy = (g3_at(p + ivec2(-1, 1)) + 2.0 * g3_at(p + ivec2(0, 1)) + g3_at(p + ivec2(1, 1))) -
               (g3_at(p + ivec2(-1, -1)) + 2.0 * g3_at(p + ivec2(0, -1)) + g3_at(p + ivec2(1, -1)));

    // Level sizes 0..2 (Vulkan mip sizes); texel t of level l+1 reduces texels 2t, 2t+1 of level
    // l, clamped to that level's last texel.
    ivec2 s0 = imageSize(g0);
    ivec2 s1 = max(s0 / 2, ivec2(1));
    ivec2 s2 = max(s1 / 2, ivec2(1));
    float lo = 1.0e30;
    float hi = -1.0e30;
    for (int j2 = 0; j2 < 2; ++j2)
    for (int i2 = 0; i2 < 2; ++i2) {
        ivec2 t2 = min(2 * p + ivec2(i2, j2), s2 - 1);
        for (int j1 = 0; j1 < 2; ++j1)
        for (int i1 = 0; i1 < 2; ++i1) {
            ivec2 t1 = min(2 * t2 + ivec2(i1, j1), s1 - 1);
            for (int j0 = 0; j0 < 2; ++j0)
            for (int i0 = 0; i0 < 2; ++i0) {
                float v = imageLoad(g0, min(2 * t1 + ivec2(i0, j0), s0 - 1)).x;
                lo = min(lo, v);
                hi = max(hi, v);
            }
        }
    }
    imageStore(field, p, vec4(gx, gy, lo, hi));
}
