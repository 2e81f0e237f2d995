// The "hid" driver: HID eye and head trackers on usage page 0x12, read through hidapi's hidraw
// backend on a reader thread that posts samples into the daemon's io_context.
//
// [[device]] keys: driver = "hid"; optional path = "/dev/hidrawN"; vid, pid (integers or hex
// strings "0x1234"); serial; screen_width_mm, screen_height_mm (used when the tracker's
// Configuration report gives no calibrated screen size).
#pragma once

#include <memory>

#include "fovea/drivers/driver.hpp"
#include "hid/tracker.hpp"

namespace fovea::drivers::hid {

// Factory registered as "hid" in drivers/registry.cpp.
Result<std::unique_ptr<Driver>> make_driver(const toml::table& config, uint32_t device_id);

// Head pose from a decoded head-tracker report: micrometres -> metres, the direction from head
// position to head direction point, rotation (degrees about X, Y, Z) as q = qz * qy * qx.
HeadPose to_head_pose(const TrackingSample& s);

// hidapi's one-time initialisation; any thread.
Result<void> ensure_hidapi();

}  // namespace fovea::drivers::hid
