// Maps a device's sample counter to host CLOCK_MONOTONIC. Receive time = capture time + a
// latency that is never negative, so the lower envelope of (receive - device time) is the
// offset: we keep per-bin minima over a sliding window and fit offset + skew (drift) to them.
// Counters of 16/32/64 bits at any tick rate are unwrapped; a device reset or a host clock
// step shows as a run of inconsistent samples and restarts the estimate.
#pragma once

#include <cstdint>
#include <deque>

#include "fovea/gaze/sample.hpp"

namespace fovea::gaze {

struct ClockSyncParams {
    double window_s = 10.0;           // history the fit uses
    double bin_s = 0.25;              // one minimum per bin
    int min_bin_samples = 200;        // ... and at least this many samples per bin
    int min_bins = 4;                 // bins before the skew fit is trusted (converged)
    double step_threshold_s = 0.002;  // a sample earlier than predicted by this is inconsistent
    double late_threshold_s = 0.5;    // a sample later than predicted by this is inconsistent
    int step_confirm = 5;             // consecutive inconsistent samples that mean a clock step
};

struct ClockMapping {
    int64_t host_ns = 0;          // device time of the sample on the host clock
    double uncertainty_us = 0.0;  // 1-sigma estimate of the mapping error
    bool converged = false;
};

// Not thread-safe: one owner thread (the daemon's loop thread, or the CLI).
class ClockSync {
public:
    explicit ClockSync(const DeviceClock& clock, const ClockSyncParams& params = {});

    // Feed one sample's counter and receive time; returns its capture time on the host clock.
    ClockMapping update(uint64_t device_ticks, int64_t receive_ns);

    uint64_t resets() const { return resets_; }              // re-convergences (steps/resets)
    uint64_t inconsistent() const { return inconsistent_; }  // samples mapped by fallback
    double skew_ppm() const { return skew_ * 1e6; }

private:
    struct Bin {
        int64_t index;
        double dev_s;
        double offset_s;
    };
    void restart(double dev_s);
    void fit();
    double predict(double dev_s) const { return a_ + skew_ * (dev_s - tc_); }

    DeviceClock clock_;
    ClockSyncParams params_;
    uint64_t mask_;
    bool have_raw_ = false;
    uint64_t last_raw_ = 0;
    int64_t unwrapped_ = 0;  // ticks since the first sample (signed: resets go backwards)
    bool have_epoch_ = false;
    int64_t host_epoch_ns_ = 0;  // receive time of the first sample
    std::deque<Bin> bins_;
    double bin_start_ = 0.0;
    int bin_count_ = 0;
    double a_ = 0.0, skew_ = 0.0, tc_ = 0.0;  // offset(dev) = a + skew * (dev - tc)
    double fit_sd_ = 0.0;                     // SD of the offset estimate at tc
    double fit_sxx_ = 0.0;
    int fit_n_ = 0;
    bool have_estimate_ = false;
    int pending_steps_ = 0;
    uint64_t resets_ = 0;
    uint64_t inconsistent_ = 0;
};

}  // namespace fovea::gaze
