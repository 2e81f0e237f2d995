// The simulated tracker: main sequence, event mix, determinism, device clock, rates, driver timing.
#include <gtest/gtest.h>

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <vector>

#include <boost/asio/io_context.hpp>

#include "fovea/drivers/driver.hpp"
#include "sim/sim_driver.hpp"
#include "sim/sim_tracker.hpp"

namespace fovea::drivers::sim {
namespace {

using gaze::Event;

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? NAN : v[v.size() / 2];
}

struct MeasuredSaccade {
    double amplitude = 0, duration_ms = 0, peak_dps = 0, peak_time_fraction = 0;
    double landing_error = 0;
};

// Measures saccades from the noise-free truth trajectory (not from the generator's parameters).
std::vector<MeasuredSaccade> measure_saccades(SimTracker& sim, int n_samples) {
    std::vector<MeasuredSaccade> out;
    const double dt = 1.0 / sim.config().rate_hz;
    SimTracker::Frame prev = sim.next();
    bool in = false;
    MeasuredSaccade cur;
    int64_t onset = 0, peak_t = 0;
    for (int i = 0; i < n_samples; ++i) {
        SimTracker::Frame f = sim.next();
        if (f.truth.in_saccade && !in) {
            in = true;
            cur = {};
            onset = f.truth.saccade_onset_ns;
            cur.amplitude = f.truth.saccade_amplitude_deg;
            cur.duration_ms = (f.truth.saccade_end_ns - f.truth.saccade_onset_ns) / 1e6;
        }
        if (in) {
            const double v =
                std::hypot(f.truth.x_deg - prev.truth.x_deg, f.truth.y_deg - prev.truth.y_deg) / dt;
            if (v > cur.peak_dps) {
                cur.peak_dps = v;
                peak_t = f.t_true_ns;
            }
        }
        if (in && !f.truth.in_saccade) {
            in = false;
            cur.peak_time_fraction = (peak_t - onset) / (cur.duration_ms * 1e6);
            // At the end of the saccade (first PSO/fixation sample) the eye is at the target,
            // up to the PSO's first excursion.
            cur.landing_error = std::hypot(prev.truth.x_deg - prev.truth.landing_x_deg,
                                           prev.truth.y_deg - prev.truth.landing_y_deg);
            out.push_back(cur);
        }
        prev = f;
    }
    return out;
}

TEST(SimTracker, SaccadesFollowTheSubjectsMainSequence) {
    SimConfig c;
    c.rate_hz = 2000;
    c.seed = 7;
    SimTracker sim(c);
    const gaze::MainSequence& ms = sim.subject_main_sequence();
    const auto saccades = measure_saccades(sim, 2000 * 300);  // 5 simulated minutes
    ASSERT_GT(saccades.size(), 500u);
    std::vector<double> v_ratio, d_ratio;
    for (const auto& s : saccades) {
        v_ratio.push_back(s.peak_dps / ms.peak_velocity_dps(s.amplitude));
        d_ratio.push_back(s.duration_ms / (ms.duration_s(s.amplitude) * 1e3));
        EXPECT_GE(s.amplitude, 0.5);
        EXPECT_LE(s.amplitude, 30.0);
    }
    EXPECT_NEAR(median(v_ratio), 1.0, 0.05);
    EXPECT_NEAR(median(d_ratio), 1.0, 0.03);
    // Variability is physiological, not wild: 90 % of saccades within +-25 % of the formula,
    // and the durations really spread (+-15-20 % at 2 SD): the middle half spans >= 8 %.
    int within = 0;
    for (double r : v_ratio) within += (r > 0.75 && r < 1.25);
    EXPECT_GT(within, 0.9 * v_ratio.size());
    std::sort(d_ratio.begin(), d_ratio.end());
    const double iqr = d_ratio[d_ratio.size() * 3 / 4] - d_ratio[d_ratio.size() / 4];
    EXPECT_GT(iqr, 0.08);
    EXPECT_LT(iqr, 0.2);
}

// The simulator draws each seed's subject from the published population curve, never from the
// curve the landing predictor assumes (gaze/main_sequence.hpp).
TEST(SimTracker, SubjectsScatterAroundThePublishedMainSequence) {
    std::vector<double> peak, dur;
    for (uint64_t seed = 1; seed <= 40; ++seed) {
        SimConfig c;
        c.seed = seed;
        const SimTracker sim(c);
        peak.push_back(sim.subject_main_sequence().peak_dps / gaze::kPublished.peak_dps);
        dur.push_back(sim.subject_main_sequence().duration_slope_ms /
                      gaze::kPublished.duration_slope_ms);
    }
    EXPECT_NEAR(median(peak), 1.0, 0.05);
    EXPECT_NEAR(median(dur), 1.0, 0.04);
    const auto [lo, hi] = std::minmax_element(peak.begin(), peak.end());
    EXPECT_GT(*hi - *lo, 0.15);  // subjects differ
    EXPECT_NE(gaze::kPublished.peak_c_deg, gaze::kLund2013Labels.peak_c_deg);
    EXPECT_NE(gaze::kPublished.duration_slope_ms, gaze::kLund2013Labels.duration_slope_ms);
}

TEST(SimTracker, SaccadeMainSequenceHoldsPerAmplitudeBand) {
    SimConfig c;
    c.rate_hz = 2000;
    c.seed = 11;
    c.saccade_median_deg = 5.0;
    SimTracker sim(c);
    const gaze::MainSequence& ms = sim.subject_main_sequence();
    const auto saccades = measure_saccades(sim, 2000 * 300);
    // Bands: 0.5-2, 2-5, 5-10, 10-20 deg; the fit holds across amplitudes, not only on average.
    const double edges[] = {0.5, 2, 5, 10, 20};
    for (int b = 0; b < 4; ++b) {
        std::vector<double> v, d;
        for (const auto& s : saccades) {
            if (s.amplitude < edges[b] || s.amplitude >= edges[b + 1]) continue;
            v.push_back(s.peak_dps / ms.peak_velocity_dps(s.amplitude));
            d.push_back(s.duration_ms / (ms.duration_s(s.amplitude) * 1e3));
        }
        ASSERT_GT(v.size(), 20u) << "band " << edges[b];
        std::printf("band %4.1f-%4.1f deg: n=%zu median Vp/formula %.3f, D/formula %.3f\n",
                    edges[b], edges[b + 1], v.size(), median(v), median(d));
        EXPECT_NEAR(median(v), 1.0, 0.07) << "band " << edges[b];
        EXPECT_NEAR(median(d), 1.0, 0.04) << "band " << edges[b];
    }
}

TEST(SimTracker, SaccadeVelocityProfileIsAsymmetricAndLandsOnTarget) {
    SimConfig c;
    c.rate_hz = 2000;
    c.seed = 3;
    c.saccade_median_deg = 10.0;
    SimTracker sim(c);
    const auto saccades = measure_saccades(sim, 2000 * 120);
    std::vector<double> large, small;
    for (const auto& s : saccades) {
        (s.amplitude > 10 ? large : small).push_back(s.peak_time_fraction);
        EXPECT_LT(s.landing_error, 0.05 * s.amplitude + 0.02);
    }
    ASSERT_GT(large.size(), 30u);
    // Peak velocity comes early (acceleration shorter than deceleration), at 30-45 % of the
    // duration, earlier when large.
    EXPECT_LT(median(large), 0.42);
    EXPECT_GT(median(large), 0.28);
    EXPECT_LT(median(small), 0.47);
    EXPECT_LT(median(large), median(small));
}

TEST(SimTracker, EventProportionsArePlausible) {
    SimConfig c;
    c.rate_hz = 500;
    c.seed = 5;
    SimTracker sim(c);
    std::map<Event, int> count;
    const int n = 500 * 600;  // 10 simulated minutes
    int blinks = 0, pso_after_saccade = 0, saccades = 0;
    Event prev = Event::kFixation;
    for (int i = 0; i < n; ++i) {
        const auto f = sim.next();
        ++count[f.truth.event];
        EXPECT_EQ(f.raw.truth, f.truth.event);
        if (f.truth.event == Event::kBlink && prev != Event::kBlink) ++blinks;
        if (f.truth.event == Event::kSaccade && prev != Event::kSaccade) ++saccades;
        if (f.truth.event == Event::kPso && prev == Event::kSaccade) ++pso_after_saccade;
        prev = f.truth.event;
    }
    const auto share = [&](Event e) { return static_cast<double>(count[e]) / n; };
    EXPECT_GT(share(Event::kFixation), 0.55);
    EXPECT_LT(share(Event::kFixation), 0.85);
    EXPECT_GT(share(Event::kSaccade), 0.04);
    EXPECT_LT(share(Event::kSaccade), 0.15);
    EXPECT_GT(share(Event::kPso), 0.02);
    EXPECT_LT(share(Event::kPso), 0.10);
    EXPECT_NEAR(share(Event::kPursuit), c.pursuit_share, 0.05);
    EXPECT_GT(share(Event::kBlink), 0.01);
    EXPECT_LT(share(Event::kBlink), 0.10);
    // ~15 blinks a minute; every saccade is followed by a PSO.
    EXPECT_NEAR(blinks / 10.0, 60 * c.blink_rate_hz, 5.0);
    EXPECT_EQ(pso_after_saccade, saccades);
}

TEST(SimTracker, BlinksLoseValidityAndLastHundredToFourHundredMs) {
    SimConfig c;
    c.rate_hz = 1000;
    c.seed = 9;
    SimTracker sim(c);
    int64_t blink_start = -1;
    int blinks = 0, invalid_in_blink = 0, invalid_outside = 0;
    double min_pupil_edge = 1e9, baseline_pupil = 0;
    for (int i = 0; i < 1000 * 240; ++i) {
        const auto f = sim.next();
        const bool blink = f.truth.event == Event::kBlink;
        if (blink && blink_start < 0) blink_start = f.t_true_ns;
        if (!blink && blink_start >= 0) {
            const double ms = (f.t_true_ns - blink_start) / 1e6;
            EXPECT_GE(ms, 99.0);
            EXPECT_LE(ms, 401.0);
            blink_start = -1;
            ++blinks;
        }
        const bool invalid = !f.raw.left.valid || !f.raw.right.valid;
        if (blink) {
            invalid_in_blink += invalid;
            if (!invalid) min_pupil_edge = std::min(min_pupil_edge, f.raw.left.pupil_mm);
            if (invalid) {
                EXPECT_TRUE(std::isnan(f.raw.left.x));
                EXPECT_EQ(f.raw.left.pupil_mm, 0.0);
            }
        } else {
            invalid_outside += invalid;
            baseline_pupil = f.raw.left.pupil_mm;
            EXPECT_GT(f.raw.left.pupil_mm, 2.5);
            EXPECT_LT(f.raw.left.pupil_mm, 4.5);
        }
    }
    EXPECT_GT(blinks, 30);
    EXPECT_GT(invalid_in_blink, blinks * 40);  // the lid is closed for most of each blink
    EXPECT_EQ(invalid_outside, 0);
    // Partial occlusion at the lid edges shrinks the measured pupil.
    EXPECT_LT(min_pupil_edge, 0.7 * baseline_pupil);
}

TEST(SimTracker, SameSeedSameSamplesDifferentSeedDifferentSamples) {
    SimConfig c;
    c.seed = 42;
    SimTracker a(c), b(c);
    c.seed = 43;
    SimTracker other(c);
    int differ = 0;
    for (int i = 0; i < 20000; ++i) {
        const auto fa = a.next(), fb = b.next(), fo = other.next();
        ASSERT_EQ(fa.raw.device_ticks, fb.raw.device_ticks);
        ASSERT_EQ(fa.t_true_ns, fb.t_true_ns);
        ASSERT_EQ(fa.raw.left.valid, fb.raw.left.valid);
        if (fa.raw.left.valid) {
            ASSERT_EQ(fa.raw.left.x, fb.raw.left.x);  // bit-identical
            ASSERT_EQ(fa.raw.right.y, fb.raw.right.y);
        }
        ASSERT_EQ(fa.truth.event, fb.truth.event);
        differ += fa.raw.left.valid && fo.raw.left.valid && fa.raw.left.x != fo.raw.left.x;
    }
    EXPECT_GT(differ, 19000 * 0.9);
}

TEST(SimTracker, DeviceCounterWrapsAtCounterBitsAndTicksAtTickRate) {
    for (int bits : {16, 32}) {
        SimConfig c;
        c.rate_hz = 1000;
        c.counter_bits = bits;
        c.tick_hz = 1e6;
        SimTracker sim(c);
        const uint64_t modulus = 1ULL << bits;
        uint64_t prev = sim.next().raw.device_ticks;
        int wraps = 0;
        for (int i = 1; i < 12000; ++i) {  // 12 s: the default offset wraps 32-bit at ~10 s
            const uint64_t t = sim.next().raw.device_ticks;
            ASSERT_LT(t, modulus);
            const uint64_t delta = (t - prev) & (modulus - 1);
            ASSERT_EQ(delta, 1000u) << "sample " << i;  // 1 ms at 1 MHz, across wraps too
            wraps += t < prev;
            prev = t;
        }
        // 65.536 ms per wrap at 16 bits; exactly one at ~10 s for 32 bits.
        EXPECT_EQ(wraps, bits == 16 ? 183 : 1);
    }
}

TEST(SimTracker, DeviceClockDriftsByConfiguredPpm) {
    SimConfig c;
    c.rate_hz = 100;
    c.counter_bits = 64;
    c.drift_ppm = 50;
    c.counter_offset = 0;
    SimTracker sim(c);
    SimTracker::Frame f;
    for (int i = 0; i <= 100 * 100; ++i) f = sim.next();  // 100 s
    // 100 s of true time read as 100 s * (1 + 50 ppm) of device time.
    EXPECT_NEAR(static_cast<double>(f.raw.device_ticks), 100e6 * (1 + 50e-6), 1.0);
    EXPECT_EQ(f.t_true_ns, 100'000'000'000);
}

TEST(SimTracker, SupportsRatesFrom60To2000HzAndRejectsOthers) {
    for (double rate : {60.0, 120.0, 250.0, 1000.0, 2000.0}) {
        SimConfig c;
        c.rate_hz = rate;
        ASSERT_TRUE(validate(c).ok());
        SimTracker sim(c);
        SimTracker::Frame f;
        std::map<Event, int> seen;
        for (int i = 0; i < rate * 60; ++i) {
            f = sim.next();
            ++seen[f.truth.event];
            if (f.raw.left.valid) {
                ASSERT_TRUE(std::isfinite(f.raw.left.x));
                ASSERT_GT(f.raw.left.x, -0.2);
                ASSERT_LT(f.raw.left.x, 1.2);
            }
        }
        EXPECT_NEAR(f.t_true_ns / 1e9, 60.0 - 1.0 / rate, 1e-6);
        EXPECT_GT(seen[Event::kSaccade], 0) << rate;
        EXPECT_GT(seen[Event::kFixation], rate * 20) << rate;
    }
    SimConfig c;
    c.rate_hz = 30;
    EXPECT_FALSE(validate(c).ok());
    c.rate_hz = 5000;
    EXPECT_FALSE(validate(c).ok());
    c.rate_hz = NAN;
    EXPECT_FALSE(validate(c).ok());
}

TEST(SimTracker, EyesDifferByASmallVergenceAndMonocularLeavesRightInvalid) {
    SimConfig c;
    c.seed = 2;
    SimTracker sim(c);
    std::vector<double> dx;
    for (int i = 0; i < 20000; ++i) {
        const auto f = sim.next();
        if (f.truth.event != Event::kFixation) continue;
        double lx, ly, rx, ry;
        c.display.to_degrees(f.raw.left.x, f.raw.left.y, lx, ly);
        c.display.to_degrees(f.raw.right.x, f.raw.right.y, rx, ry);
        dx.push_back(lx - rx);
    }
    const double m = median(dx);
    EXPECT_GT(std::fabs(m), 0.05);
    EXPECT_LT(std::fabs(m), 1.0);

    c.binocular = false;
    SimTracker mono(c);
    for (int i = 0; i < 1000; ++i) EXPECT_FALSE(mono.next().raw.right.valid);
}

TEST(SimTracker, MeasurementNoiseMatchesConfiguredRms) {
    SimConfig c;
    c.noise_deg = 0.05;
    c.tremor_deg = 0.0;
    c.seed = 4;
    SimTracker sim(c);
    double sum2 = 0;
    int n = 0;
    for (int i = 0; i < 50000; ++i) {
        const auto f = sim.next();
        if (f.truth.event != Event::kFixation || !f.raw.left.valid) continue;
        double lx, ly, rx, ry;
        c.display.to_degrees(f.raw.left.x, f.raw.left.y, lx, ly);
        c.display.to_degrees(f.raw.right.x, f.raw.right.y, rx, ry);
        // Left minus right cancels the eye movement: what is left is the two eyes' noise.
        const double d = (lx - rx) - c.vergence_deg;
        sum2 += d * d;
        ++n;
    }
    ASSERT_GT(n, 10000);
    // Constant biases shift the mean, so use the variance around it via a loose bound.
    EXPECT_NEAR(std::sqrt(sum2 / n) / std::sqrt(2.0), 0.05, 0.03);
}

TEST(SimDriver, DeliversSamplesAtTheConfiguredRateWithoutDrift) {
    boost::asio::io_context io;
    auto table = toml::table{{"driver", "sim"}, {"rate_hz", 500}, {"seed", 3}};
    auto drv = make_driver(table, 7);
    ASSERT_TRUE(drv.ok()) << drv.error().message;
    std::vector<gaze::RawSample> got;
    const auto monotonic_ns = [] {
        timespec ts{};
        clock_gettime(CLOCK_MONOTONIC, &ts);
        return int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
    };
    // The driver's clock starts somewhere inside open(), which a loaded machine can stretch by
    // milliseconds (a CI run once saw 5 ms): bracket it.
    const int64_t before_open_ns = monotonic_ns();
    ASSERT_TRUE((*drv)->open(io, [&](const gaze::RawSample& s) { got.push_back(s); }).ok());
    const int64_t after_open_ns = monotonic_ns();
    io.run_for(std::chrono::milliseconds(400));
    (*drv)->close();
    io.run_for(std::chrono::milliseconds(20));
    // Each batch delivers every sample due by its wake-up, whatever the machine's load: the
    // count (plus any backlog skipped after a stall, counted as lost) follows from the last
    // batch's receive time (deadlines are absolute, so nothing drifts).
    ASSERT_GT(got.size(), 50u);
    const double delivered = static_cast<double>(got.size() + (*drv)->stats().frames_lost);
    const int64_t last_ns = got.back().t_receive_ns;
    EXPECT_GE(delivered, (last_ns - after_open_ns) / 1e9 * 500 + 1 - 2.0);
    EXPECT_LE(delivered, (last_ns - before_open_ns) / 1e9 * 500 + 1 + 2.0);
    ASSERT_FALSE(got.empty());
    EXPECT_EQ(got.front().device_id, 7u);
    for (size_t i = 1; i < got.size(); ++i) {
        EXPECT_EQ((got[i].device_ticks - got[i - 1].device_ticks) & 0xffffffffULL, 2000u);
        EXPECT_GE(got[i].t_receive_ns, got[i - 1].t_receive_ns);
    }
    EXPECT_EQ((*drv)->stats().samples, got.size());
    EXPECT_FALSE((*drv)->stats().connected);
    EXPECT_EQ((*drv)->describe().nominal_rate_hz, 500.0);
}

TEST(SimDriver, BadConfigIsAClearError) {
    auto r = make_driver(toml::table{{"rate_hz", 5}}, 0);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("rate_hz"), std::string::npos);
    r = make_driver(toml::table{{"seed", "abc"}}, 0);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("seed"), std::string::npos);
    // A float beyond any integer (toml++ itself would cast it: undefined, found by the fuzzer).
    for (double huge : {3.3e53, -1e300, 9.3e18}) {
        r = make_driver(toml::table{{"seed", huge}}, 0);
        ASSERT_FALSE(r.ok()) << huge;
        EXPECT_NE(r.error().message.find("seed"), std::string::npos);
    }
}

TEST(SimDriver, RegisteredAsTheDefaultDriver) {
    auto r = drivers::make_driver(toml::table{}, 0);
    ASSERT_TRUE(r.ok());
    EXPECT_EQ((*r)->describe().driver, "sim");
}

}  // namespace
}  // namespace fovea::drivers::sim
