// Replays a recording (recording.hpp) as a live device: at its original timing, scaled, or as
// fast as possible.
#pragma once

#include <memory>
#include <string>

#include "fovea/drivers/driver.hpp"

namespace fovea::drivers::replay {

// `[[device]]` keys: path (required), speed (1.0 = original timing, 2.0 = twice as fast,
// 0 = as fast as possible), loop (start over at the end; default false).
struct ReplayConfig {
    std::string path;
    double speed = 1.0;
    bool loop = false;
};

Result<ReplayConfig> parse_config(const toml::table& config);

// Factory registered as "replay" in drivers/registry.cpp. Loads the file (errors are reported
// here, not at open()).
Result<std::unique_ptr<Driver>> make_driver(const toml::table& config, uint32_t device_id);
Result<std::unique_ptr<Driver>> make_replay_driver(const ReplayConfig& config, uint32_t device_id);

}  // namespace fovea::drivers::replay
