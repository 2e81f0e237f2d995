#include "fovea/gaze/landing.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace fovea::gaze {
namespace {

// A minimum-jerk saccade on the main sequence the predictor assumes, with noise: from its
// first half the landing point must be within 15 % of the amplitude, far closer than the
// current position (half the amplitude away). Not exact: the deceleration estimate assumes a
// slow-down between linear and early-peaked (landing.hpp), minimum jerk is neither; the
// simulated tracker's skewed profiles are checked in sim_eval_test.cpp.
TEST(LandingPredictor, PredictsMainSequenceSaccadeFromHalfItsDuration) {
    LandingPredictor p;
    for (double amp : {3.0, 6.0, 12.0, 20.0}) {
        const double dur = p.duration_s(amp);
        std::vector<double> t, x, y;
        uint32_t s = 3;
        for (double u = 0; u <= 0.5 * dur; u += 0.001) {
            s = s * 1664525u + 1013904223u;
            const double n = (static_cast<double>(s >> 8) / 16777216.0 - 0.5) * 0.04;
            t.push_back(u);
            x.push_back(2.0 + 0.8 * amp * p.profile(u / dur, amp) + n);
            y.push_back(-1.0 + 0.6 * amp * p.profile(u / dur, amp));
        }
        const LandingEstimate e = p.predict(t, x, y);
        ASSERT_TRUE(e.valid);
        const double err = std::hypot(e.x_deg - (2.0 + 0.8 * amp), e.y_deg - (-1.0 + 0.6 * amp));
        EXPECT_LT(err, std::max(0.3, 0.15 * amp)) << amp;
        EXPECT_GT(e.uncertainty_deg, 0.0) << amp;
    }
}

TEST(LandingPredictor, UncertaintyShrinksAsSaccadeProgresses) {
    LandingPredictor p;
    const double amp = 10.0, dur = p.duration_s(amp);
    double last = 1e9;
    for (double frac : {0.25, 0.5, 0.75, 0.95}) {
        std::vector<double> t, x, y;
        for (double u = 0; u <= frac * dur; u += 0.0005) {
            t.push_back(u);
            x.push_back(amp * p.profile(u / dur, amp));
            y.push_back(0.0);
        }
        const LandingEstimate e = p.predict(t, x, y);
        ASSERT_TRUE(e.valid);
        EXPECT_LT(e.uncertainty_deg, last) << frac;
        last = e.uncertainty_deg;
    }
}

TEST(LandingPredictor, DegenerateInputIsInvalid) {
    LandingPredictor p;
    std::vector<double> t{0.0}, x{1.0}, y{1.0};
    EXPECT_FALSE(p.predict(t, x, y).valid);
    std::vector<double> t2{0.0, 0.001}, x2{1.0, std::nan("")}, y2{1.0, 1.0};
    EXPECT_FALSE(p.predict(t2, x2, y2).valid);
}

}  // namespace
}  // namespace fovea::gaze
