// fovead's configuration: a TOML file (--config FILE, /etc/fovea/fovead.toml by default when
// it exists) with command-line overrides. Every problem is one clear line naming the key.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "fovea/gaze/event_detector.hpp"
#include "fovea/gaze/sample.hpp"
#include "fovea/result.hpp"
#include "fovea/ring.h"
#include "zmq_config.hpp"

namespace fovea::daemon {

// [calibration]: whose stored calibration the daemon applies at start, where calibrations
// live, and how calibrate.point collects from the live device.
struct CalibrationConfig {
    std::string user;          // "" = start uncalibrated
    std::string dir;           // "" = <state_dir()>/calibrations
    double settle_ms = 300;    // discarded after a target appears (saccadic latency)
    double collect_ms = 1000;  // then collected per target
};

// [processing] publish: what the gaze ring carries. kLive publishes every sample as soon as the
// chain has filtered it, with causal provisional event labels (FOVEA_FLAG_PROVISIONAL); kFinal
// waits for the event detector's look-ahead ([processing] lookahead_ms, default 350) so ring labels
// are final. Recordings and observers always get the final labels.
enum class PublishMode { kLive, kFinal };

struct DaemonConfig {
    std::string instance = "default";
    std::string log_level = "info";
    uint32_t ring_slots = 4096;
    gaze::DisplayGeometry display;
    // display_profile = "<name or path>" (drivers/profiles): sets `display` from the profile and,
    // for an HMD, the eye geometry the gaze ring carries for its readers (the OpenXR layer).
    std::string display_profile;  // the profile's name, "" when [display] (or the default) is used
    fovea_eye_geometry eyes{};    // zero unless display_profile names an HMD
    CalibrationConfig calibration;
    PublishMode publish = PublishMode::kLive;  // [processing] publish = "live" | "final"
    // [processing] lookahead_ms: the event detector's bound on how long a final label waits.
    double lookahead_ms = gaze::DetectorParams{}.lookahead_s * 1e3;
    ZmqConfig zmq;                     // [zmq]: Pupil-style gaze fan-out, off by default
    std::vector<toml::table> devices;  // [[device]] tables; empty means one simulated tracker
    std::string source_path;           // the file it came from, "" for defaults
};

// Parse TOML text; `origin` names the source in error messages.
Result<DaemonConfig> parse_config(const std::string& text, const std::string& origin);
Result<DaemonConfig> load_config(const std::string& path);

}  // namespace fovea::daemon
