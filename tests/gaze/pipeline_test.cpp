#include "fovea/gaze/pipeline.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "synthetic.hpp"

namespace fovea::gaze {
namespace {

// Sample i of a synthetic 1 kHz recording as a tracker would deliver it: a 1 MHz device counter,
// received 200 us after capture, both eyes at the recording's position.
RawSample synthetic_raw(const test::Synthetic& s, size_t i, const DisplayGeometry& display) {
    RawSample r;
    r.device_ticks = static_cast<uint64_t>(i) * 1000;
    r.t_receive_ns = 1'000'000'000 + static_cast<int64_t>(i) * 1'000'000 + 200'000;
    r.left.valid = r.right.valid = s.in[i].valid;
    if (s.in[i].valid) {
        display.to_normalized(s.in[i].x_deg, s.in[i].y_deg, r.left.x, r.left.y);
        r.right = r.left;
    }
    return r;
}

// The chain as fovead builds it for that tracker: 1 kHz, the 32-bit 1 MHz counter.
PipelineConfig synthetic_config() {
    PipelineConfig c;
    c.nominal_rate_hz = 1000.0;
    c.clock = DeviceClock{32, 1e6};
    return c;
}

TEST(Pipeline, EverySampleComesOutOnceInOrderWithBoundedDelay) {
    const PipelineConfig c = synthetic_config();
    Pipeline p(c);
    const auto s = test::make_synthetic(1000.0);
    std::vector<GazeSample> out;
    size_t emitted = 0;
    int64_t last_t = INT64_MIN;
    bool saw_landing = false;
    for (size_t i = 0; i < s.in.size(); ++i) {
        const RawSample r = synthetic_raw(s, i, c.display);
        p.process(r, out);
        for (const auto& g : out) {
            EXPECT_GT(g.t_capture_ns, last_t);
            last_t = g.t_capture_ns;
            if (g.combined.valid) {
                EXPECT_TRUE(std::isfinite(g.combined_deg_x));
                EXPECT_TRUE(std::isfinite(g.combined.x));
            }
            saw_landing |= g.saccade.landing_valid;
        }
        emitted += out.size();
        EXPECT_LE(i + 1 - emitted, static_cast<size_t>(p.lookahead_samples()) + 1);
    }
    p.flush(out);
    emitted += out.size();
    EXPECT_EQ(emitted, s.in.size());
    EXPECT_TRUE(saw_landing);
    EXPECT_EQ(p.stats().samples_in, s.in.size());
}

// A tracker that pauses (a server restart, an unplugged cable) must not keep its last samples
// back until it resumes: settle() decides every held sample at once, and the chain then goes on
// with its look-ahead as before, each sample out exactly once and in order.
TEST(Pipeline, SettleReleasesHeldSamplesAndTheChainGoesOn) {
    const PipelineConfig c = synthetic_config();
    Pipeline p(c);
    const auto s = test::make_synthetic(1000.0);
    ASSERT_GT(s.in.size(), 3000u);
    std::vector<GazeSample> out;
    std::vector<int64_t> captured;
    auto take = [&] {
        for (const auto& g : out) captured.push_back(g.t_capture_ns);
    };
    const size_t pause_at = 1500;
    for (size_t i = 0; i < pause_at; ++i) {
        p.process(synthetic_raw(s, i, c.display), out);
        take();
    }
    ASSERT_GT(pause_at - captured.size(), 10u) << "the look-ahead holds samples back";
    p.settle(out);
    take();
    EXPECT_EQ(captured.size(), pause_at) << "settle leaves nothing held";
    p.settle(out);
    EXPECT_TRUE(out.empty()) << "a second settle has nothing to add";

    size_t held_max = 0;
    for (size_t i = pause_at; i < s.in.size(); ++i) {
        p.process(synthetic_raw(s, i, c.display), out);
        take();
        held_max = std::max(held_max, i + 1 - captured.size());
    }
    EXPECT_GT(held_max, 10u) << "after the pause the look-ahead works again";
    EXPECT_LE(held_max, static_cast<size_t>(p.lookahead_samples()) + 1);
    p.flush(out);
    take();
    ASSERT_EQ(captured.size(), s.in.size());
    for (size_t i = 1; i < captured.size(); ++i) ASSERT_GT(captured[i], captured[i - 1]) << i;
}

// The live path (fovead publish = "live"): the newest sample is there right after process(),
// finite, with causal labels only; the look-ahead's final labels arrive later through `out`.
TEST(Pipeline, LatestIsTheNewestSampleWithCausalLabels) {
    const PipelineConfig c = synthetic_config();
    Pipeline p(c);
    GazeSample live;
    EXPECT_FALSE(p.latest(live));
    const auto s = test::make_synthetic(1000.0);
    std::vector<GazeSample> out;
    int live_saccades_in_true_saccade = 0, live_saccades = 0, true_saccade_samples = 0;
    bool saw_onset_before = false;
    for (size_t i = 0; i < s.in.size(); ++i) {
        const RawSample r = synthetic_raw(s, i, c.display);
        p.process(r, out);
        ASSERT_TRUE(p.latest(live));
        EXPECT_EQ(live.t_receive_ns, r.t_receive_ns);  // this very sample, not a held one
        EXPECT_GE(live.t_processed_ns, 0);
        EXPECT_NE(live.event, Event::kFixation);  // never invented causally
        EXPECT_NE(live.event, Event::kPso);
        if (!s.in[i].valid) {
            EXPECT_FALSE(live.combined.valid);
            EXPECT_EQ(live.event, Event::kBlink);
        } else {
            ASSERT_TRUE(live.combined.valid);
            EXPECT_TRUE(std::isfinite(live.combined.x) && std::isfinite(live.combined.y));
            EXPECT_TRUE(std::isfinite(live.combined_deg_x) && std::isfinite(live.combined_deg_y));
        }
        if (s.truth[i] == Event::kSaccade) ++true_saccade_samples;
        if (live.event == Event::kSaccade) {
            ++live_saccades;
            live_saccades_in_true_saccade += s.truth[i] == Event::kSaccade;
            saw_onset_before |=
                live.saccade.onset_ns > 0 && live.saccade.onset_ns <= live.t_capture_ns;
            if (live.saccade.landing_valid) {
                EXPECT_TRUE(std::isfinite(live.saccade.landing_x) &&
                            std::isfinite(live.saccade.landing_y));
            }
        }
    }
    ASSERT_GT(true_saccade_samples, 0);
    // The generated saccade is flagged while in flight, at most samples of its true duration.
    EXPECT_GE(live_saccades_in_true_saccade, true_saccade_samples / 2);
    EXPECT_GE(live_saccades_in_true_saccade * 10, live_saccades * 7);
    EXPECT_TRUE(saw_onset_before);
}

TEST(Pipeline, LatestNeverCarriesNaNForGarbageInput) {
    PipelineConfig c;
    Pipeline p(c);
    std::vector<GazeSample> out;
    GazeSample live;
    const double garbage[] = {kNaN, INFINITY, -INFINITY, 1e300, 0.5};
    for (int i = 0; i < 200; ++i) {
        RawSample r;
        r.device_ticks = static_cast<uint64_t>(i) * 1'000'000;
        r.t_receive_ns = 1'000'000'000 + int64_t{i} * 1'000'000;
        r.left = EyeSample{garbage[i % 5], garbage[(i + 2) % 5], 3.0, i % 3 != 0};
        r.right = EyeSample{garbage[(i + 1) % 5], garbage[(i + 3) % 5], 3.0, i % 4 != 0};
        p.process(r, out);
        ASSERT_TRUE(p.latest(live));
        if (live.combined.valid) {
            EXPECT_TRUE(std::isfinite(live.combined.x) && std::isfinite(live.combined.y));
        } else {
            EXPECT_EQ(live.event, Event::kBlink);
        }
        EXPECT_TRUE(std::isfinite(live.clock_uncertainty_us));
    }
}

TEST(Pipeline, CalibrationIsAppliedAndFlagged) {
    PipelineConfig c;
    Pipeline p(c);
    Calibration cal;
    for (int gy = 0; gy < 3; ++gy) {
        for (int gx = 0; gx < 3; ++gx) {
            EyeSample e{2.0 * (0.1 + 0.4 * gx), 2.0 * (0.1 + 0.4 * gy), 0.0, true};
            for (int k = 0; k < 5; ++k) cal.add_sample(0.1 + 0.4 * gx, 0.1 + 0.4 * gy, e, e);
        }
    }
    ASSERT_TRUE(cal.fit().ok());
    p.set_calibration(cal);
    std::vector<GazeSample> out, all;
    for (int i = 0; i < 500; ++i) {
        RawSample r;
        r.device_ticks = static_cast<uint64_t>(i) * 1'000'000;
        r.t_receive_ns = static_cast<int64_t>(i) * 1'000'000;
        r.left = {1.0, 1.0, 0.0, true};  // raw (1,1) -> display (0.5,0.5)
        p.process(r, out);
        all.insert(all.end(), out.begin(), out.end());
    }
    p.flush(out);
    all.insert(all.end(), out.begin(), out.end());
    ASSERT_EQ(all.size(), 500u);
    EXPECT_TRUE(all.back().calibrated);
    EXPECT_NEAR(all.back().left.x, 0.5, 1e-6);
    EXPECT_FALSE(all.back().right.valid);
}

}  // namespace
}  // namespace fovea::gaze
