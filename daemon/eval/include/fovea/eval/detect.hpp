// The product's gaze chain (gaze::Pipeline: clock mapping, filter, event detector) run over a
// labelled recording, exactly as fovead would run it on the same samples.
//
// Thread rules: pure functions of their arguments; run recordings on as many threads as wanted.
#pragma once

#include <vector>

#include "fovea/eval/dataset.hpp"
#include "fovea/gaze/event_detector.hpp"

namespace fovea::eval {

// What the detector sees: degrees, the mean of the valid eyes (dataset.hpp: degrees()).
std::vector<gaze::DetectorInput> detector_input(const Recording& r);

// One event per sample. Offline mode takes its thresholds from the whole recording
// (EventDetector::estimate_thresholds), online mode learns them as it goes.
std::vector<gaze::Event> detect(const Recording& r, gaze::DetectorMode mode,
                                const gaze::DetectorParams& params = {});

}  // namespace fovea::eval
