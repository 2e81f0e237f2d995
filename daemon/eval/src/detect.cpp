#include "fovea/eval/detect.hpp"

#include "fovea/gaze/pipeline.hpp"

namespace fovea::eval {

std::vector<gaze::DetectorInput> detector_input(const Recording& r) {
    std::vector<gaze::DetectorInput> out(r.samples.size());
    for (size_t i = 0; i < out.size(); ++i) {
        const Degrees d = degrees(r, i);
        out[i].t_s = seconds(r, i);
        out[i].x_deg = d.x;
        out[i].y_deg = d.y;
        out[i].valid = d.valid;
    }
    return out;
}

std::vector<gaze::Event> detect(const Recording& r, gaze::DetectorMode mode,
                                const gaze::DetectorParams& params) {
    gaze::PipelineConfig c;
    c.clock = gaze::DeviceClock{64, 1e6};  // device_ticks are µs, received without latency
    c.display = r.display;
    c.nominal_rate_hz = r.rate_hz;
    c.detector = params;
    c.detector_mode = mode;
    c.filter = gaze::FilterKind::kOneEuro;
    if (mode == gaze::DetectorMode::kOffline) {
        c.offline_thresholds =
            gaze::EventDetector::estimate_thresholds(detector_input(r), params, r.rate_hz);
    }
    gaze::Pipeline pipeline(c);
    std::vector<gaze::Event> events;
    events.reserve(r.samples.size());
    std::vector<gaze::GazeSample> out;
    for (const auto& s : r.samples) {
        pipeline.process(s, out);
        for (const auto& g : out) events.push_back(g.event);
    }
    pipeline.flush(out);
    for (const auto& g : out) events.push_back(g.event);
    return events;
}

}  // namespace fovea::eval
