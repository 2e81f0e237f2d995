// VR eye trackers that speak OSC over UDP (EyeTrackVR and others; VRChat's and VRCFaceTracking
// v2's address sets), received with liblo on the daemon's loop.
#pragma once

#include <memory>

#include "fovea/drivers/driver.hpp"

namespace fovea::drivers::osc {

// `[[device]]` keys: port (UDP, default 9000, the port VRChat listens on; 0 = any free port),
// rate_hz (the rate the chain assumes; default 0: measured from the receipt times, 1 kHz until
// 256 frames have come), and the address map of osc_map.hpp:
// preset, addresses, range, angle_deg, fov_deg, closed_above, lid_below.
// OSC carries no device clock: samples are stamped on receipt.
Result<std::unique_ptr<Driver>> make_driver(const toml::table& config, uint32_t device_id);

}  // namespace fovea::drivers::osc
