#include "adaptive_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace fovea::vk::methods {
namespace {

const ScreenFov kHmd{1280, 1440, 90.0, 100.0};  // the paper's HMD: 100° vertical FOV
const ScreenFov kDesk{};                        // Guenter's desktop geometry

TEST(StengelAcuity, PaperCalibrationGivesFoveaAndPeripheryFloor) {
    const AdaptiveParams p;
    // §6.1: f = 0.07 and e > 0.47 are normalised eccentricities (×50° on the HMD).
    EXPECT_DOUBLE_EQ(acuity_probability(0.0, kHmd, p), 1.0);
    EXPECT_DOUBLE_EQ(acuity_probability(0.069 * 50.0, kHmd, p), 1.0);
    EXPECT_LT(acuity_probability(0.071 * 50.0, kHmd, p), 1.0);
    EXPECT_NEAR(acuity_probability(0.30 * 50.0, kHmd, p), 1.1715 - 2.45 * 0.30, 1e-12);
    EXPECT_DOUBLE_EQ(acuity_probability(0.48 * 50.0, kHmd, p), 0.02);
    EXPECT_DOUBLE_EQ(acuity_probability(80.0, kHmd, p), 0.02);
}

TEST(StengelAcuity, Eq3EccentricityUsesPerAxisAngles) {
    // Centre to the right edge is half the horizontal FOV; opposite sides add up.
    EXPECT_NEAR(eccentricity_deg({1920, 540}, {960, 540}, kDesk), kDesk.fov_h_deg / 2, 1e-9);
    EXPECT_NEAR(eccentricity_deg({0, 540}, {1920, 540}, kDesk), kDesk.fov_h_deg, 1e-9);
    EXPECT_NEAR(eccentricity_deg({960, 0}, {960, 540}, kDesk), kDesk.fov_v_deg / 2, 1e-9);
    EXPECT_DOUBLE_EQ(eccentricity_deg({700, 300}, {700, 300}, kDesk), 0.0);
}

TEST(StengelEyeMotion, GazeLineExtendsTheFoveaAlongTheMotion) {
    const Vec2f64 prev{800, 540};
    const Vec2f64 cur{900, 540};
    // A pixel 100 px ahead of the gaze lies on the predicted segment: eccentricity 0.
    EXPECT_NEAR(eccentricity_to_gaze_line_deg({1000, 540}, prev, cur, kDesk), 0.0, 1e-9);
    // Behind the gaze and beyond the segment's end it is the point distance.
    EXPECT_NEAR(eccentricity_to_gaze_line_deg({850, 540}, prev, cur, kDesk),
                eccentricity_deg({850, 540}, cur, kDesk), 1e-9);
    EXPECT_NEAR(eccentricity_to_gaze_line_deg({1100, 540}, prev, cur, kDesk),
                eccentricity_deg({1100, 540}, {1000, 540}, kDesk), 1e-9);
    // A fixation degenerates to Eq. 3.
    EXPECT_NEAR(eccentricity_to_gaze_line_deg({300, 200}, cur, cur, kDesk),
                eccentricity_deg({300, 200}, cur, kDesk), 1e-12);
}

TEST(StengelEyeMotion, Eq5IsContinuousAndMonotone) {
    EXPECT_DOUBLE_EQ(motion_gain(0.0), 1.0);
    EXPECT_DOUBLE_EQ(motion_gain(0.83), 1.0);
    EXPECT_NEAR(motion_gain(0.8301), 1.0, 1e-3);
    EXPECT_NEAR(motion_gain(10.0), 0.962 - 0.463, 1e-12);
    EXPECT_NEAR(motion_gain(118.0), 0.002, 1e-3);
    EXPECT_DOUBLE_EQ(motion_gain(500.0), 0.002);
    EXPECT_DOUBLE_EQ(motion_gain(NAN), 1.0);
    double prev = 2.0;
    for (double v = 0.5; v < 200.0; v *= 1.1) {
        EXPECT_LE(motion_gain(v), prev);
        prev = motion_gain(v);
    }
}

TEST(StengelHighlights, Eq8PeaksOnTheReflectionAndFallsOffWithGamma20) {
    const double l[3] = {0.0, 0.0, 1.0};
    const double on[3] = {0.0, 0.0, 1.0};
    const double off[3] = {0.0, std::sin(0.3), std::cos(0.3)};
    const double away[3] = {0.0, 0.0, -1.0};
    EXPECT_DOUBLE_EQ(highlight_term(l, on, 0.7, 20.0), 0.7);
    EXPECT_NEAR(highlight_term(l, off, 1.0, 20.0), std::pow(std::cos(0.3), 20.0), 1e-12);
    EXPECT_LT(highlight_term(l, off, 1.0, 20.0), 0.5);          // 17° off: already below half
    EXPECT_DOUBLE_EQ(highlight_term(l, away, 1.0, 20.0), 0.0);  // negative influence clamped
}

TEST(StengelSilhouettes, DepthAndNormalStepsRespondFlatDoesNot) {
    const AdaptiveParams p;
    const double n[3] = {0, 0, 1};
    const double same[4][3] = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
    const double flat_depth[4] = {10.0, 10.0, 10.0, 10.0};
    EXPECT_DOUBLE_EQ(silhouette_response(10.0, flat_depth, n, same, p), 0.0);
    const double step_depth[4] = {10.0, 20.0, 10.0, 10.0};  // occlusion edge
    EXPECT_DOUBLE_EQ(silhouette_response(10.0, step_depth, n, same, p), 1.0);
    const double slight[4] = {10.0, 10.1, 10.0, 10.0};  // 1 % slope: 0.2 of a silhouette
    EXPECT_NEAR(silhouette_response(10.0, slight, n, same, p), 0.2, 1e-9);
    const double crease[4][3] = {{0, 0, 1}, {1, 0, 0}, {0, 0, 1}, {0, 0, 1}};  // 90° crease
    EXPECT_DOUBLE_EQ(silhouette_response(10.0, flat_depth, n, crease, p), 1.0);
}

TEST(StengelBrightness, Eq11ScalesDownDarkAndBrightOnly) {
    const AdaptiveParams p;
    EXPECT_DOUBLE_EQ(brightness_scale(0.0, p), 0.0);
    EXPECT_NEAR(brightness_scale(0.075, p), 0.5, 1e-12);
    EXPECT_DOUBLE_EQ(brightness_scale(0.15, p), 1.0);
    EXPECT_DOUBLE_EQ(brightness_scale(0.5, p), 1.0);
    EXPECT_DOUBLE_EQ(brightness_scale(0.9, p), 1.0);
    EXPECT_NEAR(brightness_scale(0.95, p), 0.5, 1e-12);
    EXPECT_DOUBLE_EQ(brightness_scale(1.0, p), 0.0);
    EXPECT_NEAR(luminance(1.0, 1.0, 1.0), 1.0, 1e-12);  // Eq. 9 weights sum to one
    EXPECT_DOUBLE_EQ(luminance(0.0, 1.0, 0.0), 0.587);
}

TEST(StengelBrightness, Eq10ExposureConvergesToTheTargetAndStaysFinite) {
    const AdaptiveParams p;  // a_r = 0.05, A = 0.5
    for (double scene : {0.05, 1.0, 20.0}) {
        ExposureAdapter e(1.0);
        // Additive Eq. 10 adapts slowly in the dark (dE/dt ∝ L): ~1600 frames time constant at
        // L = 0.05, like dark adaptation; 20000 frames (5.5 min at 60 Hz) settle every case.
        for (int i = 0; i < 20000; ++i) {
            const double tm = tonemap(scene, e.exposure());
            e.update(tm * 0.7, 0.7, p);  // uniform scene, ΣF_M = 0.7
        }
        EXPECT_NEAR(tonemap(scene, e.exposure()), p.auto_exposure, 0.01) << scene;
    }
    ExposureAdapter e(1.0);
    e.update(NAN, 1.0, p);  // a NaN frame is ignored
    e.update(1.0, 0.0, p);  // so is an empty weight
    EXPECT_DOUBLE_EQ(e.exposure(), 1.0);
    // The step is a_r times the error.
    EXPECT_NEAR(e.update(0.3, 1.0, p), 1.0 + 0.05 * (0.5 - 0.3), 1e-12);
}

TEST(StengelProbability, Eq12IsTheScaledMaximum) {
    EXPECT_DOUBLE_EQ(sampling_probability(0.2, 0.1, 0.7, 0.3, 1.0), 0.7);
    EXPECT_DOUBLE_EQ(sampling_probability(0.2, 0.1, 0.7, 0.3, 0.5), 0.35);
    EXPECT_DOUBLE_EQ(sampling_probability(2.0, 0.0, 0.0, 0.0, 1.0), 1.0);
}

TEST(StengelPattern, ThresholdIsStableUniformAndDecorrelated) {
    // Stable: a pure function of pixel and seed.
    EXPECT_EQ(sample_hash(17, 42, 7), sample_hash(17, 42, 7));
    // Uniform: the fraction below P matches P on 256×256 pixels.
    for (double prob : {0.05, 0.3, 0.7}) {
        int hits = 0;
        for (std::uint32_t y = 0; y < 256; ++y)
            for (std::uint32_t x = 0; x < 256; ++x) hits += sample_threshold(x, y, 1) < prob;
        EXPECT_NEAR(hits / 65536.0, prob, 0.01) << prob;
    }
    // Decorrelated: horizontal neighbours agree about half the time at P = 0.5.
    int same = 0;
    for (std::uint32_t x = 0; x < 4096; ++x)
        same += (sample_threshold(x, 9, 1) < 0.5) == (sample_threshold(x + 1, 9, 1) < 0.5);
    EXPECT_NEAR(same / 4096.0, 0.5, 0.04);
    for (std::uint32_t x = 0; x < 1000; ++x) {
        const double t = sample_threshold(x, x * 3, 5);
        EXPECT_GE(t, 0.0);
        EXPECT_LT(t, 1.0);
    }
}

TEST(StengelDilation, LowResDilationCoversFiveByFiveAndStaysWithinSevenBySeven) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (auto [w, h] : {std::pair{37, 23}, std::pair{64, 64}}) {
        ProbabilityMap m{w, h, std::vector<float>(std::size_t(w * h))};
        for (float& v : m.values) v = u(rng) < 0.05f ? u(rng) : 0.0f;  // sparse features
        const ProbabilityMap fast = dilate_via_low_res(m);
        const ProbabilityMap five = dilate_exact(m, 2);
        const ProbabilityMap seven = dilate_exact(m, 3);
        for (std::size_t i = 0; i < m.values.size(); ++i) {
            EXPECT_GE(fast.values[i], five.values[i]);
            EXPECT_LE(fast.values[i], seven.values[i]);
        }
    }
}

}  // namespace
}  // namespace fovea::vk::methods
