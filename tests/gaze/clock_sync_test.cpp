#include "fovea/gaze/clock_sync.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>

namespace fovea::gaze {
namespace {

// A generated device: counter of `bits` at `tick_hz` running `ppm` fast, samples at `rate`,
// received after a non-negative jitter (uniform or exponential, mean/max ~5 ms).
struct GeneratedClock {
    int bits = 32;
    double tick_hz = 1e6;
    double ppm = 100.0;
    double rate = 1000.0;
    bool exponential = false;
    double jitter_s = 0.005;
    uint64_t counter_at_zero = 0;
};

struct RunResult {
    double max_err_us = 0.0;  // after warm-up
    double max_reported_unc_us = 0.0;
    uint64_t resets = 0;
};

// `event(i, host_shift_ns, device_restart)` lets a test step the host clock or reset the device.
template <typename Event>
RunResult run(const GeneratedClock& g, double seconds, double warmup_s, Event event) {
    ClockSync sync(DeviceClock{g.bits, g.tick_hz});
    std::mt19937_64 rng(42);
    std::uniform_real_distribution<double> uni(0.0, g.jitter_s);
    std::exponential_distribution<double> expo(1.0 / g.jitter_s);
    const uint64_t mask = g.bits >= 64 ? ~uint64_t{0} : (uint64_t{1} << g.bits) - 1;
    const int64_t host0 = int64_t{1'000'000} * 1'000'000'000;  // far from zero
    RunResult r;
    int64_t host_shift = 0;
    double dev_origin_s = 0.0;  // device time restarts at this true time
    const auto n = static_cast<int64_t>(seconds * g.rate);
    double warm_from = warmup_s;
    for (int64_t i = 0; i < n; ++i) {
        const double t = static_cast<double>(i) / g.rate;
        bool restart = false;
        int64_t shift = 0;
        event(t, shift, restart);
        if (shift != 0) {
            host_shift += shift;
            warm_from = t + warmup_s;
        }
        if (restart) {
            dev_origin_s = t;
            warm_from = t + warmup_s;
        }
        const double dev_s = (t - dev_origin_s) * (1.0 + g.ppm * 1e-6);
        const uint64_t ticks =
            (g.counter_at_zero + static_cast<uint64_t>(std::llround(dev_s * g.tick_hz))) & mask;
        const int64_t truth = host0 + host_shift + std::llround(t * 1e9);
        const double jitter = g.exponential ? expo(rng) : uni(rng);
        const int64_t receive = truth + std::llround(jitter * 1e9);
        const ClockMapping m = sync.update(ticks, receive);
        if (t >= warm_from) {
            r.max_err_us =
                std::max(r.max_err_us, std::fabs(static_cast<double>(m.host_ns - truth)) / 1e3);
            r.max_reported_unc_us = std::max(r.max_reported_unc_us, m.uncertainty_us);
            EXPECT_TRUE(m.converged) << "t=" << t;
        }
    }
    r.resets = sync.resets();
    return r;
}

auto no_event = [](double, int64_t&, bool&) {};

TEST(ClockSync, Within50usAfter10sWith5msJitter100ppmAndWrap32bit) {
    GeneratedClock g;
    g.bits = 32;
    g.tick_hz = 1e9;                                          // wraps every 4.3 s
    g.counter_at_zero = (uint64_t{1} << 32) - 1'000'000'000;  // wrap 1 s in
    const RunResult r = run(g, 60.0, 10.0, no_event);
    std::printf("clock 32-bit 1 GHz, 100 ppm, U(0,5 ms): max error %.1f us\n", r.max_err_us);
    EXPECT_LE(r.max_err_us, 50.0);
    EXPECT_EQ(r.resets, 0u);
}

TEST(ClockSync, Within50usOn16bitMicrosecondCounterWithExponentialJitter) {
    GeneratedClock g;
    g.bits = 16;  // wraps every 65 ms
    g.tick_hz = 1e6;
    g.exponential = true;
    g.ppm = -100.0;
    const RunResult r = run(g, 40.0, 10.0, no_event);
    std::printf("clock 16-bit 1 MHz, -100 ppm, Exp(5 ms): max error %.1f us\n", r.max_err_us);
    EXPECT_LE(r.max_err_us, 50.0);
}

TEST(ClockSync, Within60usOn64bitCounterAt250HzAfter20s) {
    GeneratedClock g;
    g.bits = 64;
    g.tick_hz = 90e3;  // odd tick rate
    g.rate = 250.0;
    g.counter_at_zero = ~uint64_t{0} - 5'000'000;  // far from zero, wraps 64-bit
    // 4x fewer samples per second than the 1 kHz cases: the window needs 20 s to hold as many.
    const RunResult r = run(g, 60.0, 20.0, no_event);
    std::printf("clock 64-bit 90 kHz at 250 Hz: max error %.1f us\n", r.max_err_us);
    // Measured ~50-55 us: 4x fewer samples per bin minimum than at 1 kHz (README.md).
    EXPECT_LE(r.max_err_us, 60.0);
}

TEST(ClockSync, ReconvergesAfterDeviceReset) {
    GeneratedClock g;
    bool done = false;
    const RunResult r = run(g, 40.0, 10.0, [&](double t, int64_t&, bool& restart) {
        if (!done && t >= 15.0) restart = done = true;
    });
    EXPECT_GE(r.resets, 1u);
    EXPECT_LE(r.max_err_us, 50.0);
}

TEST(ClockSync, ReconvergesAfterHostClockStep) {
    GeneratedClock g;
    bool done = false;
    const RunResult r = run(g, 40.0, 10.0, [&](double t, int64_t& shift, bool&) {
        if (!done && t >= 15.0) {
            shift = -3'000'000'000;  // host clock stepped back 3 s
            done = true;
        }
    });
    EXPECT_GE(r.resets, 1u);
    EXPECT_LE(r.max_err_us, 50.0);
}

TEST(ClockSync, SingleGarbageSampleDoesNotReset) {
    ClockSync sync(DeviceClock{32, 1e6});
    int64_t host = 5'000'000'000;
    for (int64_t i = 0; i < 5000; ++i)
        sync.update(static_cast<uint64_t>(i) * 1000, host + i * 1'000'000);
    const ClockMapping bad = sync.update(0xdeadbeef, host + int64_t{5000} * 1'000'000);
    EXPECT_FALSE(bad.converged);
    const ClockMapping good = sync.update(5001 * 1000, host + int64_t{5001} * 1'000'000);
    EXPECT_TRUE(good.converged);
    EXPECT_NEAR(static_cast<double>(good.host_ns),
                static_cast<double>(host + int64_t{5001} * 1'000'000), 1e4);
    EXPECT_EQ(sync.resets(), 0u);
}

}  // namespace
}  // namespace fovea::gaze
