// The layer's settings, from the environment of the app it is loaded into (read at
// xrCreateInstance; see sdk/openxr/README.md):
//   FOVEA_INSTANCE                    fovead instance to read ("default")
//   FOVEA_OPENXR_GAZE=auto|replace    provide eye gaze only where the runtime has none (auto), or
//                                     always, hiding the runtime's own (replace)
//   FOVEA_OPENXR_MAX_PREDICTION_MS    furthest the pose is extrapolated past the newest sample (50)
//   FOVEA_OPENXR_STALE_MS             newest sample older than this: poses invalid (100)
//   FOVEA_OPENXR_LOG=quiet|info|debug
#pragma once

#include <string>

#include "gaze_source.hpp"

namespace fovea::openxr {

struct LayerConfig {
    bool replace_runtime_gaze = false;
    GazeSourceOptions gaze;
    std::string problems;  // settings that were ignored, for the log line
};

LayerConfig read_layer_config();

}  // namespace fovea::openxr
