#include "fovea/gaze/kalman.hpp"

#include <algorithm>
#include <cmath>

namespace fovea::gaze {

KalmanCv::KalmanCv(const KalmanParams& params) : params_(params) {}

void KalmanCv::reset() { initialized_ = false; }

double KalmanCv::filter(double z, double t_s) {
    if (!std::isfinite(z) || !std::isfinite(t_s)) return std::nan("");
    const double r = params_.measurement_sd * params_.measurement_sd;
    if (initialized_ && (t_s - last_t_ > params_.reset_gap_s || t_s < last_t_ - 1.0)) reset();
    if (!initialized_) {
        initialized_ = true;
        last_t_ = t_s;
        p_ = z;
        v_ = 0.0;
        ppp_ = r;
        ppv_ = 0.0;
        pvv_ = params_.max_velocity * params_.max_velocity;
        return p_;
    }
    const double dt = std::max(0.0, t_s - last_t_);
    if (dt > 0.0) {
        last_t_ = t_s;
        // Predict: x = F x, P = F P F' + Q with Q from white acceleration noise.
        p_ += v_ * dt;
        const double q = params_.accel_noise * params_.accel_noise;
        const double dt2 = dt * dt;
        const double npp = ppp_ + 2.0 * dt * ppv_ + dt2 * pvv_ + q * dt2 * dt / 3.0;
        const double npv = ppv_ + dt * pvv_ + q * dt2 / 2.0;
        const double nvv = pvv_ + q * dt;
        ppp_ = npp;
        ppv_ = npv;
        pvv_ = nvv;
    }
    // Update with H = [1 0].
    const double s = ppp_ + r;
    const double kp = ppp_ / s;
    const double kv = ppv_ / s;
    const double innovation = z - p_;
    p_ += kp * innovation;
    v_ = std::clamp(v_ + kv * innovation, -params_.max_velocity, params_.max_velocity);
    const double npp = (1.0 - kp) * ppp_;
    const double npv = (1.0 - kp) * ppv_;
    const double nvv = pvv_ - kv * ppv_;
    ppp_ = npp;
    ppv_ = npv;
    pvv_ = std::max(nvv, 1e-12);
    return p_;
}

}  // namespace fovea::gaze
