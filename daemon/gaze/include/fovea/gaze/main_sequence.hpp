// Saccadic main sequences: peak velocity and duration as functions of amplitude A (degrees).
// One owner for each curve the project uses, so the simulated tracker and the landing
// predictor can never share one by accident (the simulator's landing figures would then only
// show that the predictor agrees with itself):
// - kLund2013Labels: fitted to the lund2013 coders' saccades (../shared/data/README.md,
//   "Main sequence"); the landing predictor's prior for how long a saccade of A lasts.
// - kPublished: independent of any of our labels, for the simulated tracker (drivers/sim):
//   peak velocity from Dai et al. (2016), Vp = 600 (1 - e^(-A/6)) deg/s; duration from
//   Carpenter (1988, Movements of the Eyes), D = 2.2 A + 21 ms.
// Thread rules: plain values, no state.
#pragma once

#include <cmath>

namespace fovea::gaze {

struct MainSequence {
    double peak_dps = 0.0;  // Vp = peak_dps (1 - exp(-A / peak_c_deg))
    double peak_c_deg = 1.0;
    double duration_slope_ms = 0.0;  // D = slope A + intercept
    double duration_intercept_ms = 0.0;

    double peak_velocity_dps(double amplitude_deg) const {
        return peak_dps * (1.0 - std::exp(-amplitude_deg / peak_c_deg));
    }
    double duration_s(double amplitude_deg) const {
        return (duration_slope_ms * amplitude_deg + duration_intercept_ms) * 1e-3;
    }
};

inline constexpr MainSequence kLund2013Labels{560.0, 4.25, 2.6, 17.0};
inline constexpr MainSequence kPublished{600.0, 6.0, 2.2, 21.0};

}  // namespace fovea::gaze
