// Finding HID eye/head trackers on this machine: hidapi (hidraw backend) enumeration filtered to
// usage page 0x12, and the raw report descriptor from sysfs (or HIDIOCGRDESC).
// Blocking file-system and ioctl calls: call from the driver's reader thread or a tool, never
// from the daemon's loop thread.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "fovea/result.hpp"

namespace fovea::drivers::hid {

struct TrackerDevice {
    std::string path;  // /dev/hidrawN
    uint16_t vendor_id = 0;
    uint16_t product_id = 0;
    uint16_t usage = 0;  // 0x01 eye tracker, 0x02 head tracker
    std::string serial, manufacturer, product;
};

// Every top-level collection on usage page 0x12. No devices is an empty list, not an error.
Result<std::vector<TrackerDevice>> enumerate_trackers();

// The report descriptor of /dev/hidrawN: /sys/class/hidraw/hidrawN/device/report_descriptor,
// falling back to the HIDIOCGRDESC ioctl on the node.
Result<std::vector<uint8_t>> read_report_descriptor(const std::string& hidraw_path);

}  // namespace fovea::drivers::hid
