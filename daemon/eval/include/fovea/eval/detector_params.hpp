// DetectorParams by name, for experiments from the command line
// (`fovea eval-events --detector min_peak_dps=20`) without editing the shipped defaults.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "fovea/gaze/event_detector.hpp"
#include "fovea/result.hpp"

namespace fovea::eval {

// Every settable field's name, in declaration order.
std::vector<std::string> detector_param_names();

// Applies one "KEY=VALUE" assignment (VALUE a finite number; integers for integer fields).
// Errors name the key and list the valid ones. Pure; any thread.
Result<void> set_detector_param(gaze::DetectorParams& params, std::string_view assignment);

}  // namespace fovea::eval
