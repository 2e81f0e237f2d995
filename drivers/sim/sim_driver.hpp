// The built-in simulated tracker: the daemon's default device and the sample driver to copy.
#pragma once

#include <memory>

#include "fovea/drivers/driver.hpp"

namespace fovea::drivers::sim {

// Factory registered as "sim" in drivers/registry.cpp.
Result<std::unique_ptr<Driver>> make_driver(const toml::table& config, uint32_t device_id);

}  // namespace fovea::drivers::sim
