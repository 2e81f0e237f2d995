// Deterministic synthetic gaze for the record tests: fixations and saccades at 1 kHz with
// awkward values (NaN while invalid, wrapping 32-bit device counter, huge receive times).
#pragma once

#include <cmath>
#include <cstdint>

#include "fovea/gaze/sample.hpp"

namespace fovea::record::test {

inline gaze::RawSample synthetic_raw(int i, int64_t t0_ns) {
    gaze::RawSample r;
    r.device_ticks = (0xFFFFF000ull + static_cast<uint64_t>(i) * 1000ull) & 0xFFFFFFFFull;  // wraps
    r.t_receive_ns = t0_ns + int64_t{i} * 1'000'000 + (i * 7919) % 300'000;
    const bool blink = i % 1000 > 950;
    r.left.valid = r.right.valid = !blink;
    r.left.x = blink ? gaze::kNaN : 0.5 + 0.3 * std::sin(i * 0.001);
    r.left.y = blink ? gaze::kNaN : 0.5 + 0.2 * std::cos(i * 0.0013);
    r.right.x = blink ? gaze::kNaN : r.left.x + 1e-3;
    r.right.y = blink ? gaze::kNaN : r.left.y - 1e-3;
    r.left.pupil_mm = 3.0 + 1e-4 * i;
    r.right.pupil_mm = 3.1;
    r.device_id = static_cast<uint32_t>(i % 2);
    r.truth = blink ? gaze::Event::kBlink
                    : (i % 300 < 40 ? gaze::Event::kSaccade : gaze::Event::kFixation);
    return r;
}

inline gaze::GazeSample synthetic_gaze(int i, int64_t t0_ns) {
    const gaze::RawSample r = synthetic_raw(i, t0_ns);
    gaze::GazeSample g;
    g.t_capture_ns = r.t_receive_ns - 2'000'000 - (i % 13) * 10'000;
    g.t_receive_ns = r.t_receive_ns;
    g.t_processed_ns = r.t_receive_ns + 20'000 + (i % 17) * 1000;
    g.clock_uncertainty_us = 35.5 + i % 3;
    g.clock_converged = i > 100;
    g.left = r.left;
    g.right = r.right;
    g.combined = r.left;
    g.left_deg_x = std::atan(r.left.x - 0.5) * 57.3;
    g.left_deg_y = -1.25;
    g.combined_deg_x = 3.0 + 1e-9 * i;
    g.combined_deg_y = -2.0;
    g.event = r.truth;
    if (r.truth == gaze::Event::kSaccade) {
        g.saccade.onset_ns = g.t_capture_ns - (i % 300) * 1'000'000;
        g.saccade.amplitude_deg = 1.0 + (i / 300) % 20;
        g.saccade.peak_velocity_dps = 560.0 * (1.0 - std::exp(-g.saccade.amplitude_deg / 4.25));
        g.saccade.direction_deg = 45.0;
        g.saccade.landing_valid = i % 300 > 10;
        g.saccade.landing_x = 0.7;
        g.saccade.landing_y = 0.4;
    }
    g.calibrated = true;
    g.device_id = r.device_id;
    g.truth = r.truth;
    return g;
}

inline bool same_double(double a, double b) { return (std::isnan(a) && std::isnan(b)) || a == b; }

}  // namespace fovea::record::test
