#include "ring_record.hpp"

#include <cmath>

namespace fovea::daemon {
namespace {

float f(double v) { return static_cast<float>(v); }

fovea_eye to_eye(const gaze::EyeSample& e, double deg_x, double deg_y) {
    fovea_eye out{};
    // Invalid eyes carry NaN coordinates in the chain; the ring holds zeros for them so that
    // clients that ignore `valid` still never read a NaN.
    const bool ok = e.valid && std::isfinite(e.x) && std::isfinite(e.y);
    out.norm_x = ok ? f(e.x) : 0.0f;
    out.norm_y = ok ? f(e.y) : 0.0f;
    out.deg_x = ok && std::isfinite(deg_x) ? f(deg_x) : 0.0f;
    out.deg_y = ok && std::isfinite(deg_y) ? f(deg_y) : 0.0f;
    out.pupil_mm = std::isfinite(e.pupil_mm) ? f(e.pupil_mm) : 0.0f;
    out.valid = ok ? FOVEA_VALID : 0u;
    return out;
}

}  // namespace

fovea_gaze_record to_ring_record(const gaze::GazeSample& s, bool simulated) {
    fovea_gaze_record r{};
    r.t_capture_ns = s.t_capture_ns;
    r.t_receive_ns = s.t_receive_ns;
    r.t_processed_ns = s.t_processed_ns;
    r.left = to_eye(s.left, s.left_deg_x, s.left_deg_y);
    r.right = to_eye(s.right, s.right_deg_x, s.right_deg_y);
    r.combined = to_eye(s.combined, s.combined_deg_x, s.combined_deg_y);
    r.event = static_cast<uint32_t>(s.event);
    r.device_id = s.device_id;
    r.clock_uncertainty_us = f(s.clock_uncertainty_us);
    r.flags = (s.calibrated ? FOVEA_FLAG_CALIBRATED : 0u) |
              (simulated ? FOVEA_FLAG_SIMULATED : 0u) |
              (s.clock_converged ? FOVEA_FLAG_CLOCK_CONVERGED : 0u);
    const auto& sac = s.saccade;
    r.saccade_onset_ns = sac.onset_ns;
    r.saccade_amplitude_deg = f(sac.amplitude_deg);
    r.saccade_peak_velocity_dps = f(sac.peak_velocity_dps);
    r.saccade_direction_deg = f(sac.direction_deg);
    if (sac.landing_valid && std::isfinite(sac.landing_x) && std::isfinite(sac.landing_y)) {
        r.flags |= FOVEA_FLAG_LANDING_VALID;
        r.landing_norm_x = f(sac.landing_x);
        r.landing_norm_y = f(sac.landing_y);
        r.landing_deg_x = f(sac.landing_deg_x);
        r.landing_deg_y = f(sac.landing_deg_y);
        r.landing_uncertainty_deg = f(sac.landing_uncertainty_deg);
    }
    return r;
}

}  // namespace fovea::daemon
