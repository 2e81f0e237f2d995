// Pupil Capture / Pupil Service through their network API: Pupil Remote (ZeroMQ REQ) for the
// bus port, version and clock, then a SUB socket on the bus for gaze (or pupil) datums.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "fovea/drivers/driver.hpp"

namespace fovea::drivers::pupil {

// `[[device]]` keys: address (Pupil Remote, default "tcp://127.0.0.1:50020"), topics (default
// ["gaze.3d."]; also "gaze.2d.", "gaze." or "pupil."), min_confidence (0.6, Pupil's own),
// rate_hz (the rate the chain's filters assume; default 0: measured from the datums' time
// stamps, 1 kHz until 256 have come), sync_interval_s (how often the
// clock is re-synced, default 5), sync_rounds ("t" round trips per sync, default 20),
// set_pupil_clock (send "T" so Pupil time = host time; moves Pupil's clock under every other
// client, so default false), request_timeout_ms (500), silence_s (no datum for this long: ask
// Pupil Remote whether Capture is still there; default 2), reconnect_min_ms (100),
// reconnect_max_ms (5000).
struct PupilConfig {
    std::string address = "tcp://127.0.0.1:50020";
    std::vector<std::string> topics = {"gaze.3d."};
    double min_confidence = 0.6;
    double rate_hz = 0.0;  // 0: measured (RateMeter)
    double sync_interval_s = 5.0;
    int sync_rounds = 20;
    bool set_pupil_clock = false;
    int request_timeout_ms = 500;
    double silence_s = 2.0;
    int reconnect_min_ms = 100;
    int reconnect_max_ms = 5000;
};

Result<PupilConfig> parse_config(const toml::table& config);

// Factory registered as "pupil" in drivers/registry.cpp.
Result<std::unique_ptr<Driver>> make_driver(const toml::table& config, uint32_t device_id);

}  // namespace fovea::drivers::pupil
