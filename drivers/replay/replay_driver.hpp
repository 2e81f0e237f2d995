// Replays a recording as a live device, at its original timing, scaled, or as fast as possible.
// The file is read as it plays (fovea::import, constant memory): any format the importer reads.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "fovea/drivers/driver.hpp"
#include "fovea/import/reader.hpp"

namespace fovea::drivers::replay {

// `[[device]]` keys: path (required; a file or a Pupil recording folder), format (force one of
// fovea::import's format names; default: detected from the content), speed (1.0 = original
// timing, 2.0 = twice as fast, 0 = as fast as possible), loop (start over at the end; default
// false), min_confidence (Pupil: gaze below it is invalid; default 0.6).
struct ReplayConfig {
    std::string path;
    std::optional<import::Format> format;
    double speed = 1.0;
    bool loop = false;
    double min_confidence = 0.6;
};

Result<ReplayConfig> parse_config(const toml::table& config);

// Factory registered as "replay" in drivers/registry.cpp. Opens the file and reads its header
// (errors are reported here, not at open()).
Result<std::unique_ptr<Driver>> make_driver(const toml::table& config, uint32_t device_id);
Result<std::unique_ptr<Driver>> make_replay_driver(const ReplayConfig& config, uint32_t device_id);

}  // namespace fovea::drivers::replay
