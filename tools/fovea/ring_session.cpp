#include "ring_session.hpp"

#include <chrono>
#include <stdexcept>
#include <thread>

namespace fovea::cli {

std::unique_ptr<Client> open_ring(const std::string& instance, int timeout_ms) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
    for (;;) {
        try {
            return std::make_unique<Client>(instance);
        } catch (const ClientError& e) {
            if (e.status() != FOVEA_E_NOT_FOUND || std::chrono::steady_clock::now() >= deadline)
                throw std::runtime_error(e.what());
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
}

}  // namespace fovea::cli
