// Deterministic synthetic gaze for detector/pipeline tests: fixations with noise, a minimum-jerk
// main-sequence saccade, a pursuit ramp and a blink, with ground-truth events.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "fovea/gaze/event_detector.hpp"

namespace fovea::gaze::test {

struct Synthetic {
    std::vector<DetectorInput> in;
    std::vector<Event> truth;
};

inline double noise(uint64_t& s) {
    s = s * 6364136223846793005ULL + 1442695040888963407ULL;
    return (static_cast<double>(s >> 11) / 9007199254740992.0 - 0.5) * 2.0;
}

// rate Hz; 1 s fixation, 10 deg saccade, 0.5 s fixation, 1 s pursuit at 8 deg/s, 0.5 s fixation,
// 120 ms blink, 0.8 s fixation. Noise ~0.02 deg.
inline Synthetic make_synthetic(double rate, uint64_t seed = 7) {
    Synthetic s;
    double x = -5.0, y = 0.0, t = 0.0;
    const double dt = 1.0 / rate;
    auto emit = [&](Event e, bool valid = true) {
        DetectorInput d;
        d.t_s = t;
        d.valid = valid;
        d.x_deg = valid ? x + 0.02 * noise(seed) : kNaN;
        d.y_deg = valid ? y + 0.02 * noise(seed) : kNaN;
        s.in.push_back(d);
        s.truth.push_back(e);
        t += dt;
    };
    auto fixate = [&](double secs) {
        for (double u = 0; u < secs; u += dt) emit(Event::kFixation);
    };
    fixate(1.0);
    const double amp = 10.0, dur = (2.6 * amp + 17.0) * 1e-3, x0 = x;
    for (double u = 0; u < dur; u += dt) {
        const double tau = u / dur;
        x = x0 + amp * tau * tau * tau * (10 - 15 * tau + 6 * tau * tau);
        emit(Event::kSaccade);
    }
    x = x0 + amp;
    fixate(0.5);
    for (double u = 0; u < 1.0; u += dt) {
        x -= 8.0 * dt;
        emit(Event::kPursuit);
    }
    fixate(0.5);
    for (double u = 0; u < 0.12; u += dt) emit(Event::kBlink, false);
    fixate(0.8);
    return s;
}

}  // namespace fovea::gaze::test
