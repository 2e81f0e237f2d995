// The 1€ filter (Casiez, Roussel, Vogel, CHI 2012): a first-order low-pass whose cutoff rises
// with speed, so gaze is smooth at rest and lags little in motion. Matches the authors' C++
// reference vector (github.com/casiez/OneEuroFilter): derivative against the last filtered
// value, rate re-estimated from each timestamp step.
#pragma once

namespace fovea::gaze {

struct OneEuroParams {
    double min_cutoff_hz = 1.0;
    double beta = 0.0;
    double d_cutoff_hz = 1.0;
    double initial_rate_hz = 120.0;  // used until two distinct timestamps have been seen
    double reset_gap_s = 0.5;        // a longer gap restarts the filter (new fixation context)
};

// One scalar channel. Not thread-safe; one owner thread.
class OneEuroFilter {
public:
    explicit OneEuroFilter(const OneEuroParams& params = {});

    // Filter value x observed at time t (seconds). dt <= 0 keeps the last rate estimate; a
    // non-finite x or t returns NaN and leaves the state untouched.
    double filter(double x, double t_s);
    void reset();
    const OneEuroParams& params() const { return params_; }

private:
    static double alpha(double cutoff_hz, double rate_hz);

    OneEuroParams params_;
    double rate_hz_;
    bool initialized_ = false;
    double last_t_ = 0.0;
    double x_hat_ = 0.0;   // filtered value
    double dx_hat_ = 0.0;  // filtered derivative
};

}  // namespace fovea::gaze
