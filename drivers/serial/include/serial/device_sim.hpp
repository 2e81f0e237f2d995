// The device end of a simulated serial tracker: a pseudo-terminal (posix_openpt) whose master
// side speaks the protocol, fed by the simulated tracker, with injectable faults. Used by
// `fovea simulate serial` and by the driver tests; the host side is the real serial driver
// talking to the real pty slave.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "fovea/result.hpp"
#include "serial/protocol.hpp"
#include "sim/sim_tracker.hpp"

namespace fovea::drivers::serial {

// One pty pair. The slave stays open here too (raw mode, and no EIO on the master while the
// host is away). Single-threaded.
class PtyPort {
public:
    // `link`: optional symlink updated atomically to point at the slave, so a host configured
    // with the link finds the port again after a close/reopen.
    static Result<std::unique_ptr<PtyPort>> open(const std::string& link = {});
    ~PtyPort();
    PtyPort(const PtyPort&) = delete;
    PtyPort& operator=(const PtyPort&) = delete;

    const std::string& slave_path() const { return slave_path_; }
    // What a host should open: the link if there is one, else the slave.
    const std::string& path() const { return link_.empty() ? slave_path_ : link_; }
    int master_fd() const { return master_; }

    // Non-blocking. write() returns the bytes accepted (0 when the pty buffer is full).
    Result<std::size_t> write(std::span<const uint8_t> bytes);
    Result<std::size_t> read(std::span<uint8_t> bytes);

private:
    PtyPort() = default;
    int master_ = -1, slave_ = -1;
    std::string slave_path_, link_;
};

struct FaultOptions {
    double garbage = 0.0;  // chance per frame of a burst of 1..64 random bytes before it
    double drop = 0.0;     // chance per frame of not sending it (the sequence number still moves)
    double corrupt = 0.0;  // chance per frame of flipping one of its bytes
    uint64_t seed = 1;
};

// Turns simulated samples into protocol bytes, applies faults and answers host requests.
class DeviceEmulator {
public:
    struct Stats {
        uint64_t frames = 0;  // frames put on the wire intact (hellos included)
        uint64_t hellos = 0;
        uint64_t dropped = 0;    // frames skipped on purpose (--drop)
        uint64_t corrupted = 0;  // frames sent with a flipped byte (--corrupt)
        uint64_t garbage_bursts = 0;
        uint64_t host_frames = 0;  // requests understood
    };

    DeviceEmulator(const sim::SimConfig& sim, const FaultOptions& faults, std::string name);

    // Appends the hello frame (capabilities, current configuration).
    void hello(std::vector<uint8_t>& out);
    // Appends the next sample's bytes (maybe with faults); `sample` gets the clean sample.
    void next_sample(std::vector<uint8_t>& out, gaze::RawSample* sample = nullptr);
    // Feeds bytes from the host; appends replies (hello after a request or a configuration).
    void on_host_bytes(std::span<const uint8_t> bytes, std::vector<uint8_t>& out);

    double rate_hz() const { return sim_config_.rate_hz; }
    uint32_t baud() const { return baud_; }
    const Stats& stats() const { return stats_; }

private:
    sim::SimConfig sim_config_;
    FaultOptions faults_;
    std::string name_;
    std::unique_ptr<sim::SimTracker> tracker_;
    uint64_t rng_;
    uint16_t seq_ = 0;
    uint64_t last_ticks_ = 0;
    uint32_t baud_ = 921'600;
    FrameDecoder host_decoder_;
    Stats stats_;

    double uniform();
};

}  // namespace fovea::drivers::serial
