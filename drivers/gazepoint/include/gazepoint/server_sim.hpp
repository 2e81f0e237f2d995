// A loopback Open Gaze API server fed by the simulated tracker: `fovea simulate gazepoint` and
// the driver tests. Answers SET/GET with ACK (NACK for unknown IDs) and streams REC elements with
// the fields each client enabled once it sets ENABLE_SEND_DATA. All methods run on the loop thread.
#pragma once

#include <cstdint>
#include <memory>

#include <boost/asio/io_context.hpp>

#include "fovea/result.hpp"
#include "sim/sim_tracker.hpp"

namespace fovea::drivers::gazepoint {

struct ServerOptions {
    uint16_t port = 4242;  // 0: any free port (tests)
    sim::SimConfig sim;    // rate, seed, ...; the clock is replaced by TIME_TICK's
    double tick_hz = 10'000'000.0;
    double drop = 0.0;     // chance per record of skipping it (CNT still advances)
    double garbage = 0.0;  // chance per record of stray bytes before it
};

class SimServer {
public:
    struct Stats {
        uint64_t clients = 0;  // connections accepted
        uint64_t records = 0;  // REC elements written to sockets, summed over clients
        uint64_t dropped = 0;  // records skipped on purpose
        uint64_t garbage = 0;  // garbage bursts
    };

    SimServer(boost::asio::io_context& io, const ServerOptions& options);
    ~SimServer();
    SimServer(const SimServer&) = delete;
    SimServer& operator=(const SimServer&) = delete;

    // Binds 127.0.0.1:port and starts accepting.
    Result<void> start();
    // Closes the listener and every client connection.
    void stop();
    uint16_t port() const;
    Stats stats() const;

private:
    struct Impl;
    std::shared_ptr<Impl> impl_;
};

}  // namespace fovea::drivers::gazepoint
