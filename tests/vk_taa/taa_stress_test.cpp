// Numerical stability of the TAA reference model over long runs: 10^5 frames (label slow), or
// FOVEA_TAA_STRESS_FRAMES frames in the shortened CI variant.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include "taa_model.hpp"
#include "test_images.hpp"

namespace fovea::vk::post {
namespace {

bool all_finite(const Image& img) {
    for (float v : img.data) {
        if (!std::isfinite(v)) return false;
    }
    return true;
}

float max_abs_diff(const Image& a, const Image& b) {
    float m = 0;
    for (std::size_t i = 0; i < a.data.size(); ++i)
        m = std::max(m, std::fabs(a.data[i] - b.data[i]));
    return m;
}

Image tonemapped(const Image& rgb) {
    Image t(rgb.width, rgb.height, 3);
    for (int y = 0; y < rgb.height; ++y)
        for (int x = 0; x < rgb.width; ++x) {
            const Vec3 v = tonemap_forward({rgb.at(x, y, 0), rgb.at(x, y, 1), rgb.at(x, y, 2)});
            t.at(x, y, 0) = v.x;
            t.at(x, y, 1) = v.y;
            t.at(x, y, 2) = v.z;
        }
    return t;
}

// 10^5 frames (label slow) or FOVEA_TAA_STRESS_FRAMES (CI uses a shortened run).
int stress_frames() {
    const char* env = std::getenv("FOVEA_TAA_STRESS_FRAMES");
    return env ? std::max(1, std::atoi(env)) : 100000;
}

void run_stress(bool moving, bool half) {
    const int w = 16, hgt = 12;
    const Image base = testing::texture(w + 64, hgt, 2.0f);
    const Image depth(w, hgt, 1, 1.0f);
    Image rate(w, hgt, 1);
    for (int y = 0; y < hgt; ++y)
        for (int x = 0; x < w; ++x) rate.at(x, y) = float(x) / float(w - 1);
    TaaParams p;
    p.half_storage = half;
    TaaHistory h;
    Image motion(w, hgt, 2, 0.0f);
    Image frame(w, hgt, 3);
    const int n = stress_frames();
    Image first_converged;
    int drift_checks = 0;
    for (int i = 0; i < n; ++i) {
        // Slow pan: 1/64 pixel per frame, wrapping every 64 px of texture (exactly periodic).
        const float off = moving ? std::fmod(float(i) / 64.0f, 64.0f) : 0.0f;
        for (int y = 0; y < hgt; ++y)
            for (int x = 0; x < w; ++x) {
                const float sx = float(x) + off;
                const int x0 = int(sx);
                const float t = sx - float(x0);
                for (int c = 0; c < 3; ++c)
                    frame.at(x, y, c) = base.at(x0, y, c) * (1 - t) + base.at(x0 + 1, y, c) * t;
                motion.at(x, y, 0) = moving ? -1.0f / 64.0f : 0.0f;  // content slides left
            }
        const Image out = taa_resolve({&frame, &depth, &motion, &rate, false}, h, p);
        if ((i & 1023) == 0 || i == n - 1) {
            ASSERT_TRUE(all_finite(out)) << "frame " << i;
            ASSERT_TRUE(all_finite(h.colour)) << "frame " << i;
        }
        if (!moving && i == 200) first_converged = taa_history_tonemapped(h);
        if (moving && i == 299) first_converged = taa_history_tonemapped(h);
        if (moving && i > 299 && (i - 299) % 4096 == 0) {
            // Same phase of the periodic pan (4096 frames = 64 px): the image must not drift.
            ASSERT_LT(max_abs_diff(taa_history_tonemapped(h), first_converged), 1.0f / 255.0f)
                << "frame " << i;
            ++drift_checks;
        }
    }
    if (moving) { EXPECT_EQ(drift_checks, std::max(0, n - 300) / 4096); }
    if (!moving && n > 200) {
        EXPECT_LT(max_abs_diff(taa_history_tonemapped(h), first_converged), 1.0f / 255.0f);
        EXPECT_LT(max_abs_diff(taa_history_tonemapped(h), tonemapped(frame)), 1.0f / 255.0f);
    }
}

TEST(TaaStress, StaticViewNeverDriftsFloat) { run_stress(false, false); }
TEST(TaaStress, StaticViewNeverDriftsHalf) { run_stress(false, true); }
TEST(TaaStress, SlowPanStaysFiniteAndPeriodicFloat) { run_stress(true, false); }
TEST(TaaStress, SlowPanStaysFiniteAndPeriodicHalf) { run_stress(true, true); }

}  // namespace
}  // namespace fovea::vk::post
