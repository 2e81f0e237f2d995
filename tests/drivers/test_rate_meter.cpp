// RateMeter: the rate trackers that never state one actually deliver (Gazepoint, Pupil, OSC).
#include "fovea/drivers/rate_meter.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace {

using fovea::drivers::RateMeter;

TEST(RateMeter, NothingUntilAWholeWindowThenTheRate) {
    RateMeter m;
    for (int i = 0; i < RateMeter::kWindow; ++i) {
        m.add(100.0 + i / 400.0);
        EXPECT_EQ(m.rate_hz(), 0.0) << i;
    }
    m.add(100.0 + RateMeter::kWindow / 400.0);  // the window's last interval
    EXPECT_EQ(m.rate_hz(), 400.0);
}

TEST(RateMeter, GapsAndBurstsDoNotMoveIt) {
    RateMeter m;
    double t = 0;
    for (int i = 0; i < 4 * RateMeter::kWindow; ++i) {
        t += i % 40 == 39 ? 0.5 : 1.0 / 150.0;  // a reconnect every 40 samples
        m.add(t);
        if (i % 60 == 0) m.add(t + 1e-6);  // a datagram that came in a pair
    }
    EXPECT_EQ(m.rate_hz(), 150.0);
}

TEST(RateMeter, JitteredReceiptTimesGiveTheSendersRate) {
    RateMeter m;
    std::mt19937 rng(7);
    std::normal_distribution<double> jitter(0.0, 0.0004);  // 0.4 ms network jitter at 120 Hz
    for (int i = 0; i < 4 * RateMeter::kWindow; ++i) m.add(i / 120.0 + jitter(rng));
    EXPECT_NEAR(m.rate_hz(), 120.0, 2.0);
}

TEST(RateMeter, TimesThatAreNotFiniteOrGoBackAreSkipped) {
    RateMeter m;
    double t = 5.0;
    for (int i = 0; i < 2 * RateMeter::kWindow; ++i) {
        t += 0.001;
        m.add(t);
        if (i % 10 == 0) m.add(NAN);
        if (i % 17 == 0) m.add(t - 0.5);  // an older datum arriving late
        if (i % 23 == 0) m.add(INFINITY);
    }
    EXPECT_EQ(m.rate_hz(), 1000.0);
}

TEST(RateMeter, ARateChangeShowsWithinOneWindow) {
    RateMeter m;
    double t = 0;
    for (int i = 0; i < 2 * RateMeter::kWindow + 1; ++i) m.add(t += 1.0 / 60.0);
    EXPECT_EQ(m.rate_hz(), 60.0);
    for (int i = 0; i < RateMeter::kWindow; ++i) m.add(t += 1.0 / 2000.0);
    EXPECT_EQ(m.rate_hz(), 2000.0);
}

}  // namespace
