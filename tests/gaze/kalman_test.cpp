#include "fovea/gaze/kalman.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace fovea::gaze {
namespace {

TEST(KalmanCv, TracksConstantVelocityWithVariableDt) {
    KalmanCv k({10.0, 0.05, 0.5, 1000.0});
    double t = 0.0, last = 0.0;
    for (int i = 0; i < 2000; ++i) {
        t += (i % 3 == 0) ? 0.0005 : 0.0015;
        const double noise = 0.05 * std::sin(i * 12.9898);
        last = k.filter(10.0 * t + noise, t);
    }
    EXPECT_NEAR(last, 10.0 * t, 0.05);
    EXPECT_NEAR(k.velocity(), 10.0, 1.0);
}

TEST(KalmanCv, NanAndZeroDtNeverPoisonState) {
    KalmanCv k;
    k.filter(1.0, 0.0);
    EXPECT_TRUE(std::isnan(k.filter(std::nan(""), 0.001)));
    EXPECT_TRUE(std::isnan(k.filter(INFINITY, 0.002)));
    const double a = k.filter(1.0, 0.002);
    const double b = k.filter(1.0, 0.002);  // dt = 0: pure measurement update
    EXPECT_TRUE(std::isfinite(a));
    EXPECT_TRUE(std::isfinite(b));
    EXPECT_NEAR(b, 1.0, 0.01);
}

TEST(KalmanCv, HugeOutlierDoesNotDiverge) {
    KalmanCv k;
    for (int i = 0; i < 100; ++i) k.filter(0.0, i * 0.001);
    k.filter(1e12, 0.1);
    double v = 0;
    for (int i = 0; i < 2000; ++i) v = k.filter(0.0, 0.101 + i * 0.001);
    EXPECT_TRUE(std::isfinite(v));
    EXPECT_NEAR(v, 0.0, 1e-3);
}

}  // namespace
}  // namespace fovea::gaze
