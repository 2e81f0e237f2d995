// Attach to an instance's gaze ring, waiting for fovead to create it if needed.
#pragma once

#include <memory>
#include <string>

#include "fovea/client.hpp"

namespace fovea::cli {

// Throws std::runtime_error (one clear line) if no ring appears within timeout_ms.
std::unique_ptr<Client> open_ring(const std::string& instance, int timeout_ms);

}  // namespace fovea::cli
