#include "fovea/gaze/event_detector.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "synthetic.hpp"

namespace fovea::gaze {
namespace {

std::vector<Event> run(const test::Synthetic& s, DetectorMode mode, double rate,
                       size_t* max_held = nullptr) {
    std::vector<Event> out;
    if (mode == DetectorMode::kOffline) {
        for (const auto& o : EventDetector::detect_offline(s.in, {}, rate)) out.push_back(o.event);
        return out;
    }
    EventDetector d({}, rate, mode);
    DetectorOutput o;
    for (size_t i = 0; i < s.in.size(); ++i) {
        d.push(s.in[i]);
        while (d.pop(o)) {
            EXPECT_EQ(o.index, static_cast<int64_t>(out.size()));
            out.push_back(o.event);
        }
        if (max_held) *max_held = std::max(*max_held, i + 1 - out.size());
    }
    d.flush();
    while (d.pop(o)) out.push_back(o.event);
    return out;
}

double agreement(const std::vector<Event>& a, const std::vector<Event>& b, Event e) {
    size_t both = 0, any = 0;
    for (size_t i = 0; i < a.size() && i < b.size(); ++i) {
        both += (a[i] == e && b[i] == e);
        any += (a[i] == e || b[i] == e);
    }
    return any ? static_cast<double>(both) / static_cast<double>(any) : 1.0;
}

class EventDetectorRates : public ::testing::TestWithParam<double> {};

TEST_P(EventDetectorRates, FindsSaccadePursuitFixationAndBlink) {
    const double rate = GetParam();
    const auto s = test::make_synthetic(rate);
    for (auto mode : {DetectorMode::kOffline, DetectorMode::kOnline}) {
        const auto ev = run(s, mode, rate);
        ASSERT_EQ(ev.size(), s.in.size());
        // Overlap (intersection over union) per event with the truth.
        EXPECT_GT(agreement(ev, s.truth, Event::kSaccade), 0.6) << "rate " << rate;
        EXPECT_GT(agreement(ev, s.truth, Event::kPursuit), 0.65) << "rate " << rate;
        EXPECT_GT(agreement(ev, s.truth, Event::kFixation), 0.8) << "rate " << rate;
        EXPECT_GT(agreement(ev, s.truth, Event::kBlink), 0.5) << "rate " << rate;
    }
}

INSTANTIATE_TEST_SUITE_P(Rates, EventDetectorRates,
                         ::testing::Values(250.0, 500.0, 1000.0, 2000.0));

TEST(EventDetector, OnlineHoldsAtMostItsReportedLookahead) {
    const auto s = test::make_synthetic(1000.0);
    EventDetector d({}, 1000.0, DetectorMode::kOnline);
    size_t held = 0;
    run(s, DetectorMode::kOnline, 1000.0, &held);
    EXPECT_LE(held, static_cast<size_t>(d.lookahead_samples()) + 1);
    EXPECT_GT(d.lookahead_samples(), 0);
}

TEST(EventDetector, SaccadeRecordCarriesAmplitudeAndDirection) {
    const auto s = test::make_synthetic(1000.0);
    bool seen = false;
    for (const auto& o : EventDetector::detect_offline(s.in, {}, 1000.0)) {
        if (o.event != Event::kSaccade) continue;
        seen = true;
        EXPECT_NEAR(o.saccade.amplitude_deg, 10.0, 1.0);
        EXPECT_NEAR(o.saccade.direction_deg, 0.0, 5.0);
        EXPECT_GT(o.saccade.peak_velocity_dps, 300.0);
        EXPECT_NEAR(o.saccade.onset_ns * 1e-9, 1.0, 0.01);
        break;
    }
    EXPECT_TRUE(seen);
}

TEST(EventDetector, GarbageInputIsLabelledNotPropagated) {
    EventDetector d({}, 500.0, DetectorMode::kOnline);
    DetectorOutput o;
    size_t out = 0;
    for (int i = 0; i < 5000; ++i) {
        DetectorInput in;
        in.t_s = (i % 97 == 0) ? std::nan("") : (i % 89 == 0 ? 0.0 : i * 0.002);  // bad stamps
        in.valid = i % 13 != 0;
        in.x_deg = (i % 31 == 0) ? 1e300 : 0.01 * (i % 7);
        in.y_deg = (i % 37 == 0) ? INFINITY : 0.0;
        d.push(in);
        while (d.pop(o)) ++out;
    }
    d.flush();
    while (d.pop(o)) ++out;
    EXPECT_EQ(out, 5000u);
}

}  // namespace
}  // namespace fovea::gaze
