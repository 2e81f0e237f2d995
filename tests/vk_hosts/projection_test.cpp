// jittered_projection() / crop_projection(): the documented jitter sign and crop, checked on
// points projected through a real perspective matrix.
#include <gtest/gtest.h>

#include <cmath>

#include "fovea/vk/projection.hpp"

namespace fovea::vk {
namespace {

// Vulkan-style perspective (y down, depth 0..1), column-major.
Mat4 perspective(float tan_x, float tan_y, float near_z, float far_z) {
    Mat4 m{};
    m[0] = 1.0f / tan_x;
    m[5] = -1.0f / tan_y;  // +y up in view space -> down in Vulkan NDC
    m[10] = far_z / (near_z - far_z);
    m[11] = -1.0f;
    m[14] = near_z * far_z / (near_z - far_z);
    return m;
}

// Window coordinates (pixels from the top-left corner) of view-space point v.
std::array<double, 3> to_window(const Mat4& m, std::array<float, 3> v, VkExtent2D size) {
    double c[4];
    for (int r = 0; r < 4; ++r)
        c[r] = m[0 * 4 + r] * v[0] + m[1 * 4 + r] * v[1] + m[2 * 4 + r] * v[2] + m[3 * 4 + r];
    return {(c[0] / c[3] + 1.0) * 0.5 * size.width, (c[1] / c[3] + 1.0) * 0.5 * size.height,
            c[2] / c[3]};
}

TEST(Projection, JitterMovesTheSampleByPlusJitterPixels) {
    const Mat4 p = perspective(0.6f, 0.4f, 0.1f, 100.f);
    const VkExtent2D size{640, 360};
    const std::array<float, 2> j{0.25f, -0.375f};
    const Mat4 pj = jittered_projection(p, j, size);
    for (const auto& v : {std::array<float, 3>{0.3f, -0.2f, -2.f}, {-1.f, 0.5f, -7.f}}) {
        const auto a = to_window(p, v, size), b = to_window(pj, v, size);
        // The point the plain projection puts at q is rendered at q - jitter: pixel centre
        // p + 0.5 samples what sits at p + 0.5 + jitter.
        EXPECT_NEAR(b[0], a[0] - j[0], 1e-3);
        EXPECT_NEAR(b[1], a[1] - j[1], 1e-3);
        EXPECT_NEAR(b[2], a[2], 1e-6);  // depth untouched
    }
}

TEST(Projection, CropMapsTheSubRectangleOntoTheView) {
    const Mat4 p = perspective(0.8f, 0.45f, 0.1f, 50.f);
    const VkExtent2D full{1920, 1080}, view{300, 200};
    const std::array<float, 4> crop{0.25f, 0.5f, 0.5f, 0.75f};
    const std::array<float, 2> j{-0.5f, 0.125f};
    const Mat4 pc = crop_projection(p, crop, j, view);
    for (const auto& v : {std::array<float, 3>{-0.4f, -0.1f, -3.f}, {-0.2f, -0.2f, -1.5f}}) {
        const auto a = to_window(p, v, full), b = to_window(pc, v, view);
        const double u = a[0] / full.width, w = a[1] / full.height;
        EXPECT_NEAR(b[0], (u - crop[0]) / (crop[2] - crop[0]) * view.width - j[0], 1e-3);
        EXPECT_NEAR(b[1], (w - crop[1]) / (crop[3] - crop[1]) * view.height - j[1], 1e-3);
        EXPECT_NEAR(b[2], a[2], 1e-6);
    }
    const Mat4 whole = crop_projection(p, {0.f, 0.f, 1.f, 1.f}, j, full);
    const Mat4 jit = jittered_projection(p, j, full);
    for (int i = 0; i < 16; ++i) EXPECT_FLOAT_EQ(whole[i], jit[i]);
}

}  // namespace
}  // namespace fovea::vk
