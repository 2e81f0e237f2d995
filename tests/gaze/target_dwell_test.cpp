#include "fovea/gaze/target_dwell.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

namespace fovea::gaze {
namespace {

constexpr int64_t kMs = 1'000'000;

// 1 kHz samples in degrees; where(t_ms, x, y) sets the gaze and returns false for a lost sample.
template <typename Where>
std::vector<TargetSample> record(int ms, Where where) {
    std::vector<TargetSample> out;
    uint32_t seed = 7;
    const auto noise = [&] {
        seed = seed * 1664525u + 1013904223u;
        return (static_cast<double>(seed >> 8) / 16777216.0 - 0.5) * 0.1;
    };
    for (int t = 0; t < ms; ++t) {
        TargetSample s;
        s.t_ns = t * kMs;
        double x = 0, y = 0;
        if (where(t, x, y)) {
            for (EyeSample* e : {&s.left, &s.right}) {
                e->x = x + noise();
                e->y = y + noise();
                e->valid = true;
            }
        }
        out.push_back(s);
    }
    return out;
}

double offset_deg(const TargetSample& s, double tx, double ty) {
    return std::hypot(s.left.x - tx, s.left.y - ty);
}

TEST(TargetDwell, KeepsTheSettledDwellAfterALateArrivalAndNothingNearTheLids) {
    // The eyes leave 8 deg away at 150 ms, land at 200 ms; a blink loses 300-339 ms and the
    // lids drag the gaze down by up to 3 deg for 20 ms before and 40 ms after.
    const auto samples = record(500, [](int t, double& x, double& y) {
        x = t < 150 ? -8.0 : t < 200 ? -8.0 + 8.0 * (t - 150) / 50.0 : 0.0;
        if (t >= 300 && t < 340) return false;
        const double occlusion = t >= 280 && t < 300   ? (t - 280) / 20.0
                                 : t >= 340 && t < 380 ? (380 - t) / 40.0
                                                       : 0.0;
        y = 3.0 * occlusion * occlusion;
        return true;
    });
    const TargetDwell d = target_dwell(samples, true, true);
    EXPECT_EQ(d.lost, 40u);
    EXPECT_EQ(d.lid, 30u + 60u) << "30 ms before the loss, 60 ms after";
    ASSERT_FALSE(d.keep.empty());
    for (size_t i : d.keep) {
        EXPECT_GE(samples[i].t_ns, 230 * kMs) << "the saccade is over and has settled";
        EXPECT_FALSE(samples[i].t_ns >= 270 * kMs && samples[i].t_ns < 400 * kMs) << i;
        EXPECT_LT(offset_deg(samples[i], 0, 0), 0.2) << i;
    }
    EXPECT_GE(d.keep.size(), 35u + 100u);
    EXPECT_EQ(d.keep.size() + d.unsettled + d.lid + d.lost, samples.size());
    EXPECT_NEAR(d.dwell_s, 0.499 - 0.231, 0.005);
}

TEST(TargetDwell, ADwellShorterThanAFixationKeepsNothing) {
    const auto samples = record(400, [](int t, double& x, double&) {
        x = t < 330 ? 6.0 : 0.0;  // arrives 70 ms before the collection ends
        return true;
    });
    const TargetDwell d = target_dwell(samples, true, true);
    EXPECT_TRUE(d.keep.empty());
    EXPECT_EQ(d.unsettled, samples.size());
    EXPECT_NEAR(d.dwell_s, 0.069 - 0.040, 0.002) << "after the landing's settling";
}

TEST(TargetDwell, AOneSampleSpikeAndASmallMicrosaccadeDoNotEndTheDwell) {
    const auto samples = record(300, [](int t, double& x, double& y) {
        x = t == 150 ? 3.0 : t >= 200 ? 0.6 : 0.0;
        y = 0;
        return true;
    });
    const TargetDwell d = target_dwell(samples, true, true);
    EXPECT_EQ(d.keep.size(), 299u);
    EXPECT_EQ(d.unsettled, 1u);
    EXPECT_NEAR(d.dwell_s, 0.299, 0.001);
}

TEST(TargetDwell, OneEyeLostIsNoBlinkAndAnUnusedEyeIsIgnored) {
    auto samples = record(200, [](int, double&, double&) { return true; });
    for (auto& s : samples) s.right = EyeSample{};
    TargetDwell d = target_dwell(samples, true, true);
    EXPECT_EQ(d.lost, 0u);
    EXPECT_EQ(d.keep.size(), samples.size());
    d = target_dwell(samples, false, true);  // calibrating the right eye only
    EXPECT_EQ(d.lost, samples.size());
    EXPECT_TRUE(d.keep.empty());
}

TEST(TargetDwell, ANoisyTrackerWidensTheRadiusInsteadOfEndingTheDwell) {
    uint32_t seed = 11;
    const auto gauss = [&] {  // sum of 12 uniforms: SD 1
        double s = -6;
        for (int k = 0; k < 12; ++k) {
            seed = seed * 1664525u + 1013904223u;
            s += static_cast<double>(seed >> 8) / 16777216.0;
        }
        return s;
    };
    const auto samples = record(500, [&](int, double& x, double& y) {
        x = 0.8 * gauss();  // 0.8 deg per axis: a noisy consumer tracker's sample noise
        y = 0.8 * gauss();
        return true;
    });
    TargetDwellRules fixed_radius;
    fixed_radius.noise_radius_factor = 0;
    EXPECT_LT(target_dwell(samples, true, true, fixed_radius).dwell_s, 0.4)
        << "the test's noise does cross 1.5 deg twice in a row";
    const TargetDwell d = target_dwell(samples, true, true);
    EXPECT_NEAR(d.dwell_s, 0.499, 0.001);
    EXPECT_EQ(d.keep.size(), samples.size());
}

TEST(TargetDwell, NothingOrOnlyLostSamplesKeepNothing) {
    EXPECT_TRUE(target_dwell({}, true, true).keep.empty());
    const auto lost = record(100, [](int, double&, double&) { return false; });
    const TargetDwell d = target_dwell(lost, true, true);
    EXPECT_TRUE(d.keep.empty());
    EXPECT_EQ(d.lost, 100u);
}

TEST(TargetDwell, KnowingThePreviousTargetTheLongestDwellWinsOverAnEarlyDeparture) {
    // From the previous target (-8, 0) to this one at 100-150 ms; 830-850 ms the eyes leave for
    // (6, 0) (a glance, or anticipating the next target) and stay 150 ms.
    const auto samples = record(1000, [](int t, double& x, double&) {
        x = t < 100   ? -8.0
            : t < 150 ? -8.0 + 8.0 * (t - 100) / 50.0
            : t < 830 ? 0.0
            : t < 850 ? 6.0 * (t - 830) / 20.0
                      : 6.0;
        return true;
    });
    TargetSample previous;
    previous.left = previous.right = EyeSample{-8.0, 0.0, 0.0, true};
    const TargetDwell d = target_dwell(samples, true, true, {}, &previous);
    ASSERT_FALSE(d.keep.empty());
    int leaving = 0;  // the departure's first ms, still within the dwell's radius
    for (size_t i : d.keep) {
        EXPECT_GE(samples[i].t_ns, 181 * kMs) << "within 1.5 deg at 141 ms, settled 40 ms later";
        if (samples[i].t_ns >= 830 * kMs) {
            ++leaving;
            EXPECT_LT(offset_deg(samples[i], 0, 0), 1.5) << i;
        } else {
            EXPECT_LT(offset_deg(samples[i], 0, 0), 0.2) << i;
        }
    }
    EXPECT_LE(leaving, 5);
    EXPECT_GE(d.keep.size(), 650u);
    EXPECT_NEAR(d.dwell_s, 0.834 - 0.181, 0.003);
    EXPECT_TRUE(d.at.left.valid);
    EXPECT_NEAR(d.at.left.x, 0.0, 0.05);
    // Not knowing where the eyes came from, the final dwell: the departure.
    const TargetDwell blind = target_dwell(samples, true, true);
    ASSERT_FALSE(blind.keep.empty());
    EXPECT_GE(samples[blind.keep.front()].t_ns, 850 * kMs);
    EXPECT_NEAR(blind.at.left.x, 6.0, 0.05);
}

TEST(TargetDwell, TheEyesStillAtThePreviousTargetAreNotTheDwellThoughLonger) {
    // A late arrival: 250 ms still at the previous target, 180 ms at this one.
    const auto samples = record(450, [](int t, double& x, double&) {
        x = t < 250 ? -8.0 : t < 270 ? -8.0 + 8.0 * (t - 250) / 20.0 : 0.0;
        return true;
    });
    TargetSample previous;
    previous.left = previous.right = EyeSample{-8.3, 0.2, 0.0, true};
    const TargetDwell d = target_dwell(samples, true, true, {}, &previous);
    ASSERT_FALSE(d.keep.empty());
    EXPECT_GE(samples[d.keep.front()].t_ns, 300 * kMs);
    EXPECT_NEAR(d.at.left.x, 0.0, 0.05);
}

TEST(TargetDwell, WhenEveryDwellIsAtThePreviousTargetTheFinalOneIsKept) {
    // The same target shown twice: the eyes never move.
    const auto samples = record(300, [](int, double& x, double&) {
        x = 2.0;
        return true;
    });
    TargetSample previous;
    previous.left = previous.right = EyeSample{2.0, 0.0, 0.0, true};
    const TargetDwell d = target_dwell(samples, true, true, {}, &previous);
    EXPECT_EQ(d.keep.size(), samples.size());
    EXPECT_EQ(d.keep, target_dwell(samples, true, true).keep);
}

}  // namespace
}  // namespace fovea::gaze
