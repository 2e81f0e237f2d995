// The whole gaze chain in one object: ClockSync -> Calibration -> Filter -> EventDetector ->
// Predictor. fovead calls it online, the CLI offline on recordings; results are identical.
#pragma once

#include <memory>
#include <vector>

#include "fovea/gaze/sample.hpp"

namespace fovea::gaze {

struct PipelineConfig {
    DeviceClock clock;
    DisplayGeometry display;
    double nominal_rate_hz = 1000.0;
    bool predict_landing = true;  // the daemon turns this off while no reader is attached
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

    void set_predict_landing(bool on);
    // Look-ahead delay of online detection, in samples (bounded, reported in status).
    int lookahead_samples() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace fovea::gaze
