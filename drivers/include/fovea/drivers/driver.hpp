// The Driver interface: one implementation per protocol under drivers/<name>/, registered with
// one line in drivers/registry.cpp. drivers/sim is the sample to copy.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>

#include <toml++/toml.h>
#include <boost/asio/io_context.hpp>

#include "fovea/gaze/sample.hpp"
#include "fovea/result.hpp"

namespace fovea::drivers {

struct DriverInfo {
    std::string driver;   // registry name: "sim", "serial", ...
    std::string name;     // human-readable device name, e.g. "Fovea serial tracker v1"
    std::string address;  // port, TCP address, VID:PID, ...
    double nominal_rate_hz = 0.0;
    gaze::DeviceClock clock;
    bool binocular = true;
    bool has_pupil = false;
};

// Counters every driver keeps; `fovea status` shows them.
struct DriverStats {
    uint64_t samples = 0;         // good samples delivered to the sink
    uint64_t frames_dropped = 0;  // malformed, wrong CRC, absurd values, ...
    uint64_t frames_lost = 0;     // gaps in the device's sequence counter
    uint64_t resyncs = 0;         // times the parser had to hunt for a frame boundary
    uint64_t bytes = 0;
    uint64_t reconnects = 0;
    bool connected = false;
    std::string last_error;
    // Driver-specific figures and texts for `fovea status` (e.g. the pupil driver's
    // "clock_offset_s", "clock_uncertainty_us", "version"); shown under "details".
    std::map<std::string, double> figures;
    std::map<std::string, std::string> notes;
};

// Called on the io_context's thread with every good sample, in order.
using SampleSink = std::function<void(const gaze::RawSample&)>;

// A head pose from a head tracker (HID usage 0x12:0x02); the daemon publishes it into a
// FOVEA_STREAM_HEAD ring (fovea_head_record). Absent parts have valid_* = false.
struct HeadPose {
    uint64_t device_ticks = 0;  // device counter as read; same clock as the device's RawSamples
    int64_t t_receive_ns = 0;   // host CLOCK_MONOTONIC when the report arrived
    double position_m[3] = {0, 0, 0};        // tracker frame, metres
    double direction[3] = {0, 0, 1};         // unit forward direction, tracker frame
    double rotation_quat[4] = {0, 0, 0, 1};  // x, y, z, w
    bool position_valid = false, direction_valid = false, rotation_valid = false;
    uint32_t device_id = 0;
};
// Called on the io_context's thread, like SampleSink.
using HeadSink = std::function<void(const HeadPose&)>;

class Driver {
public:
    virtual ~Driver() = default;

    // Start delivering samples to `sink`. Called once, on the loop thread; must not block.
    // A device that is absent is not an error: the driver keeps retrying with backoff and
    // reports connected = false. Errors are for configurations that can never work.
    virtual Result<void> open(boost::asio::io_context& io, SampleSink sink) = 0;
    // Stop and release the device. Loop thread; the sink is not called after it returns.
    virtual void close() = 0;
    // Any thread.
    virtual DriverInfo describe() const = 0;
    virtual DriverStats stats() const = 0;
    // Drivers that read head trackers publish head pose here. Call before open(), loop thread.
    virtual void set_head_sink(HeadSink /*sink*/) {}
    // Calibration: a target is shown at (x, y), normalized display coordinates, or hidden
    // (`shown` false). Simulated trackers make their eyes fixate it; real ones ignore it.
    // Returns whether this device's gaze follows the target. Loop thread.
    virtual bool follow_target(bool /*shown*/, double /*x*/, double /*y*/) { return false; }
};

// A driver is built from its `[[device]]` table of the daemon's TOML configuration.
using DriverFactory = Result<std::unique_ptr<Driver>> (*)(const toml::table& config,
                                                          uint32_t device_id);

struct DriverRegistration {
    const char* name;
    DriverFactory factory;
};

// Every driver compiled in (drivers/registry.cpp).
const DriverRegistration* registered_drivers(std::size_t& count);
// Build the driver named by config["driver"] (default "sim").
Result<std::unique_ptr<Driver>> make_driver(const toml::table& config, uint32_t device_id);

}  // namespace fovea::drivers
