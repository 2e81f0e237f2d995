// Serial trackers speaking the Fovea serial protocol (PROTOCOL.md) over boost::asio::serial_port.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "fovea/drivers/driver.hpp"

namespace fovea::drivers::serial {

// `[[device]]` keys: port (required), baud, rate_hz (asks the device to switch; 0 = keep),
// reconnect_min_ms, reconnect_max_ms, counter_bits and tick_hz (the clock describe() reports
// until the device's hello says otherwise).
struct SerialConfig {
    std::string port;
    uint32_t baud = 921'600;
    double rate_hz = 0.0;
    int reconnect_min_ms = 50;
    int reconnect_max_ms = 2000;
    int counter_bits = 32;
    double tick_hz = 1e6;
};

Result<SerialConfig> parse_config(const toml::table& config);

// Factory registered as "serial" in drivers/registry.cpp.
Result<std::unique_ptr<Driver>> make_driver(const toml::table& config, uint32_t device_id);
std::unique_ptr<Driver> make_serial_driver(const SerialConfig& config, uint32_t device_id);

}  // namespace fovea::drivers::serial
