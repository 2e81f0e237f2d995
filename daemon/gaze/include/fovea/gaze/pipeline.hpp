// The whole gaze chain in one object: ClockSync -> Calibration -> Filter -> EventDetector ->
// Predictor. fovead calls it online, the CLI offline on recordings; results are identical.
#pragma once

#include <memory>
#include <vector>

#include "fovea/gaze/calibration.hpp"
#include "fovea/gaze/clock_sync.hpp"
#include "fovea/gaze/event_detector.hpp"
#include "fovea/gaze/kalman.hpp"
#include "fovea/gaze/landing.hpp"
#include "fovea/gaze/one_euro.hpp"
#include "fovea/gaze/sample.hpp"

namespace fovea::gaze {

enum class FilterKind { kNone, kOneEuro, kKalman };

struct PipelineConfig {
    DeviceClock clock;
    DisplayGeometry display;
    double nominal_rate_hz = 1000.0;
    bool predict_landing = true;  // the daemon turns this off while no reader is attached
    // Published positions are filtered (in degrees); event detection sees the unfiltered,
    // calibrated signal so the filter's lag never shifts saccade onsets.
    FilterKind filter = FilterKind::kOneEuro;
    OneEuroParams one_euro{1.0, 0.1, 1.0, 1000.0, 0.5};  // deg units; see README.md
    KalmanParams kalman{};
    ClockSyncParams clock_sync{};
    DetectorParams detector{};
    DetectorMode detector_mode = DetectorMode::kOnline;
    // Offline mode only: fixed velocity thresholds (EventDetector::estimate_thresholds).
    VelocityThresholds offline_thresholds{};
    LandingParams landing{};
};

// Counters for status/diagnostics.
struct PipelineStats {
    uint64_t samples_in = 0;
    uint64_t samples_out = 0;
    uint64_t eyes_invalid = 0;     // per-eye samples that were invalid or non-finite
    uint64_t clock_fallbacks = 0;  // samples mapped by receive time (inconsistent clock)
    uint64_t clock_resets = 0;
    uint64_t predictions = 0;
};

class Pipeline {
public:
    explicit Pipeline(const PipelineConfig& config);
    ~Pipeline();
    Pipeline(Pipeline&&) noexcept;
    Pipeline& operator=(Pipeline&&) noexcept;

    // Process one raw sample. Called from one thread (the daemon's loop thread). Online
    // detection may hold samples back for a bounded look-ahead: every call appends zero or more
    // finished samples, in order, to `out` (cleared first), and flush() drains the rest.
    void process(const RawSample& raw, std::vector<GazeSample>& out);
    void flush(std::vector<GazeSample>& out);
    // The device paused: every held sample, finished with what is known now, to `out` (cleared
    // first); process() may go on afterwards with the look-ahead as before.
    void settle(std::vector<GazeSample>& out);

    void set_predict_landing(bool on);
    // The configuration this chain was built with.
    const PipelineConfig& config() const;
    // Look-ahead delay of online detection, in samples (bounded, reported in status).
    int lookahead_samples() const;

    // Replace the calibration applied to raw samples (loop thread; copy built elsewhere).
    void set_calibration(const Calibration& calibration);
    void clear_calibration();
    PipelineStats stats() const;
    // The landing prediction for a saccade in flight at the NEWEST processed sample (not yet
    // emitted because of the look-ahead). For renderers that cannot wait: publish this with
    // the latest raw gaze. False when no saccade is in flight.
    bool latest_landing(SaccadeInfo& out) const;
    // The newest processed sample, available right after process() returns, without waiting
    // for the look-ahead: filtered position, validity, clock stamps, t_processed_ns (when the
    // chain finished it) and a PROVISIONAL causal event: kSaccade while the detector sees a
    // saccade in flight (onset time, and the landing prediction when there is one), kBlink
    // when no eye is tracked, otherwise kUnknown (fixations are only known after the fact).
    // The final look-ahead labels of the same sample come later through process()'s `out`.
    // False before the first sample.
    bool latest(GazeSample& out) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace fovea::gaze
