// Saccade landing prediction while the saccade is in flight (Arabadzhiyska et al. 2017): the
// displacement observed since onset is fitted to a main-sequence saccade of unknown amplitude A,
// whose duration D(A) and velocity profile follow from A. The fit's amplitude, along the current
// direction, is the landing point; its uncertainty shrinks as more of the saccade is seen.
#pragma once

#include <array>
#include <span>

namespace fovea::gaze {

struct LandingParams {
    // Main sequence fitted to the lund2013 labels (../shared/data/README.md).
    double peak_velocity_dps = 560.0;  // Vp = peak * (1 - exp(-A / c))
    double peak_c_deg = 4.25;
    double duration_slope_ms = 2.6;  // D = slope * A + intercept
    double duration_intercept_ms = 17.0;
    int max_fit_points = 12;  // observed samples used by the fit (evenly spaced)
    // Velocity profile ~ Beta(a, b) in normalised time; (3, 3) is minimum jerk. Early-peaked
    // shapes closer to the labelled data's mean profile (~(1.5, 2)) make the amplitude fit
    // unstable early in flight (README.md, "Landing prediction"), so the default stays (3, 3).
    double profile_a = 3.0;
    double profile_b = 3.0;
};

struct LandingEstimate {
    bool valid = false;
    double x_deg = 0.0, y_deg = 0.0;  // predicted landing point
    double amplitude_deg = 0.0;
    double duration_s = 0.0;       // predicted total duration
    double fraction = 0.0;         // elapsed / predicted duration
    double uncertainty_deg = 0.0;  // 1-sigma radius
};

class LandingPredictor {
public:
    explicit LandingPredictor(const LandingParams& params = {});

    // Samples since onset: t relative to onset (s), positions in degrees; [0] is the onset.
    LandingEstimate predict(std::span<const double> t_s, std::span<const double> x_deg,
                            std::span<const double> y_deg) const;

    double duration_s(double amplitude_deg) const;
    // Normalised position profile s(tau) in [0,1] of a saccade of amplitude A at tau = t/D.
    double profile(double tau, double amplitude_deg) const;

private:
    static constexpr int kSteps = 256;
    LandingParams p_;
    std::array<double, kSteps + 1> cdf_{};  // position profile table
};

}  // namespace fovea::gaze
