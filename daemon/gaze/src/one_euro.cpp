#include "fovea/gaze/one_euro.hpp"

#include <cmath>
#include <numbers>

namespace fovea::gaze {

OneEuroFilter::OneEuroFilter(const OneEuroParams& params)
    : params_(params), rate_hz_(params.initial_rate_hz) {}

void OneEuroFilter::reset() {
    initialized_ = false;
    rate_hz_ = params_.initial_rate_hz;
    dx_hat_ = 0.0;
}

double OneEuroFilter::alpha(double cutoff_hz, double rate_hz) {
    const double te = 1.0 / rate_hz;
    const double tau = 1.0 / (2.0 * std::numbers::pi * cutoff_hz);
    return 1.0 / (1.0 + tau / te);
}

double OneEuroFilter::filter(double x, double t_s) {
    if (!std::isfinite(x) || !std::isfinite(t_s)) return std::nan("");
    if (initialized_ && t_s - last_t_ > params_.reset_gap_s) reset();
    if (!initialized_) {
        initialized_ = true;
        last_t_ = t_s;
        x_hat_ = x;
        dx_hat_ = 0.0;
        return x;
    }
    // As in the reference: the rate only changes when time advances.
    if (t_s > last_t_) {
        rate_hz_ = 1.0 / (t_s - last_t_);
        last_t_ = t_s;
    }
    // As in the authors' vector: the derivative is taken against the last filtered value.
    const double dx = (x - x_hat_) * rate_hz_;
    const double ad = alpha(params_.d_cutoff_hz, rate_hz_);
    dx_hat_ = ad * dx + (1.0 - ad) * dx_hat_;
    const double cutoff = params_.min_cutoff_hz + params_.beta * std::fabs(dx_hat_);
    const double a = alpha(cutoff, rate_hz_);
    x_hat_ = a * x + (1.0 - a) * x_hat_;
    return x_hat_;
}

}  // namespace fovea::gaze
