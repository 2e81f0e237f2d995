// fovead's configuration: a TOML file (--config FILE, /etc/fovea/fovead.toml by default when
// it exists) with command-line overrides. Every problem is one clear line naming the key.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "fovea/gaze/sample.hpp"
#include "fovea/result.hpp"
#include "zmq_publisher.hpp"

namespace fovea::daemon {

struct DaemonConfig {
    std::string instance = "default";
    std::string log_level = "info";
    uint32_t ring_slots = 4096;
    gaze::DisplayGeometry display;
    ZmqConfig zmq;                     // [zmq]: Pupil-style gaze fan-out, off by default
    std::vector<toml::table> devices;  // [[device]] tables; empty means one simulated tracker
    std::string source_path;           // the file it came from, "" for defaults
};

// Parse TOML text; `origin` names the source in error messages.
Result<DaemonConfig> parse_config(const std::string& text, const std::string& origin);
Result<DaemonConfig> load_config(const std::string& path);

}  // namespace fovea::daemon
