// Saccade landing prediction while the saccade is in flight (after Arabadzhiyska et al. 2017):
// up to three estimates of the amplitude A along the onset-to-now direction, combined:
//   1. profile: the displacement d observed after t is A * s(t / D(A)) for a minimum-jerk
//      position profile s; of the (up to two) amplitudes that explain d, the one whose
//      profile speed at t is closest to the eye's current speed;
//   2. remaining distance: the eye still has D(A) - t to go and decelerates roughly linearly
//      from its current speed v to zero, so A = d + c * v * (D(A) - t), linear in A;
//   3. once the speed has clearly peaked (v < peak_passed_ratio x the highest speed seen), the
//      same remaining distance with the duration taken from the observed peak speed Vp instead
//      of the main sequence: D = r * A / Vp (r = peak / mean speed), so
//      A = d + c * v * (r * A / Vp - t), again linear in A. The labels' duration scatters
//      +-17 % around the main sequence; the peak speed carries part of that per-saccade scatter.
// The profile estimate runs low when the real profile peaks early, the deceleration estimates
// run high while the eye is still accelerating; the base prediction is their geometric mean.
// Late in flight (predicted elapsed fraction >= ~0.65) the base prediction overshoots when it
// still expects much distance to go, and undershoots while the eye is still fast: a 3-constant
// log-linear late correction (LateCorrection), fitted on labelled saccades, fixes most of that.
// The correction ramps in with the phase t / D(A_phase), A_phase the geometric mean of the base
// prediction and the same three estimates taken at the speed fit's mean time: the line fit's
// slope is the speed ~1.5 sample intervals before the newest sample, so the base estimates pair
// the newest displacement with an older, faster speed in the slow-down. That lag grows as the
// rate falls (3 ms at 500 Hz, 6-7.5 ms at 200-250 Hz) and overshoots late in flight, which kept
// the phase low and the correction off at 200-250 Hz; the estimates at the mean time (one
// instant's displacement, speed and time) undershoot at mid-flight instead. Opposite biases are
// combined as the three estimates are, by a geometric mean; the prediction itself keeps the
// base estimates (with the mean-time ones the 50 % point is worse: daemon/eval/README.md).
// Computing both sets costs ~1.9x per predict() (BM_LandingPredictCall 1.5 -> 2.8 us): still
// well under 1 % of a core at 1 kHz, and only while a saccade is in flight.
// `fovea eval-landing --cv dataset` refits it without each dataset; the measurements behind the
// constants below are in daemon/eval/README.md ("Landing").
#pragma once

#include <array>
#include <span>

#include "fovea/gaze/main_sequence.hpp"

namespace fovea::gaze {

struct LandingParams {
    // The duration a saccade of amplitude A is expected to last (main_sequence.hpp).
    MainSequence main_sequence = kLund2013Labels;
    // Position profile of estimate 1 ~ Beta(a, b) in normalised time; (3, 3) is minimum jerk.
    // Early-peaked shapes closer to the labels' mean profile (~(1.5, 2)) make the first root
    // ill-conditioned: their slow start fits any large amplitude as well as the right one.
    double profile_a = 3.0;
    double profile_b = 3.0;
    // Estimates 2 and 3: remaining distance = factor x speed x remaining time. 1/2 is a linear
    // slow-down (minimum jerk: 0.53 at mid-flight); early-peaked profiles with long tails, as
    // the labels have, want less. Trades the 50 % point against the 75 % one.
    double deceleration_factor = 0.40;
    // Current speed and position: a line through the newest samples, so that one noisy sample
    // sets neither. A 6 ms time span instead did not generalize better (daemon/eval/README.md).
    int speed_fit_samples = 4;
    // Estimate 3. r = Vp * D / A: 15/8 for a minimum-jerk profile, near the labels' median.
    double peak_to_mean_speed = 1.875;
    // The peak counts as passed when the current speed is below this fraction of the highest
    // speed seen: above the ~5-10 % that noise alone moves a 4-sample line fit at 500 Hz.
    double peak_passed_ratio = 0.85;
    double max_amplitude_deg = 60.0;
    // Uncertainty radius = scale x A x f^-power (+ position noise, at most max_amplitude_deg),
    // f = t / D(A) the predictor's own elapsed fraction. Early estimates run far low (the eye
    // has covered little and is still accelerating), so the error shrinks steeply with f. The
    // scale is fitted (the 2/3 quantile, `eval-landing --cv`) for ~2/3 coverage at 25, 50 and
    // 75 % of the duration.
    double uncertainty_scale = 0.04;
    double uncertainty_power = 3.0;
    double position_noise_deg = 0.1;
    // Late correction: log(A / A_base) = bias + displacement x d / A_base + speed x v / Vp
    // (d covered distance, v current and Vp highest speed so far), blended in linearly as the
    // phase (LandingObservation::phase_fraction) goes from late_from to late_full (fitted where
    // it is >= 0.65; the ramp avoids a jump there). Least absolute log error over labelled
    // saccades > 2 deg at 15-95 % of their durations (fit_late_correction; `fovea eval-landing
    // --cv` reproduces the constants). A_base overshoots when it still expects much distance this
    // late (d / A_base small: up to ~1/4 pulled back) and undershoots while the eye is fast.
    double late_bias = -1.353;
    double late_displacement = 1.359;
    double late_speed = 0.246;
    double late_from = 0.60;
    double late_full = 0.70;
    // Pushes beyond A_base are capped (log units): the labels reward pushes (the coders include
    // slow saccade ends), abruptly ending profiles punish them (minimum jerk at 95 % of its
    // duration is overshot by ~8 % of the amplitude uncapped).
    double late_max_log_push = 0.03;
};

// What a prediction is made from (exposed for fitting the late correction and for tests).
struct LandingObservation {
    bool valid = false;
    double x0_deg = 0.0, y0_deg = 0.0;  // onset
    double ux = 0.0, uy = 0.0;          // unit direction onset -> newest sample
    double elapsed_s = 0.0;
    double displacement_deg = 0.0;    // along (ux, uy), line fit through the newest samples
    double speed_dps = 0.0;           // same fit's slope
    double peak_speed_dps = 0.0;      // highest earlier fit slope (>= speed_dps)
    double base_amplitude_deg = 0.0;  // geometric mean of the three estimates
    // Geometric mean of the base amplitude and the three estimates at the speed fit's mean
    // time, and the late correction's phase: elapsed / D(phase amplitude), <= 1.
    double phase_amplitude_deg = 0.0;
    double phase_fraction = 0.0;
};

// One training row of the late correction: an observation and the amplitude along its
// direction where the saccade really landed.
struct LateCorrectionRow {
    LandingObservation obs;
    double landed_along_deg = 0.0;
};
struct LateCorrection {
    double bias = 0.0, displacement = 0.0, speed = 0.0;
    size_t rows = 0;  // rows in the fit (late enough)
};

struct LandingEstimate {
    bool valid = false;
    double x_deg = 0.0, y_deg = 0.0;  // predicted landing point
    double amplitude_deg = 0.0;
    double duration_s = 0.0;       // predicted total duration
    double fraction = 0.0;         // elapsed / predicted duration
    double uncertainty_deg = 0.0;  // radius holding ~2/3 of the errors (see LandingParams)
};

class LandingPredictor {
public:
    explicit LandingPredictor(const LandingParams& params = {});

    // Samples since onset: t relative to onset (s), positions in degrees; [0] is the onset.
    LandingEstimate predict(std::span<const double> t_s, std::span<const double> x_deg,
                            std::span<const double> y_deg) const;
    // predict() = estimate(observe()).
    LandingObservation observe(std::span<const double> t_s, std::span<const double> x_deg,
                               std::span<const double> y_deg) const;
    LandingEstimate estimate(const LandingObservation& obs) const;
    // Weight of the late correction at a phase (0 before late_from, 1 from late_full).
    double late_weight(double phase_fraction) const;
    // Least-absolute-log-error fit of the late correction's three constants over the rows whose
    // phase is past the ramp's midpoint (IRLS); the other constants stay as they are.
    LateCorrection fit_late_correction(std::span<const LateCorrectionRow> rows) const;

    double duration_s(double amplitude_deg) const;
    // Normalised position profile s(tau) in [0,1] of a saccade of amplitude A at tau = t/D.
    double profile(double tau, double amplitude_deg) const;

    // The two amplitude estimates (exposed for tests and tools).
    double amplitude_from_profile(double elapsed_s, double displacement_deg,
                                  double speed_dps) const;
    double amplitude_from_deceleration(double elapsed_s, double displacement_deg,
                                       double speed_dps) const;
    // Estimate 3; NaN while the peak speed has not clearly been passed.
    double amplitude_from_peak(double elapsed_s, double displacement_deg, double speed_dps,
                               double peak_speed_dps) const;

private:
    static constexpr int kSteps = 256;
    double speed_profile(double tau) const;  // d s / d tau
    LandingParams p_;
    std::array<double, kSteps + 1> cdf_{};  // position profile table
};

}  // namespace fovea::gaze
