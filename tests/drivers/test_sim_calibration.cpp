// The simulated tracker's calibration aids: eyes that fixate a shown target (look_at) and the
// documented raw-output distortion.
#include <gtest/gtest.h>

#include <cmath>

#include "fovea/drivers/driver.hpp"
#include "sim/sim_driver.hpp"
#include "sim/sim_tracker.hpp"

namespace fovea::drivers::sim {
namespace {

using gaze::Event;

TEST(SimCalibration, EyesFixateTheTargetAfterASaccadicLatencyUntilReleased) {
    SimConfig c;
    c.seed = 5;
    c.blink_rate_hz = 0;
    SimTracker sim(c);
    for (int i = 0; i < 200; ++i) sim.next();
    sim.look_at(8.0, -4.0);
    EXPECT_TRUE(sim.has_target());
    int first_saccade_ms = -1;
    double worst_late = 0;
    for (int ms = 0; ms < 3000; ++ms) {
        const auto f = sim.next();
        if (first_saccade_ms < 0 && f.truth.in_saccade &&
            std::fabs(f.truth.landing_x_deg - 8.0) < 1e-9)
            first_saccade_ms = ms;
        // After latency + saccade + PSO the gaze stays on the target (fixational drift only).
        if (ms > 400)
            worst_late = std::max(worst_late, std::hypot(f.truth.x_deg - 8.0, f.truth.y_deg + 4.0));
        if (ms > 400) { EXPECT_NE(f.truth.event, Event::kPursuit) << ms; }
    }
    EXPECT_GE(first_saccade_ms, 145);
    EXPECT_LE(first_saccade_ms, 260);
    EXPECT_LT(worst_late, 0.6);
    sim.release();
    EXPECT_FALSE(sim.has_target());
    double farthest = 0;
    for (int ms = 0; ms < 8000; ++ms) {
        const auto f = sim.next();
        farthest = std::max(farthest, std::hypot(f.truth.x_deg - 8.0, f.truth.y_deg + 4.0));
    }
    EXPECT_GT(farthest, 2.0) << "free viewing resumes after release()";
}

TEST(SimCalibration, DistortionIsTheDocumentedPolynomialOnTheSameSamples) {
    SimConfig plain;
    plain.seed = 9;
    SimConfig bent = plain;
    bent.distortion = 1.0;
    SimTracker a(plain), b(bent);
    double worst = 0, mean_shift = 0;
    int n = 0;
    for (int i = 0; i < 2000; ++i) {
        const auto fa = a.next(), fb = b.next();
        ASSERT_EQ(fa.raw.left.valid, fb.raw.left.valid);
        if (!fa.raw.left.valid) continue;
        for (bool right : {false, true}) {
            const gaze::EyeSample& ea = right ? fa.raw.right : fa.raw.left;
            const gaze::EyeSample& eb = right ? fb.raw.right : fb.raw.left;
            double x = ea.x, y = ea.y;
            distort(1.0, right, x, y);
            worst = std::max({worst, std::fabs(x - eb.x), std::fabs(y - eb.y)});
            double d0x, d0y, d1x, d1y;
            plain.display.to_degrees(ea.x, ea.y, d0x, d0y);
            plain.display.to_degrees(eb.x, eb.y, d1x, d1y);
            mean_shift += std::hypot(d1x - d0x, d1y - d0y);
            ++n;
        }
    }
    EXPECT_LT(worst, 1e-12);
    mean_shift /= n;
    EXPECT_GT(mean_shift, 1.5) << "S = 1 moves raw gaze by degrees";
    EXPECT_LT(mean_shift, 4.0);
    // Off means off.
    double x = 0.3, y = 0.6;
    distort(0.0, true, x, y);
    EXPECT_EQ(x, 0.3);
    EXPECT_EQ(y, 0.6);
}

TEST(SimCalibration, DriverFollowsTargetsAndRejectsABadDistortion) {
    toml::table t{{"driver", "sim"}, {"distortion", 0.5}};
    auto d = make_driver(t, 0);
    ASSERT_TRUE(d.ok()) << d.error().message;
    EXPECT_TRUE((*d)->follow_target(true, 0.2, 0.3));
    EXPECT_TRUE((*d)->follow_target(false, 0, 0));
    toml::table bad{{"driver", "sim"}, {"distortion", 5.0}};
    auto e = make_driver(bad, 0);
    ASSERT_FALSE(e.ok());
    EXPECT_NE(e.error().message.find("distortion"), std::string::npos) << e.error().message;
}

}  // namespace
}  // namespace fovea::drivers::sim
