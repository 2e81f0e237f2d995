// Constant-velocity Kalman filter for one gaze axis: state (position, velocity), white-noise
// acceleration process model, handles variable dt. Two instances per eye.
#pragma once

namespace fovea::gaze {

struct KalmanParams {
    double accel_noise = 2000.0;   // process noise: acceleration spectral density, units/s^2
    double measurement_sd = 0.05;  // measurement noise SD, same units as the input
    double reset_gap_s = 0.5;      // a longer gap restarts from the next measurement
    double max_velocity = 1000.0;  // clamp, units/s: keeps one wild sample from diverging
};

// Not thread-safe; one owner thread.
class KalmanCv {
public:
    explicit KalmanCv(const KalmanParams& params = {});

    // Update with measurement z at time t (seconds); returns the filtered position. NaN/Inf
    // input returns NaN and leaves the state untouched; dt <= 0 is a pure measurement update.
    double filter(double z, double t_s);
    double velocity() const { return v_; }
    void reset();

private:
    KalmanParams params_;
    bool initialized_ = false;
    double last_t_ = 0.0;
    double p_ = 0.0, v_ = 0.0;                  // state
    double ppp_ = 0.0, ppv_ = 0.0, pvv_ = 0.0;  // covariance (symmetric 2x2)
};

}  // namespace fovea::gaze
