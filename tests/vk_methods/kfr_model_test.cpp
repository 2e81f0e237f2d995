#include "kfr_model.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace fovea::vk::methods {
namespace {

constexpr int kW = 1920;
constexpr int kH = 1080;

KfrMap make_map(Vec2d gaze, double sigma = 1.8, KfrKernel k = kfr_study_kernel(4.0)) {
    return KfrMap(kW, kH, kfr_buffer_extent(kW, sigma), kfr_buffer_extent(kH, sigma), gaze, k);
}

TEST(KfrKernel, PowerKernelInvertsExactly) {
    const KfrKernel k = KfrKernel::power(4.0);
    for (double x = 0.0; x <= 1.0; x += 0.05) EXPECT_NEAR(k.inverse(k.eval(x)), x, 1e-12);
    EXPECT_DOUBLE_EQ(k.eval(0.0), 0.0);
    EXPECT_DOUBLE_EQ(k.eval(1.0), 1.0);
}

TEST(KfrKernel, PolynomialKernelInvertsByBisection) {
    auto k = KfrKernel::polynomial({0.0, 0.2, 0.3, 0.0, 0.5});  // 0.2x + 0.3x² + 0.5x⁴
    ASSERT_TRUE(k.ok());
    for (double x = 0.0; x <= 1.0; x += 0.05) EXPECT_NEAR(k->inverse(k->eval(x)), x, 1e-12);
    EXPECT_NEAR(k->eval(0.5), 0.2 * 0.5 + 0.3 * 0.25 + 0.5 * 0.0625, 1e-15);
}

TEST(KfrKernel, PolynomialKernelRejectsInvalidCoefficients) {
    EXPECT_FALSE(KfrKernel::polynomial({0.0, 0.5}).ok());        // K(1) != 1
    EXPECT_FALSE(KfrKernel::polynomial({0.1, 0.9}).ok());        // K(0) != 0
    EXPECT_FALSE(KfrKernel::polynomial({0.0, -0.5, 1.5}).ok());  // decreasing near 0
}

TEST(KfrMap, BufferIsReducedBySigma) {
    EXPECT_EQ(kfr_buffer_extent(1920, 1.8), 1067);
    EXPECT_EQ(kfr_buffer_extent(1080, 1.8), 600);
    EXPECT_EQ(kfr_buffer_extent(1920, 1.0), 1920);
}

TEST(KfrMap, LIsTheLogOfTheFarthestCorner) {
    EXPECT_NEAR(kfr_log_max_radius(kW, kH, {960, 540}), std::log(std::hypot(960.0, 540.0)), 1e-12);
    EXPECT_NEAR(kfr_log_max_radius(kW, kH, {100, 50}), std::log(std::hypot(1820.0, 1030.0)), 1e-12);
    EXPECT_NEAR(kfr_log_max_radius(kW, kH, {1900, 1000}), std::log(std::hypot(1900.0, 1000.0)),
                1e-12);
}

TEST(KfrMap, RoundTripRecoversScreenPoints) {
    for (Vec2d gaze : {Vec2d{960, 540}, Vec2d{10, 1070}, Vec2d{1500, 200}}) {
        const KfrMap m = make_map(gaze);
        for (double y = 0.5; y < kH; y += 37.0)
            for (double x = 0.5; x < kW; x += 41.0) {
                if (std::hypot(x - gaze.x, y - gaze.y) < 1.0) continue;  // clamped core
                const Vec2d lp = m.forward({x, y});
                const Vec2d back = m.inverse(lp);
                EXPECT_NEAR(back.x, x, 1e-6);
                EXPECT_NEAR(back.y, y, 1e-6);
            }
    }
}

TEST(KfrMap, PolynomialKernelRoundTrips) {
    auto k = KfrKernel::polynomial({0.0, 0.25, 0.0, 0.75});
    ASSERT_TRUE(k.ok());
    const KfrMap m = make_map({700, 300}, 1.6, *k);
    for (Vec2d p : {Vec2d{0, 0}, Vec2d{1919, 1079}, Vec2d{703, 301}, Vec2d{1200, 900}}) {
        const Vec2d back = m.inverse(m.forward(p));
        EXPECT_NEAR(back.x, p.x, 1e-6);
        EXPECT_NEAR(back.y, p.y, 1e-6);
    }
}

TEST(KfrMap, GazePointSingularityIsFinite) {
    const KfrMap m = make_map({960.25, 540.75});
    for (Vec2d p : {Vec2d{960.25, 540.75}, Vec2d{960.2500001, 540.75}, Vec2d{960.7, 540.9}}) {
        const Vec2d lp = m.forward(p);
        EXPECT_TRUE(std::isfinite(lp.x) && std::isfinite(lp.y));
        EXPECT_DOUBLE_EQ(lp.x, 0.0);  // within one pixel: the centre column
        EXPECT_GE(lp.y, 0.0);
        EXPECT_LT(lp.y, m.buffer_height());
    }
    const Vec2d centre = m.inverse({0.0, 0.0});
    EXPECT_TRUE(std::isfinite(centre.x) && std::isfinite(centre.y));
    EXPECT_NEAR(std::hypot(centre.x - 960.25, centre.y - 540.75), 1.0, 1e-12);
}

TEST(KfrMap, AngleSeamIsContinuousAcrossMinusPiToPi) {
    // Left of the gaze the angle crosses ±π: just above and below map to v ≈ h/2 on either side
    // (no jump to 0 or h), and just below/above the +x axis map near 0 and h, which a wrapping
    // sampler treats as neighbours.
    const KfrMap m = make_map({960, 540});
    const double h = m.buffer_height();
    const Vec2d above = m.forward({500, 540 - 1e-6});
    const Vec2d below = m.forward({500, 540 + 1e-6});
    EXPECT_NEAR(above.y, h / 2, 1e-3);
    EXPECT_NEAR(below.y, h / 2, 1e-3);
    const Vec2d right_up = m.forward({1500, 540 - 1e-6});
    const Vec2d right_down = m.forward({1500, 540 + 1e-6});
    const double wrapped = std::fmod(right_up.y - right_down.y + 1.5 * h, h) - 0.5 * h;
    EXPECT_NEAR(wrapped, 0.0, 1e-3);
    EXPECT_LT(right_up.y, h);
    EXPECT_GE(right_down.y, 0.0);
    // The inverse is periodic in v: v and v + h are the same screen point.
    const Vec2d a = m.inverse({300.0, 2.0});
    const Vec2d b = m.inverse({300.0, 2.0 + h});
    EXPECT_NEAR(a.x, b.x, 1e-9);
    EXPECT_NEAR(a.y, b.y, 1e-9);
}

TEST(KfrMap, FarthestCornerMapsToTheLastColumnOthersInside) {
    const Vec2d gaze{400, 300};
    const KfrMap m = make_map(gaze);
    const Vec2d far = m.forward({kW, kH});
    EXPECT_NEAR(far.x, m.buffer_width(), 1e-9);
    for (Vec2d c : {Vec2d{0, 0}, Vec2d{kW, 0}, Vec2d{0, kH}}) {
        const Vec2d lp = m.forward(c);
        EXPECT_GT(lp.x, 0.0);
        EXPECT_LT(lp.x, m.buffer_width());
    }
}

TEST(KfrMap, StudyKernelShiftsSamplesTowardsThePeriphery) {
    // Figs. 3–5: raising α gives the periphery a larger share of the LP buffer. With the study
    // kernel the screen radius at mid-buffer grows with α; the literal reading shrinks it.
    const Vec2d g{960, 540};
    auto mid_radius = [&](const KfrKernel& k) {
        const KfrMap m = make_map(g, 1.8, k);
        const Vec2d p = m.inverse({m.buffer_width() / 2.0, 0.0});
        return std::hypot(p.x - g.x, p.y - g.y);
    };
    const double classic = mid_radius(kfr_study_kernel(1.0));
    EXPECT_NEAR(classic, std::exp(0.5 * kfr_log_max_radius(kW, kH, g)), 1e-6);
    EXPECT_GT(mid_radius(kfr_study_kernel(4.0)), 5.0 * classic);
    EXPECT_LT(mid_radius(kfr_study_kernel(4.0, true)), classic / 5.0);
    // α = 4 keeps the fovea at >= 1 LP column per screen pixel out to 20 px (Fig. 4: quality
    // holds); α = 6 drops below it (Fig. 4: "when α >= 5 foveal quality suffers").
    const KfrMap a4 = make_map(g, 1.8, kfr_study_kernel(4.0));
    const KfrMap a6 = make_map(g, 1.8, kfr_study_kernel(6.0));
    const double u4 = a4.forward({g.x + 20.0, g.y}).x;
    const double u6 = a6.forward({g.x + 20.0, g.y}).x;
    EXPECT_LT(a4.radial_scale(u4), 1.0);
    EXPECT_GT(a6.radial_scale(u6), 1.0);
    EXPECT_GT(a4.radial_scale(a4.buffer_width() * 0.95), 1.0);  // periphery is reduced
}

TEST(KfrMap, OffscreenOrNanGazeIsClamped) {
    const KfrMap m = make_map({NAN, 1e9});
    const Vec2d lp = m.forward({100, 100});
    EXPECT_TRUE(std::isfinite(lp.x) && std::isfinite(lp.y));
}

}  // namespace
}  // namespace fovea::vk::methods
