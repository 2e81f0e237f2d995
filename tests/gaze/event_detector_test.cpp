#include "fovea/gaze/event_detector.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
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
        // 0.79 since stop 41 (above 0.80 before): the synthetic's noise is white, so the pursuit
        // floor no longer rises above the 1-deg bound, and the pursuit's abrupt start and stop
        // smear ~150 ms into the fixations around them (daemon/gaze/README.md).
        EXPECT_GT(agreement(ev, s.truth, Event::kFixation), 0.75) << "rate " << rate;
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

// Scripted gaze at 500 Hz (the lund2013 rate) with ~0.01 deg noise; positions per sample.
struct Script {
    std::vector<DetectorInput> in;
    uint64_t seed = 11;
    double x = 0.0, y = 0.0;
    static constexpr double kRate = 500.0;
    void sample() {
        DetectorInput d;
        d.t_s = static_cast<double>(in.size()) / kRate;
        d.valid = true;
        d.x_deg = x + 0.01 * test::noise(seed);
        d.y_deg = y + 0.01 * test::noise(seed);
        in.push_back(d);
    }
    void fixate(double secs) {
        for (int i = 0; i < std::lround(secs * kRate); ++i) sample();
    }
    // Minimum-jerk saccade along x over the main-sequence duration of `amp`, ending at
    // x0 + amp + overshoot; y moves at y_dps over its last `hook_samples` samples.
    void saccade(double amp, double overshoot = 0.0, double y_dps = 0.0, int hook_samples = 0) {
        const double x0 = x, dur = (2.6 * amp + 17.0) * 1e-3;
        const int n = static_cast<int>(std::lround(dur * kRate));
        for (int i = 1; i <= n; ++i) {
            const double tau = static_cast<double>(i) / n;
            x = x0 + (amp + overshoot) * tau * tau * tau * (10 - 15 * tau + 6 * tau * tau);
            if (i > n - hook_samples) y += y_dps / kRate;
            sample();
        }
    }
    // Smooth movement at (vx, vy) deg/s.
    void pursue(double secs, double vx, double vy = 0.0) {
        for (int i = 0; i < std::lround(secs * kRate); ++i) {
            x += vx / kRate;
            y += vy / kRate;
            sample();
        }
    }
    void lose(int samples) {
        for (int i = 0; i < samples; ++i) {
            DetectorInput d;
            d.t_s = static_cast<double>(in.size()) / kRate;
            in.push_back(d);
        }
    }
    size_t size() const { return in.size(); }
};

std::vector<DetectorOutput> detect(const Script& s) {
    return EventDetector::detect_offline(s.in, {}, Script::kRate);
}

// Pursuit that speeds up past the peak threshold (35 deg/s against the 30 deg/s threshold of a
// quiet tracker) and slows down again is still pursuit: a saccade is judged on the speed
// relative to the eye's own motion just before it.
TEST(EventDetector, FastPursuitIsNoSaccade) {
    Script s;
    s.fixate(3.0);
    const size_t pursuit_start = s.size();
    double speed = 0.0;
    auto pursue = [&](double secs, double accel_dps2) {
        for (int i = 0; i < std::lround(secs * Script::kRate); ++i) {
            speed = std::clamp(speed + accel_dps2 / Script::kRate, 0.0, 35.0);
            s.y += speed / Script::kRate;
            s.sample();
        }
    };
    pursue(0.6, 150.0);  // 0 -> 35 deg/s over 233 ms, then steady
    pursue(0.4, -150.0);
    const size_t pursuit_end = s.size();
    s.fixate(3.0);

    // The thresholds of a quiet tracker whose recording is mostly fixation (N&H over this
    // short script would rise above the pursuit's speed).
    auto saccade_samples = [&](const DetectorParams& p) {
        EventDetector d(p, Script::kRate, DetectorMode::kOffline);
        d.set_thresholds({30.0, 15.0, 0.01});
        std::vector<DetectorOutput> out;
        DetectorOutput o;
        for (const auto& in : s.in) {
            d.push(in);
            while (d.pop(o)) out.push_back(o);
        }
        d.flush();
        while (d.pop(o)) out.push_back(o);
        EXPECT_EQ(out.size(), s.size());
        int n = 0;
        for (size_t i = pursuit_start; i < pursuit_end && i < out.size(); ++i)
            n += out[i].event == Event::kSaccade;
        return n;
    };
    EXPECT_EQ(saccade_samples({}), 0);
    // The absolute speed (the old rule) takes the fast pursuit for saccades.
    DetectorParams absolute;
    absolute.relative_window_s = 0.0;
    EXPECT_GT(saccade_samples(absolute), 20);
}

// Share of the samples in [lo, hi) labelled `want` among those labelled fixation or pursuit.
double smooth_share(const std::vector<DetectorOutput>& out, size_t lo, size_t hi, Event want) {
    int n = 0, k = 0;
    for (size_t i = lo; i < hi && i < out.size(); ++i) {
        if (out[i].event != Event::kFixation && out[i].event != Event::kPursuit) continue;
        ++n;
        k += out[i].event == want;
    }
    return n ? static_cast<double>(k) / n : 0.0;
}

std::vector<DetectorOutput> detect(const std::vector<DetectorInput>& samples, double rate,
                                   const DetectorParams& p, DetectorMode mode) {
    if (mode == DetectorMode::kOffline) return EventDetector::detect_offline(samples, p, rate);
    EventDetector d(p, rate, mode);
    std::vector<DetectorOutput> out;
    DetectorOutput o;
    for (const auto& in : samples) {
        d.push(in);
        while (d.pop(o)) out.push_back(o);
    }
    d.flush();
    while (d.pop(o)) out.push_back(o);
    return out;
}

std::vector<DetectorOutput> detect(const Script& s, const DetectorParams& p, DetectorMode mode) {
    return detect(s.in, Script::kRate, p, mode);
}

// Pursuit at 3.2 deg/s split by 1-deg catch-up saccades every 0.28 s (lund2013 dots,
// UH25_trial1): each piece moves 0.9 deg, under the 1-deg bound on its own, but the eye keeps
// its direction and speed across each saccade, which goes the same way: pursuit.
TEST(EventDetector, PursuitSplitByCatchUpSaccadesIsPursuit) {
    Script s;
    s.fixate(1.0);
    s.saccade(2.0);
    std::vector<std::pair<size_t, size_t>> pieces;
    for (int k = 0; k < 5; ++k) {
        if (k > 0) s.saccade(1.0);
        const size_t lo = s.size();
        s.pursue(0.28, 3.2);
        pieces.emplace_back(lo, s.size());
    }
    s.saccade(2.0);
    const size_t fix_lo = s.size();
    s.fixate(1.0);
    const size_t fix_hi = s.size();
    DetectorParams on;
    on.pursuit_catch_up = 1;
    DetectorParams off = on;
    off.pursuit_catch_up = 0;
    for (auto mode : {DetectorMode::kOffline, DetectorMode::kOnline}) {
        const auto out_on = detect(s, on, mode);
        const auto out_off = detect(s, off, mode);
        ASSERT_EQ(out_on.size(), s.size());
        for (const auto& [lo, hi] : pieces) {
            EXPECT_GT(smooth_share(out_on, lo, hi, Event::kPursuit), 0.9) << lo;
            // Without the rule each piece is too short and too slow for the bound.
            EXPECT_LT(smooth_share(out_off, lo, hi, Event::kPursuit), 0.5) << lo;
        }
        // The fixation after the last catch-up saccade stays fixation.
        EXPECT_GT(smooth_share(out_on, fix_lo, fix_hi, Event::kFixation), 0.95);
    }
}

// A short fixation between two forward saccades inside a pursuit, drifting the same way at
// 0.5 deg/s, is not pooled with the pursuit on either side: its speed is a tenth of theirs.
TEST(EventDetector, FixationBetweenPursuitAndSaccadesIsNotAbsorbed) {
    Script s;
    s.fixate(1.0);
    s.saccade(2.0);
    const size_t p1 = s.size();
    s.pursue(0.6, 5.0);
    const size_t p1_end = s.size();
    s.saccade(1.0);
    const size_t fix_lo = s.size();
    s.pursue(0.3, 0.5);
    const size_t fix_hi = s.size();
    s.saccade(1.0);
    const size_t p2 = s.size();
    s.pursue(0.6, 5.0);
    const size_t p2_end = s.size();
    s.saccade(2.0);
    s.fixate(1.0);
    DetectorParams on;
    on.pursuit_catch_up = 1;
    for (auto mode : {DetectorMode::kOffline, DetectorMode::kOnline}) {
        const auto out = detect(s, on, mode);
        ASSERT_EQ(out.size(), s.size());
        EXPECT_GT(smooth_share(out, fix_lo, fix_hi, Event::kFixation), 0.9);
        EXPECT_GT(smooth_share(out, p1, p1_end, Event::kPursuit), 0.9);
        EXPECT_GT(smooth_share(out, p2, p2_end, Event::kPursuit), 0.9);
    }
}

// Two fixations drifting alike at 3 deg/s (as the coders' fixations in lund2013 video
// UL27_video_triple_jump) on either side of an 8-deg saccade the same way: no catch-up saccade
// is that large (pursuit_join_max_deg), so they are not pooled into pursuit.
TEST(EventDetector, DriftingFixationsAcrossALargeSaccadeAreNotPooled) {
    Script s;
    s.fixate(1.0);
    s.saccade(4.0);
    const size_t lo = s.size();
    s.pursue(0.25, 3.0);
    s.saccade(8.0);
    s.pursue(0.25, 3.0);
    const size_t hi = s.size();
    s.saccade(4.0);
    s.fixate(1.0);
    DetectorParams on;
    on.pursuit_catch_up = 1;
    DetectorParams uncapped = on;
    uncapped.pursuit_join_max_deg = 0.0;
    for (auto mode : {DetectorMode::kOffline, DetectorMode::kOnline}) {
        EXPECT_GT(smooth_share(detect(s, on, mode), lo, hi, Event::kFixation), 0.9);
        EXPECT_GT(smooth_share(detect(s, uncapped, mode), lo, hi, Event::kPursuit), 0.5);
    }
}

// The eye overshoots and turns back while its other component keeps moving (a hooked saccade
// end, as in the lund2013 dots recordings): its speed never falls to a minimum below the
// offset threshold (0.2 x ~430 deg/s peak), but the saccade is over when the velocity reverses
// along the saccade's direction, and the return is the PSO.
TEST(EventDetector, SaccadeEndsWhereTheVelocityTurnsBackAndTheReturnIsPso) {
    Script s;
    s.fixate(1.0);
    const double hook_dps = 150.0;
    s.saccade(8.0, 0.8, hook_dps, 6);
    const size_t turn = s.size() - 1;  // last sample moving forward
    const int back = 8;                // 16 ms: x returns 0.8 deg while y keeps moving
    const double x_top = s.x;
    for (int i = 1; i <= back; ++i) {
        const double u = static_cast<double>(i) / back;
        s.x = x_top - 0.8 * (1.0 - std::cos(M_PI * u)) / 2.0;
        s.y += hook_dps / Script::kRate;
        s.sample();
    }
    s.fixate(1.0);
    const auto out = detect(s);
    ASSERT_EQ(out.size(), s.size());
    size_t last_saccade = 0;
    for (size_t i = 0; i < out.size(); ++i) {
        if (out[i].event == Event::kSaccade) last_saccade = i;
    }
    EXPECT_GE(last_saccade + 2, turn);
    EXPECT_LE(last_saccade, turn + 1);
    int pso = 0;
    for (size_t i = turn + 2; i <= turn + back - 2; ++i) pso += out[i].event == Event::kPso;
    EXPECT_GE(pso, back - 4) << "the return movement is the PSO";
}

// A second, larger saccade that starts inside the first one's PSO window is a saccade of its
// own: it is faster than the saccade whose wobble it would be.
TEST(EventDetector, FasterMovementInsidePsoWindowIsANewSaccade) {
    Script s;
    s.fixate(1.0);
    s.saccade(3.0);
    const size_t first_end = s.size() - 1;
    // 16 ms wobble (damped, one period), then the next saccade 20 ms after the first.
    const double x_end = s.x;
    for (int i = 1; i <= 10; ++i) {
        s.x = x_end + 0.3 * std::exp(-i / 6.0) * std::sin(2 * M_PI * i / 8.0);
        s.sample();
    }
    s.x = x_end;
    const size_t second_start = s.size();
    s.saccade(12.0);
    const size_t second_end = s.size() - 1;
    s.fixate(1.0);
    const auto out = detect(s);
    ASSERT_EQ(out.size(), s.size());
    int saccade = 0;
    int64_t id = -1;
    for (size_t i = second_start; i <= second_end; ++i) {
        if (out[i].event != Event::kSaccade) continue;
        ++saccade;
        id = out[i].saccade_id;
    }
    EXPECT_GE(saccade, static_cast<int>(0.8 * static_cast<double>(second_end - second_start + 1)));
    EXPECT_EQ(out[first_end - 3].event, Event::kSaccade);
    EXPECT_NE(out[first_end - 3].saccade_id, id) << "two saccades, not one";
    EXPECT_NEAR(out[second_end - 3].saccade.amplitude_deg, 12.0, 1.5);
}

// Before a blink the tracker may lose the pupil on and off, and the samples between the
// dropouts jump around: they are undefined (no event), not saccades; the lid's own margin
// before the loss stays blink, and so does a whole blink that one stray sample splits.
TEST(EventDetector, DropoutsBeforeABlinkAreUndefinedNotSaccades) {
    Script s;
    s.fixate(1.0);
    const size_t chain_start = s.size();
    uint64_t seed = 5;
    for (int k = 0; k < 8; ++k) {  // 80 ms: one lost sample in five, jumps of up to 4 deg
        s.lose(1);
        for (int i = 0; i < 4; ++i) {
            s.x = 4.0 * test::noise(seed);
            s.sample();
        }
    }
    s.x = 0.0;
    const size_t loss_start = s.size();
    s.lose(40);  // an 80 ms blink split by one stray sample, then 80 ms more
    s.sample();
    s.lose(40);
    const size_t loss_end = s.size();
    s.fixate(1.0);
    const auto out = detect(s);
    ASSERT_EQ(out.size(), s.size());
    const size_t margin = static_cast<size_t>(DetectorParams{}.blink_pre_s * Script::kRate);
    size_t undefined = 0;
    for (size_t i = chain_start; i < loss_end; ++i) {
        EXPECT_NE(out[i].event, Event::kSaccade) << "sample " << i;
        EXPECT_NE(out[i].event, Event::kPso) << "sample " << i;
        undefined += i < loss_start - margin && out[i].event == Event::kUnknown;
    }
    // (A jump right before the margin may be taken as the lid's artefact: blink.)
    EXPECT_GE(undefined, (loss_start - margin - chain_start) * 3 / 4);
    for (size_t i = loss_start - margin + 1; i < loss_end; ++i) {
        EXPECT_EQ(out[i].event, Event::kBlink) << "sample " << i;
    }
    for (size_t i = 0; i + 20 < chain_start; ++i) ASSERT_EQ(out[i].event, Event::kFixation);
}

// Offline microsaccade stage (Engbert & Kliegl 2003): a 2 s fixation on a noisy tracker (0.03
// deg per axis, U'n'Eye's level) with one 0.3-deg, 14-ms microsaccade (peak ~40 deg/s). On this
// noise N&H's adaptive thresholds often keep it above their onset threshold for less than the
// 10 ms minimum, and it stays fixation; E&K's per-axis ellipse (6 median-based SDs, 6 ms) finds
// it in every case. On the same noise without the microsaccade the stage adds nothing.
std::vector<DetectorInput> noisy_fixation(double rate, double microsaccade_deg, uint64_t seed,
                                          double onset = 1.0, double length = 2.0) {
    std::vector<DetectorInput> in;
    const double dt = 1.0 / rate, dur = 0.014;
    for (double t = 0.0; t < length; t += dt) {
        // Roughly Gaussian: the sum of three uniforms, SD 0.03 deg per axis.
        auto g = [&] { return 0.03 * (test::noise(seed) + test::noise(seed) + test::noise(seed)); };
        const double tau = std::clamp((t - onset) / dur, 0.0, 1.0);
        const double shift = microsaccade_deg * tau * tau * tau * (10 - 15 * tau + 6 * tau * tau);
        DetectorInput d;
        d.t_s = t;
        d.valid = true;
        d.x_deg = shift + g();
        d.y_deg = g();
        in.push_back(d);
    }
    return in;
}

class MicrosaccadeRates : public ::testing::TestWithParam<double> {};

TEST_P(MicrosaccadeRates, OfflineLabelsAMicrosaccadeAndNotNoise) {
    const double rate = GetParam();
    DetectorParams without;
    without.microsaccade_lambda = 0.0;  // N&H alone
    int missed_by_nh = 0;
    for (uint64_t seed : {3u, 11u, 29u, 41u, 57u, 73u}) {
        SCOPED_TRACE(::testing::Message() << rate << " Hz, seed " << seed);
        const auto in = noisy_fixation(rate, 0.3, seed);
        auto saccade_samples = [](const std::vector<DetectorInput>& samples,
                                  const std::vector<DetectorOutput>& out, double from, double to) {
            size_t n = 0;
            for (const auto& o : out) {
                const double t = samples[static_cast<size_t>(o.index)].t_s;
                n += t >= from && t <= to && o.event == Event::kSaccade;
            }
            return n;
        };
        const auto with_stage = EventDetector::detect_offline(in, {}, rate);
        const auto nh_only = EventDetector::detect_offline(in, without, rate);
        ASSERT_EQ(with_stage.size(), in.size());
        // Found, for at least E&K's 6 ms, where it is ...
        const size_t found = saccade_samples(in, with_stage, 1.0, 1.02);
        EXPECT_GE(found, static_cast<size_t>(std::ceil(0.006 * rate)));
        missed_by_nh += saccade_samples(in, nh_only, 1.0, 1.02) == 0;
        // ... and nothing added elsewhere, nor on the same noise without the microsaccade.
        EXPECT_EQ(
            saccade_samples(in, with_stage, 0.0, 0.99) + saccade_samples(in, with_stage, 1.03, 2.0),
            saccade_samples(in, nh_only, 0.0, 0.99) + saccade_samples(in, nh_only, 1.03, 2.0));
        const auto noise = noisy_fixation(rate, 0.0, seed);
        EXPECT_EQ(
            saccade_samples(noise, EventDetector::detect_offline(noise, {}, rate), 0.0, 2.0),
            saccade_samples(noise, EventDetector::detect_offline(noise, without, rate), 0.0, 2.0));
        // The SDs come from the recording (offline); online mode has none and skips the stage.
        const auto t = EventDetector::estimate_thresholds(in, {}, rate);
        EXPECT_GT(t.microsaccade_sigma_x_dps, 0.0);
        EXPECT_GT(t.microsaccade_sigma_y_dps, 0.0);
    }
    EXPECT_GT(missed_by_nh, 0) << "the case no longer needs the microsaccade stage";
}

INSTANTIATE_TEST_SUITE_P(Rates, MicrosaccadeRates, ::testing::Values(250.0, 500.0, 1000.0));

// 20 s of a still eye under 0.25-deg noise per axis (a webcam tracker's) at `rate`.
std::vector<DetectorInput> loud_noise(double rate, uint64_t seed) {
    std::vector<DetectorInput> in;
    for (int i = 0; i < int(20.0 * rate); ++i) {
        DetectorInput d;
        d.t_s = i / rate;
        d.valid = true;
        d.x_deg = 0.25 * (test::noise(seed) + test::noise(seed) + test::noise(seed));
        d.y_deg = 0.25 * (test::noise(seed) + test::noise(seed) + test::noise(seed));
        in.push_back(d);
    }
    return in;
}

// At the ends of the supported range the stage adds nothing on noise alone: at 60 Hz one sample
// already spans E&K's 6 ms and their velocity window is a single sample either side; at 2000 Hz
// the window is 8 samples either side. 20 s per seed of noise loud enough (0.25 deg per axis, a
// webcam tracker's) that its speeds pass the 20 deg/s peak floor, so only the ellipse decides.
TEST(EventDetector, MicrosaccadeStageAddsNothingOnNoiseAt60And2000Hz) {
    DetectorParams without;
    without.microsaccade_lambda = 0.0;
    auto saccades = [](const std::vector<DetectorOutput>& out) {
        return std::count_if(out.begin(), out.end(),
                             [](const DetectorOutput& o) { return o.event == Event::kSaccade; });
    };
    for (double rate : {60.0, 2000.0}) {
        for (uint64_t seed : {5u, 17u, 31u}) {
            SCOPED_TRACE(::testing::Message() << rate << " Hz, seed " << seed);
            const std::vector<DetectorInput> in = loud_noise(rate, seed);
            const auto with_stage = EventDetector::detect_offline(in, {}, rate);
            ASSERT_EQ(with_stage.size(), in.size());
            EXPECT_EQ(saccades(with_stage),
                      saccades(EventDetector::detect_offline(in, without, rate)));
        }
    }
}

// Online (fovead's) microsaccade stage: the per-axis median-based SDs come from the past
// (a decaying histogram over threshold_horizon_s, fed as samples arrive, so it may use the
// bounded look-ahead too). The same 0.3-deg microsaccade, 3 s into a 4-s fixation, is found
// for at least 6 ms wherever the offline stage finds it (at 250 Hz it sits at lambda 6 and
// two of six seeds miss it both ways; with 1 s of history instead of 3 the estimate is ~10 %
// off the recording's and the marginal seeds change), nothing is added elsewhere, nor on the
// noise alone; labels stay within the look-ahead the detector reports.
std::vector<DetectorOutput> run_online(const std::vector<DetectorInput>& in,
                                       const DetectorParams& params, double rate,
                                       size_t* max_held = nullptr) {
    EventDetector d(params, rate, DetectorMode::kOnline);
    std::vector<DetectorOutput> out;
    DetectorOutput o;
    for (size_t i = 0; i < in.size(); ++i) {
        d.push(in[i]);
        while (d.pop(o)) {
            EXPECT_EQ(o.index, static_cast<int64_t>(out.size()));
            out.push_back(o);
        }
        if (max_held) {
            *max_held = std::max(*max_held, i + 1 - out.size());
            EXPECT_LE(i + 1 - out.size(), static_cast<size_t>(d.lookahead_samples()) + 1);
        }
    }
    d.flush();
    while (d.pop(o)) out.push_back(o);
    return out;
}

size_t saccade_samples_between(const std::vector<DetectorInput>& samples,
                               const std::vector<DetectorOutput>& out, double from, double to) {
    size_t n = 0;
    for (const auto& o : out) {
        const double t = samples[static_cast<size_t>(o.index)].t_s;
        n += t >= from && t <= to && o.event == Event::kSaccade;
    }
    return n;
}

TEST_P(MicrosaccadeRates, OnlineLabelsAMicrosaccadeAfterWarmUpAndNotNoise) {
    const double rate = GetParam();
    DetectorParams without;
    without.online_microsaccades = 0;  // N&H alone, online
    int missed_without = 0, found = 0;
    const auto minimum = static_cast<size_t>(std::ceil(0.006 * rate));
    for (uint64_t seed : {3u, 11u, 29u, 41u, 57u, 73u}) {
        SCOPED_TRACE(::testing::Message() << rate << " Hz, seed " << seed);
        const auto in = noisy_fixation(rate, 0.3, seed, 3.0, 4.0);
        size_t held = 0;
        const auto with_stage = run_online(in, {}, rate, &held);
        const auto nh_only = run_online(in, without, rate);
        ASSERT_EQ(with_stage.size(), in.size());
        const bool offline_found =
            saccade_samples_between(in, EventDetector::detect_offline(in, {}, rate), 3.0, 3.02) >=
            minimum;
        const size_t online = saccade_samples_between(in, with_stage, 3.0, 3.02);
        found += online >= minimum;
        if (offline_found) { EXPECT_GE(online, minimum); }
        missed_without += saccade_samples_between(in, nh_only, 3.0, 3.02) == 0;
        EXPECT_EQ(saccade_samples_between(in, with_stage, 0.0, 2.99) +
                      saccade_samples_between(in, with_stage, 3.03, 4.0),
                  saccade_samples_between(in, nh_only, 0.0, 2.99) +
                      saccade_samples_between(in, nh_only, 3.03, 4.0));
        const auto noise = noisy_fixation(rate, 0.0, seed, 3.0, 4.0);
        EXPECT_EQ(saccade_samples_between(noise, run_online(noise, {}, rate), 0.0, 4.0),
                  saccade_samples_between(noise, run_online(noise, without, rate), 0.0, 4.0));
    }
    EXPECT_GE(found, 4);
    EXPECT_GT(missed_without, 0) << "the case no longer needs the online microsaccade stage";
}

TEST(EventDetector, OnlineMicrosaccadeStageAddsNothingOnNoiseAt60And2000Hz) {
    DetectorParams without;
    without.online_microsaccades = 0;
    auto saccades = [](const std::vector<DetectorOutput>& out) {
        return std::count_if(out.begin(), out.end(),
                             [](const DetectorOutput& o) { return o.event == Event::kSaccade; });
    };
    for (double rate : {60.0, 2000.0}) {
        for (uint64_t seed : {5u, 17u, 31u}) {
            SCOPED_TRACE(::testing::Message() << rate << " Hz, seed " << seed);
            const std::vector<DetectorInput> in = loud_noise(rate, seed);
            const auto with_stage = run_online(in, {}, rate);
            ASSERT_EQ(with_stage.size(), in.size());
            EXPECT_EQ(saccades(with_stage), saccades(run_online(in, without, rate)));
        }
    }
}

// The online SD estimate over a long run: one hour at 1000 Hz of fixation noise whose level
// doubles halfway, with single lost samples, NaN positions and 150-ms blinks mixed in. The
// estimate stays finite and positive throughout (its weights are rescaled once, ~35 min in),
// settles near the offline (whole-recording) value of each half, and follows the change within
// a few threshold horizons.
TEST(EventDetector, OnlineMicrosaccadeSigmaIsStableOverAnHourAndFollowsTheNoise) {
    const double rate = 1000.0;
    const int64_t n = static_cast<int64_t>(3600.0 * rate);
    EventDetector d({}, rate, DetectorMode::kOnline);
    EXPECT_EQ(d.microsaccade_sigma_dps()[0], 0.0) << "off until warmed up";
    uint64_t seed = 123;
    DetectorOutput o;
    int64_t popped = 0, bad = 0;
    std::array<double, 2> at_half{}, at_end{};
    std::vector<DetectorInput> first_minute, last_minute;
    for (int64_t i = 0; i < n; ++i) {
        const double t = static_cast<double>(i) / rate;
        const double level = i < n / 2 ? 0.02 : 0.04;
        DetectorInput in;
        in.t_s = t;
        in.valid = i % 211 != 0 && std::fmod(t, 7.0) > 0.15;  // dropouts and a blink every 7 s
        in.x_deg = 0.5 + level * (test::noise(seed) + test::noise(seed) + test::noise(seed));
        in.y_deg = -0.5 + level * (test::noise(seed) + test::noise(seed) + test::noise(seed));
        if (i % 307 == 0) in.x_deg = kNaN;  // "valid" but not a number
        d.push(in);
        while (d.pop(o)) ++popped;
        if (i == n / 2 - 1) at_half = d.microsaccade_sigma_dps();
        if (i >= 1000 && i % 1000 == 0) {
            const auto s = d.microsaccade_sigma_dps();
            bad += !(std::isfinite(s[0]) && std::isfinite(s[1]) && s[0] > 0 && s[1] > 0);
        }
        if (i < 60000 + 30000 && i >= 30000) first_minute.push_back(in);
        if (i >= n - 60000) last_minute.push_back(in);
    }
    at_end = d.microsaccade_sigma_dps();
    d.flush();
    while (d.pop(o)) ++popped;
    EXPECT_EQ(popped, n);
    EXPECT_EQ(bad, 0);
    const auto off_first = EventDetector::estimate_thresholds(first_minute, {}, rate);
    const auto off_last = EventDetector::estimate_thresholds(last_minute, {}, rate);
    ASSERT_GT(off_first.microsaccade_sigma_x_dps, 0.0);
    // Each half's estimate within 10 % of the offline one on the same noise ...
    EXPECT_NEAR(at_half[0], off_first.microsaccade_sigma_x_dps,
                0.1 * off_first.microsaccade_sigma_x_dps);
    EXPECT_NEAR(at_half[1], off_first.microsaccade_sigma_y_dps,
                0.1 * off_first.microsaccade_sigma_y_dps);
    EXPECT_NEAR(at_end[0], off_last.microsaccade_sigma_x_dps,
                0.1 * off_last.microsaccade_sigma_x_dps);
    EXPECT_NEAR(at_end[1], off_last.microsaccade_sigma_y_dps,
                0.1 * off_last.microsaccade_sigma_y_dps);
    // ... and the doubled noise doubles it.
    EXPECT_NEAR(at_end[0] / at_half[0], 2.0, 0.2);
    EXPECT_NEAR(at_end[1] / at_half[1], 2.0, 0.2);
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

// A still eye whose position drifts (a random walk on the millisecond scale, pulled back over
// half a second) under white tracker noise, sampled at 2000 Hz and taken every `every`-th sample.
std::vector<DetectorInput> drifting_fixation(size_t every, uint64_t seed) {
    constexpr double kRate = 2000.0, kDiffusion = 0.15, kNoise = 0.01, kPullBack = 0.5;
    std::vector<DetectorInput> in;
    double dx = 0.0, dy = 0.0;
    const double step = std::sqrt(kDiffusion / kRate / 3.0);  // 3 uniforms: variance 1 each
    for (size_t i = 0; i < static_cast<size_t>(10.0 * kRate); ++i) {
        dx += -dx / (kPullBack * kRate) +
              step * (test::noise(seed) + test::noise(seed) + test::noise(seed));
        dy += -dy / (kPullBack * kRate) +
              step * (test::noise(seed) + test::noise(seed) + test::noise(seed));
        if (i % every != 0) continue;
        DetectorInput d;
        d.t_s = static_cast<double>(i) / kRate;
        d.valid = true;
        d.x_deg = dx + kNoise * (test::noise(seed) + test::noise(seed) + test::noise(seed));
        d.y_deg = dy + kNoise * (test::noise(seed) + test::noise(seed) + test::noise(seed));
        in.push_back(d);
    }
    return in;
}

// The position noise behind the pursuit floor is measured over a fixed 2 ms whatever the rate:
// from 62.5 to 2000 Hz the same eye and tracker give it within 30 % of its 500 Hz value (it is
// within 4 % down to 250 Hz; -25 % at 62.5 Hz, extrapolated from 16 and 32 ms). Per sample
// (noise_reference_s 0, the design before) it grows with the interval as the drift adds up,
// 1.7x at 62.5 Hz here, and slow pursuit became fixation at low rates (Lund dots fixation kappa
// .707 at 500 Hz, .22 at 250 Hz: daemon/eval/README.md).
TEST(EventDetector, PositionNoiseIsTheSameAtEveryRate) {
    DetectorParams per_sample;
    per_sample.noise_reference_s = 0.0;
    std::map<size_t, double> fixed, old;
    for (const size_t every : {1u, 2u, 4u, 8u, 16u, 32u}) {
        const auto in = drifting_fixation(every, 11);
        const double rate = 2000.0 / static_cast<double>(every);
        fixed[every] = EventDetector::estimate_thresholds(in, {}, rate).noise_deg;
        old[every] = EventDetector::estimate_thresholds(in, per_sample, rate).noise_deg;
    }
    for (const auto& [every, noise] : fixed) {
        EXPECT_NEAR(noise / fixed[4], 1.0, 0.30) << 2000 / every << " Hz: " << noise;
    }
    EXPECT_EQ(old[4], fixed[4]);  // one sample is 2 ms at 500 Hz: the same measurement
    for (const auto& [every, noise] : fixed)
        std::printf("%5.1f Hz: noise %.4f deg (per sample %.4f)\n", 2000.0 / every, noise,
                    old[every]);
    EXPECT_GT(old[32] / old[4], 1.5) << "the drift no longer separates the two designs";
}

// 1 s still, 2 s of pursuit at 4 deg/s to the right, 1 s still, 500 Hz, under white noise of
// `sd` deg per axis (Gaussian: 3 uniforms): the events as the detector labels them offline.
std::vector<Event> slow_pursuit_under_noise(double sd, std::vector<Event>& truth) {
    constexpr double kRate = 500.0;
    uint64_t seed = 23;
    std::vector<DetectorInput> in;
    truth.clear();
    for (int i = 0; i < static_cast<int>(4.0 * kRate); ++i) {
        const double t = i / kRate;
        const double x = 4.0 * std::clamp(t - 1.0, 0.0, 2.0);
        DetectorInput d;
        d.t_s = t;
        d.valid = true;
        d.x_deg = x + sd * (test::noise(seed) + test::noise(seed) + test::noise(seed));
        d.y_deg = sd * (test::noise(seed) + test::noise(seed) + test::noise(seed));
        in.push_back(d);
        truth.push_back(t > 1.0 && t < 3.0 ? Event::kPursuit : Event::kFixation);
    }
    std::vector<Event> events;
    for (const auto& o : EventDetector::detect_offline(in, {}, kRate)) events.push_back(o.event);
    return events;
}

// Pursuit at 4 deg/s is pursuit, and a still eye is not, whatever the tracker's white noise up
// to 0.1 deg: white noise hardly moves a 0.4 s window's slope (sd sqrt(12 / (n T^2)), ~0.06 deg/s
// at 0.1 deg), so the pursuit floor (a 3-SD bound on noise and drift) stays under the 1-deg
// bound. The floor used to be 85 x the noise, 2.5 deg/s at 0.4 s on Lund's SMI: with 0.05 deg of
// white noise it passed 10 deg/s and this pursuit was fixation (Lund dots fixation kappa .707 ->
// .054 with 0.05 deg added: daemon/eval/README.md).
TEST(EventDetector, SlowPursuitStaysPursuitUnderWhiteNoise) {
    for (const double sd : {0.01, 0.05, 0.1}) {
        std::vector<Event> truth;
        const auto got = slow_pursuit_under_noise(sd, truth);
        ASSERT_EQ(got.size(), truth.size());
        size_t pursuit = 0, found = 0, still = 0, false_pursuit = 0;
        // Transitions smear by up to the window's reach; score 0.4 s away from them.
        for (size_t i = 0; i < got.size(); ++i) {
            const double t = static_cast<double>(i) / 500.0;
            if (std::fabs(t - 1.0) < 0.4 || std::fabs(t - 3.0) < 0.4) continue;
            if (truth[i] == Event::kPursuit) {
                ++pursuit;
                found += got[i] == Event::kPursuit;
            } else {
                ++still;
                false_pursuit += got[i] == Event::kPursuit;
            }
        }
        EXPECT_GT(static_cast<double>(found) / pursuit, 0.9) << "noise " << sd;
        EXPECT_LT(static_cast<double>(false_pursuit) / still, 0.1) << "noise " << sd;
    }
}

// Saccades of 4-14 deg (minimum jerk, main-sequence duration 2.2 A + 21 ms), each starting at a
// different phase of the sample interval, between 0.6 s fixations under 0.01 deg of noise; a
// sample is the saccade's when the eye moves at its time stamp. Mean onset and offset error of
// the detected saccades (detected minus true sample index) at `rate`, in both modes.
struct BoundError {
    double onset = 0.0, offset = 0.0;
    int saccades = 0;
};
BoundError saccade_bound_error(double rate, const DetectorParams& params, DetectorMode mode) {
    std::vector<DetectorInput> in;
    std::vector<bool> moving;
    uint64_t seed = 5;
    const double dt = 1.0 / rate;
    double x = 0.0, t = 0.0;
    auto sample = [&](double pos, bool in_flight) {
        DetectorInput d;
        d.t_s = t;
        d.valid = true;
        d.x_deg = pos + 0.01 * test::noise(seed);
        d.y_deg = 0.01 * test::noise(seed);
        in.push_back(d);
        moving.push_back(in_flight);
        t += dt;
    };
    for (int k = 0; k < 24; ++k) {
        const double amp = (4.0 + 10.0 * ((k * 7) % 11) / 10.0) * (k % 2 ? -1.0 : 1.0);
        const double dur = (2.2 * std::fabs(amp) + 21.0) * 1e-3;
        const double t0 = t + 0.6 + dt * ((k * 5) % 12) / 12.0;  // onset phase within a sample
        while (t < t0) sample(x, false);
        while (t < t0 + dur) {
            const double tau = (t - t0) / dur;
            sample(x + amp * tau * tau * tau * (10 - 15 * tau + 6 * tau * tau), true);
        }
        x += amp;
    }
    const double end = t + 0.6;
    while (t < end) sample(x, false);
    std::vector<Event> ev;
    for (const auto& o : detect(in, rate, params, mode)) ev.push_back(o.event);
    BoundError e;
    for (size_t i = 1; i < moving.size(); ++i) {
        if (!moving[i] || moving[i - 1]) continue;
        size_t last = i;
        while (last + 1 < moving.size() && moving[last + 1]) ++last;
        // The detected saccade overlapping this one (PSO counts as its end's wobble, not it).
        size_t lo = i, hi = last;
        while (lo > 0 && ev[lo - 1] == Event::kSaccade) --lo;
        while (lo <= hi && ev[lo] != Event::kSaccade) ++lo;
        while (hi + 1 < ev.size() && ev[hi + 1] == Event::kSaccade) ++hi;
        while (hi >= lo && ev[hi] != Event::kSaccade) --hi;
        if (lo > hi) continue;
        e.onset += static_cast<double>(lo) - static_cast<double>(i);
        e.offset += static_cast<double>(hi) - static_cast<double>(last);
        ++e.saccades;
    }
    if (e.saccades) {
        e.onset /= e.saccades;
        e.offset /= e.saccades;
    }
    return e;
}

// At 167 Hz and below the velocity window is one sample either side and still wider than its
// +-4 ms design: a saccade's speed is high already at the sample before it and still at the
// one after it. trim_window_excess moves both bounds in by the excess (one sample here). On these
// clean minimum-jerk saccades the untrimmed offset is ~2 samples late (the local-minimum rule
// also waits for the speed to stop falling, which a noiseless landing does a sample after
// arriving) and the trimmed one ~1; on the labelled data the trim leaves +0.1 to +0.7 samples
// where it was +0.8 to +1.6 (daemon/eval/README.md, stop 42). Pinned: the onset within half a
// sample, the offset a whole sample nearer the movement's end, at every rate of the range.
TEST(EventDetector, SaccadeBoundsAtLowRatesAreWhereTheEyeMoves) {
    DetectorParams untrimmed;
    untrimmed.trim_window_excess = 0;
    for (const double rate : {62.5, 100.0, 125.0, 150.0}) {
        for (const auto mode : {DetectorMode::kOffline, DetectorMode::kOnline}) {
            const char* m = mode == DetectorMode::kOffline ? "offline" : "online";
            const BoundError on = saccade_bound_error(rate, {}, mode);
            const BoundError off = saccade_bound_error(rate, untrimmed, mode);
            std::printf("%5.1f Hz %-7s onset %+.2f offset %+.2f (untrimmed %+.2f %+.2f), %d\n",
                        rate, m, on.onset, on.offset, off.onset, off.offset, on.saccades);
            EXPECT_EQ(on.saccades, 24) << rate << " Hz " << m;
            EXPECT_LE(std::fabs(on.onset), 0.5) << rate << " Hz " << m;
            EXPECT_LE(std::fabs(on.onset), std::fabs(off.onset)) << rate << " Hz " << m;
            EXPECT_GE(off.offset - on.offset, 0.9) << rate << " Hz " << m;
            EXPECT_GE(on.offset, 0.0) << rate << " Hz " << m;  // never into the movement
        }
    }
    // Above 167 Hz nothing moves: the window's rounding error is no bias.
    for (const double rate : {250.0, 500.0}) {
        const BoundError on = saccade_bound_error(rate, {}, DetectorMode::kOffline);
        const BoundError off = saccade_bound_error(rate, untrimmed, DetectorMode::kOffline);
        EXPECT_EQ(on.onset, off.onset) << rate;
        EXPECT_EQ(on.offset, off.offset) << rate;
    }
}

// Fixations of 0.3-0.5 s under `sd` deg of white noise with (or without) a saccade of 2-12 deg
// between each two: minimum jerk over nine tenths of it (2.2 A + 21 ms), the last tenth a
// post-saccadic drift (time constant 20 ms).
std::vector<DetectorInput> fixations_and_saccades(double rate, bool with_saccades, double sd) {
    std::vector<DetectorInput> in;
    uint64_t seed = 31;
    const double dt = 1.0 / rate;
    double x = 0.0, t = 0.0;
    auto sample = [&](double pos) {
        DetectorInput d;
        d.t_s = t;
        d.valid = true;
        d.x_deg = pos + sd * (test::noise(seed) + test::noise(seed) + test::noise(seed));
        d.y_deg = sd * (test::noise(seed) + test::noise(seed) + test::noise(seed));
        in.push_back(d);
        t += dt;
    };
    for (int k = 0; k < 120; ++k) {
        const double t0 = t + 0.3 + 0.2 * ((k * 7) % 11) / 10.0;
        while (t < t0) sample(x);
        if (!with_saccades) continue;
        const double amp = (2.0 + 10.0 * ((k * 5) % 9) / 8.0) * (k % 2 ? -1.0 : 1.0);
        const double main = 0.9 * amp;
        const double dur = (2.2 * std::fabs(main) + 21.0) * 1e-3;
        while (t < t0 + dur) {
            const double tau = (t - t0) / dur;
            sample(x + main * tau * tau * tau * (10 - 15 * tau + 6 * tau * tau));
        }
        const double t1 = t0 + dur;
        while (t < t1 + 0.1) sample(x + main + (amp - main) * (1.0 - std::exp(-(t - t1) / 0.02)));
        x += amp;
    }
    return in;
}

// At 167 Hz and below a saccade's neighbours see part of its jump through their one-sample
// velocity window. Fed to the threshold statistics they raised the peak threshold the next
// saccades had to pass; on GazeCom at 83 Hz the onset samples (27-43 deg/s) then stayed below
// it (daemon/eval/README.md, stop 43). Pinned on the statistic (no floor): with the neighbours
// left out the peak threshold keeps less than half of what saccades add to the noise's own,
// and above 167 Hz nothing changes.
TEST(EventDetector, SaccadeNeighboursStayOutOfTheThresholdsAtLowRates) {
    DetectorParams p;
    p.min_peak_dps = 1.0;  // the statistic itself, not the floor
    DetectorParams flanks_in = p;
    flanks_in.stats_exclude_flanks = 0;
    for (const double rate : {62.5, 100.0, 125.0, 250.0}) {
        const auto still = fixations_and_saccades(rate, false, 0.1);
        const auto in = fixations_and_saccades(rate, true, 0.1);
        const double noise_only = EventDetector::estimate_thresholds(still, p, rate).peak_dps;
        const double out = EventDetector::estimate_thresholds(in, p, rate).peak_dps;
        const double with = EventDetector::estimate_thresholds(in, flanks_in, rate).peak_dps;
        std::printf("%5.1f Hz: peak %.1f deg/s (neighbours in %.1f, no saccades %.1f)\n", rate, out,
                    with, noise_only);
        if (rate > 167.0) {
            EXPECT_EQ(out, with) << rate;
            continue;
        }
        EXPECT_GT(with - noise_only, 0.5) << rate << " Hz: the saccades no longer raise it";
        EXPECT_LT(out - noise_only, 0.5 * (with - noise_only)) << rate;
    }
}

// 62.5 Hz, 0.04 deg of white noise: 8 s of the eye still (`speed_dps` 0) or moving right at
// that speed, with a 0.9-deg jump made between two samples every `every_s` seconds (alternating
// in direction when still, forward when pursuing). `jump[i]`: sample i ends a jump's interval.
std::vector<DetectorInput> jumps_at_62_hz(double speed_dps, double every_s,
                                          std::vector<bool>& jump) {
    constexpr double kRate = 62.5, kJump = 0.9;
    uint64_t seed = 41;
    std::vector<DetectorInput> in;
    double offset = 0.0, next = 0.5 * every_s;
    int k = 0;
    for (int i = 0; i < static_cast<int>(8.0 * kRate); ++i) {
        const double t = i / kRate;
        const bool jumped = t >= next;
        if (jumped) {
            offset += speed_dps > 0 || k % 2 == 0 ? kJump : -kJump;
            next += every_s;
            ++k;
        }
        DetectorInput d;
        d.t_s = t;
        d.valid = true;
        d.x_deg = speed_dps * t + offset + 0.04 * test::noise(seed);
        d.y_deg = 0.04 * test::noise(seed);
        in.push_back(d);
        jump.push_back(jumped);
    }
    return in;
}

// A jump of 0.9 deg inside one 16-ms interval is a saccade, but the central difference halves
// it (28 deg/s) and a peak threshold above that misses it (GazeCom at 62.5 Hz: 35 deg/s; here
// the floor stands in for it). Its window then moved 0.9 deg and was called pursuit: GazeCom at
// 62.5 Hz called 144 of 966 fixation samples pursuit, 115 of them next to such jumps. Taking the
// jump out of the window's fit leaves a still eye fixation, and pursuit with catch-up jumps
// pursuit, as pooling across detected catch-up saccades does (daemon/eval/README.md, stop 43).
TEST(EventDetector, AJumpBetweenTwoSamplesIsNoSmoothMovementAtLowRates) {
    DetectorParams missed;
    missed.min_peak_dps = 40.0;  // the jumps stay undetected
    DetectorParams kept = missed;
    kept.pursuit_skip_jumps = 0;
    auto share = [](const std::vector<DetectorOutput>& out, const std::vector<bool>& jump,
                    Event want) {
        size_t n = 0, hit = 0;
        for (size_t i = 0; i < out.size(); ++i) {
            if (jump[i] || (i > 0 && jump[i - 1])) continue;  // the jumps and the samples after
            ++n;
            hit += out[i].event == want;
        }
        return static_cast<double>(hit) / static_cast<double>(n);
    };
    for (const auto mode : {DetectorMode::kOffline, DetectorMode::kOnline}) {
        const char* m = mode == DetectorMode::kOffline ? "offline" : "online";
        std::vector<bool> jump;
        const auto still = jumps_at_62_hz(0.0, 2.0, jump);
        const double fix = share(detect(still, 62.5, missed, mode), jump, Event::kFixation);
        const double fix_before = share(detect(still, 62.5, kept, mode), jump, Event::kFixation);
        jump.clear();
        const auto pursuit = jumps_at_62_hz(4.0, 0.5, jump);
        const double pur = share(detect(pursuit, 62.5, missed, mode), jump, Event::kPursuit);
        std::printf("%-7s still: fixation %.2f (jumps kept %.2f); pursuit: pursuit %.2f\n", m, fix,
                    fix_before, pur);
        EXPECT_GT(fix, 0.95) << m;
        EXPECT_LT(fix_before, 0.9) << m << ": the jumps no longer make pursuit without the rule";
        EXPECT_GT(pur, 0.9) << m;
    }
}

}  // namespace
}  // namespace fovea::gaze
