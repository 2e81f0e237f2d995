// GazeSample (the gaze library's) -> fovea_gaze_record (the ring's ABI).
#pragma once

#include "fovea/gaze/sample.hpp"
#include "fovea/ring.h"

namespace fovea::daemon {

// index, t_publish_ns and checksum are left for the ring writer to fill.
fovea_gaze_record to_ring_record(const gaze::GazeSample& s, bool simulated);

}  // namespace fovea::daemon
