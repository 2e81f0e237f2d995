// The sampling rate a tracker delivers, for protocols that never state it (Gazepoint's Open Gaze
// API, Pupil's network API, OSC). The gaze chain sizes its velocity windows and look-ahead by the
// rate, so a configured guess that is off by 2x (a 400 Hz Pupil Core behind a 200 Hz default)
// puts every window off by 2x; the daemon rebuilds the chain when describe() reports a new rate.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

namespace fovea::drivers {

// Median of the positive intervals in each window of kWindow of them: gaps (reconnects, dropped
// frames) and bursts (network batching) move a mean, not the median. Times that are not finite
// or do not advance are skipped. Not thread-safe: the driver guards it with its own mutex.
class RateMeter {
public:
    static constexpr int kWindow = 256;

    // t_s: the sample's time in seconds on any steady clock (the device's or the host's).
    void add(double t_s) {
        if (!std::isfinite(t_s)) return;
        const double dt = t_s - last_t_;
        const bool have_last = std::isfinite(last_t_);
        if (!have_last || dt > 0) last_t_ = t_s;  // a time that goes back is not a new origin
        if (!have_last || !(dt > 0)) return;
        intervals_[n_++] = dt;
        if (n_ < kWindow) return;
        auto mid = intervals_.begin() + kWindow / 2;
        std::nth_element(intervals_.begin(), mid, intervals_.end());
        rate_hz_ = std::round(1.0 / *mid);
        n_ = 0;
    }

    // Rounded to 1 Hz; 0 until the first window is complete.
    double rate_hz() const { return rate_hz_; }

private:
    std::array<double, kWindow> intervals_{};
    int n_ = 0;
    double last_t_ = NAN;
    double rate_hz_ = 0;
};

}  // namespace fovea::drivers
