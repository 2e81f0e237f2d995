// HID "Eye and Head Trackers" (usage page 0x12, HUTRR74, HID Usage Tables 1.2+): finds the
// Tracking Data input report(s) and the Capabilities / Configuration / Status feature reports
// in a parsed descriptor, wherever the descriptor puts them, and decodes them.
// Pure functions and value types: any thread.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "fovea/result.hpp"
#include "hid/descriptor.hpp"

namespace fovea::drivers::hid {

// Usage IDs on page 0x12 (checked against the HID Usage Tables' Eye and Head Trackers page).
namespace usage {
inline constexpr uint16_t kPage = 0x12;
inline constexpr uint16_t kEyeTracker = 0x01;
inline constexpr uint16_t kHeadTracker = 0x02;
inline constexpr uint16_t kTrackingData = 0x10;
inline constexpr uint16_t kCapabilities = 0x11;
inline constexpr uint16_t kConfiguration = 0x12;
inline constexpr uint16_t kStatus = 0x13;
inline constexpr uint16_t kControl = 0x14;
inline constexpr uint16_t kSensorTimestamp = 0x20;
inline constexpr uint16_t kPositionX = 0x21;
inline constexpr uint16_t kPositionY = 0x22;
inline constexpr uint16_t kPositionZ = 0x23;
inline constexpr uint16_t kGazePoint = 0x24;
inline constexpr uint16_t kLeftEyePosition = 0x25;
inline constexpr uint16_t kRightEyePosition = 0x26;
inline constexpr uint16_t kHeadPosition = 0x27;
inline constexpr uint16_t kHeadDirectionPoint = 0x28;
inline constexpr uint16_t kRotationX = 0x29;
inline constexpr uint16_t kRotationY = 0x2A;
inline constexpr uint16_t kRotationZ = 0x2B;
inline constexpr uint16_t kTrackerQuality = 0x100;
inline constexpr uint16_t kMinimumTrackingDistance = 0x101;
inline constexpr uint16_t kOptimumTrackingDistance = 0x102;
inline constexpr uint16_t kMaximumTrackingDistance = 0x103;
inline constexpr uint16_t kMaximumScreenPlaneWidth = 0x104;
inline constexpr uint16_t kMaximumScreenPlaneHeight = 0x105;
inline constexpr uint16_t kDisplayManufacturerId = 0x200;
inline constexpr uint16_t kDisplayProductId = 0x201;
inline constexpr uint16_t kDisplaySerialNumber = 0x202;
inline constexpr uint16_t kDisplayManufacturerDate = 0x203;
inline constexpr uint16_t kCalibratedScreenWidth = 0x204;
inline constexpr uint16_t kCalibratedScreenHeight = 0x205;
inline constexpr uint16_t kSamplingFrequency = 0x300;
inline constexpr uint16_t kConfigurationStatus = 0x301;
inline constexpr uint16_t kDeviceModeRequest = 0x400;
}  // namespace usage

// Configuration Status values (Status feature report).
enum class ConfigurationStatus : uint8_t {
    kUnknown = 0,
    kReady = 1,
    kConfiguring = 2,
    kScreenSetupNeeded = 3,
    kUserCalibrationNeeded = 4,
};
const char* to_string(ConfigurationStatus s);

// The values a Tracking Data report can carry, each located independently.
enum Channel : int {
    kGazeX,
    kGazeY,
    kLeftEyeX,
    kLeftEyeY,
    kLeftEyeZ,
    kRightEyeX,
    kRightEyeY,
    kRightEyeZ,
    kHeadX,
    kHeadY,
    kHeadZ,
    kHeadDirX,
    kHeadDirY,
    kHeadDirZ,
    kRotX,
    kRotY,
    kRotZ,
    kChannelCount,
};

// Where one Tracking Data input report keeps its values (indices into ReportDescriptor::fields).
struct TrackingReportLayout {
    uint8_t report_id = 0;
    uint32_t wire_bytes = 0;         // expected bytes per read, report ID byte included
    bool head_tracker = false;       // inside a Head Tracker (0x02) application collection
    std::vector<int> timestamp;      // fields concatenated little-endian (a 64-bit stamp may be
                                     // declared as 8 one-byte fields sharing the usage)
    double timestamp_tick_hz = 1e6;  // HUTRR74 timestamps count microseconds unless a unit says
    std::array<int, kChannelCount> channel{};   // field index or -1
    std::array<double, kChannelCount> scale{};  // physical value -> micrometres or degrees
};

// Every field a tracker's feature reports carry, by usage id (page 0x12), plus their report IDs.
struct FeatureLayout {
    struct Item {
        uint16_t usage = 0;
        int field = -1;
        double scale = 1.0;  // physical -> micrometres for distances, 1 otherwise
    };
    std::vector<Item> items;
    std::vector<uint8_t> report_ids;  // distinct feature report IDs to request
};

struct TrackerLayout {
    bool numbered = false;
    bool eye_tracker = false;
    bool head_tracker = false;
    std::vector<TrackingReportLayout> tracking;  // one per Tracking Data input report
    FeatureLayout features;
    uint32_t max_input_bytes = 0;
};

// Finds the tracker's reports. Fails with a clear message when the descriptor has no usable
// Tracking Data input report on page 0x12.
Result<TrackerLayout> locate_tracker(const ReportDescriptor& desc);

// One decoded Tracking Data report. Distances in micrometres (HUTRR74's unit) in the tracker's
// frame, angles in degrees. A channel outside its logical range (the HID null value) is absent.
struct TrackingSample {
    uint8_t report_id = 0;
    bool head_tracker = false;
    std::optional<uint64_t> timestamp;  // device ticks, see TrackingReportLayout::timestamp_tick_hz
    std::optional<std::array<double, 2>> gaze_um;  // on the screen plane, origin top-left
    std::optional<std::array<double, 3>> left_eye_um, right_eye_um;
    std::optional<std::array<double, 3>> head_position_um, head_direction_point_um;
    std::optional<std::array<double, 3>> rotation_deg;  // about X, Y, Z
};

enum class DecodeStatus : uint8_t {
    kOk,
    kUnknownReport,  // a report ID this layout does not know (other collections): ignored
    kTooShort,       // fewer bytes than the descriptor declares: dropped
};

// Decodes one input report as read from hidraw (with its ID byte when numbered). Reports longer
// than declared are decoded from their declared prefix (the kernel may pad).
DecodeStatus decode_tracking(const ReportDescriptor& desc, const TrackerLayout& layout,
                             std::span<const uint8_t> report, TrackingSample& out);

// Capabilities, Configuration and Status, merged from whichever feature reports were read.
struct TrackerInfo {
    std::optional<uint32_t> tracker_quality;
    std::optional<double> min_tracking_distance_um, optimum_tracking_distance_um,
        max_tracking_distance_um;
    std::optional<double> max_screen_width_um, max_screen_height_um;
    std::optional<uint32_t> display_manufacturer_id, display_product_id, display_serial_number,
        display_manufacturer_date;
    std::optional<double> calibrated_screen_width_um, calibrated_screen_height_um;
    std::optional<double> sampling_frequency_hz;
    ConfigurationStatus configuration_status = ConfigurationStatus::kUnknown;
};

// Merges one feature report (with its ID byte when numbered) into `info`. Returns the number of
// values taken from it.
int decode_feature(const ReportDescriptor& desc, const TrackerLayout& layout,
                   std::span<const uint8_t> report, TrackerInfo& info);

// Gaze on the screen plane (micrometres from the top-left corner) to normalized display
// coordinates (0..1). NaN when the screen size is unknown or not positive.
std::array<double, 2> gaze_to_normalized(const std::array<double, 2>& gaze_um,
                                         double screen_width_um, double screen_height_um);

}  // namespace fovea::drivers::hid
