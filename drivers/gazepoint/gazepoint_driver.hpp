// Gazepoint trackers (GP3, GP3 HD) through the Open Gaze API server on TCP (default port 4242).
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "fovea/drivers/driver.hpp"
#include "gazepoint/opengaze.hpp"

namespace fovea::drivers::gazepoint {

// `[[device]]` keys: address ("host:port", default "127.0.0.1:4242"), gaze ("eyes": LPOG/RPOG
// per eye, or "best": BPOG in both), rate_hz (nominal rate to report; default: measured),
// reconnect_min_ms, reconnect_max_ms, tick_hz (TIME_TICK frequency describe() reports until
// the server acknowledges TIME_TICK_FREQUENCY; 10 MHz is Windows' usual QPC rate).
struct GazepointConfig {
    std::string host = "127.0.0.1";
    std::string port = "4242";
    GazeSource gaze = GazeSource::kEyes;
    double rate_hz = 0.0;
    int reconnect_min_ms = 100;
    int reconnect_max_ms = 2000;
    double tick_hz = 1e7;
};

Result<GazepointConfig> parse_config(const toml::table& config);

// Factory registered as "gazepoint" in drivers/registry.cpp.
Result<std::unique_ptr<Driver>> make_driver(const toml::table& config, uint32_t device_id);
std::unique_ptr<Driver> make_gazepoint_driver(const GazepointConfig& config, uint32_t device_id);

}  // namespace fovea::drivers::gazepoint
