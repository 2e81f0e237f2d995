// Samples as they flow through the gaze chain (DESIGN.md §1, §3). Knows nothing of drivers,
// Asio or the ring: the same types run live in fovead and offline in the CLI.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

namespace fovea::gaze {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Values match fovea_event in sdk/include/fovea/ring.h.
enum class Event : uint8_t {
    kUnknown = 0,
    kFixation = 1,
    kSaccade = 2,
    kPso = 3,
    kPursuit = 4,
    kBlink = 5,
};

// One eye as a tracker reports it. x/y are normalized display coordinates (0..1, origin
// top-left) unless a calibration maps them from raw tracker units.
struct EyeSample {
    double x = kNaN;
    double y = kNaN;
    double pupil_mm = 0.0;  // 0 where the tracker does not report it
    bool valid = false;
};

// The device's clock as its counter reports it; ClockSync unwraps and maps it to host time.
struct DeviceClock {
    int counter_bits = 64;  // 16, 32 or 64
    double tick_hz = 1e9;   // counter ticks per second
    // The driver already mapped device time to host CLOCK_MONOTONIC ns (Pupil: by "t" round
    // trips): ClockSync passes the ticks through and reports sync_uncertainty_us.
    bool host_synced = false;
    double sync_uncertainty_us = 0.0;
};

// What a driver hands to the chain: one tracker frame, untouched but for unit conversion.
struct RawSample {
    uint64_t device_ticks = 0;  // the device counter as read (may wrap at counter_bits)
    int64_t t_receive_ns = 0;   // host CLOCK_MONOTONIC when the bytes arrived
    EyeSample left, right;
    uint32_t device_id = 0;
    // Ground-truth event where the source knows it (the simulated tracker, labelled replays).
    Event truth = Event::kUnknown;
};

struct SaccadeInfo {
    int64_t onset_ns = 0;
    double amplitude_deg = 0.0;
    double peak_velocity_dps = 0.0;
    double direction_deg = 0.0;
    bool landing_valid = false;
    double landing_x = kNaN, landing_y = kNaN;  // normalized display coordinates
    double landing_deg_x = kNaN, landing_deg_y = kNaN;
    double landing_uncertainty_deg = 0.0;
};

// One processed sample: what fovead publishes into the ring and the recorder logs.
struct GazeSample {
    int64_t t_capture_ns = 0;  // device time mapped to host CLOCK_MONOTONIC
    int64_t t_receive_ns = 0;
    int64_t t_processed_ns = 0;
    double clock_uncertainty_us = 0.0;
    bool clock_converged = false;
    EyeSample left, right, combined;              // filtered, normalized display coordinates
    double left_deg_x = kNaN, left_deg_y = kNaN;  // visual angle from the display centre
    double right_deg_x = kNaN, right_deg_y = kNaN;
    double combined_deg_x = kNaN, combined_deg_y = kNaN;
    Event event = Event::kUnknown;
    SaccadeInfo saccade;
    bool calibrated = false;
    uint32_t device_id = 0;
    Event truth = Event::kUnknown;
};

// Display geometry for normalized <-> degrees. A flat screen at a distance, or an HMD eye
// given by its field of view (then width_m/height_m/distance_m describe the virtual image plane).
struct DisplayGeometry {
    int width_px = 1920;
    int height_px = 1080;
    double width_m = 0.531;  // 24" 16:9 monitor
    double height_m = 0.299;
    double distance_m = 0.60;

    // Visual angle of a normalized point from the display centre, degrees (+x right, +y down).
    void to_degrees(double nx, double ny, double& deg_x, double& deg_y) const {
        constexpr double kRadToDeg = 57.29577951308232;
        deg_x = std::atan2((nx - 0.5) * width_m, distance_m) * kRadToDeg;
        deg_y = std::atan2((ny - 0.5) * height_m, distance_m) * kRadToDeg;
    }
    void to_normalized(double deg_x, double deg_y, double& nx, double& ny) const {
        constexpr double kDegToRad = 0.017453292519943295;
        nx = 0.5 + std::tan(deg_x * kDegToRad) * distance_m / width_m;
        ny = 0.5 + std::tan(deg_y * kDegToRad) * distance_m / height_m;
    }
    // Pixels per degree at the display centre.
    double pixels_per_degree() const {
        constexpr double kDegToRad = 0.017453292519943295;
        return std::tan(kDegToRad) * distance_m / width_m * width_px;
    }
};

}  // namespace fovea::gaze
