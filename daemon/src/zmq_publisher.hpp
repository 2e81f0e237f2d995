// Optional fan-out of published gaze over ZeroMQ (the message format: zmq_gaze.hpp).
// Enabled by the [zmq] table of the daemon configuration (zmq_config.hpp).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "fovea/result.hpp"
#include "fovea/ring.h"
#include "zmq_config.hpp"
#include "zmq_gaze.hpp"

namespace fovea::daemon {

class Daemon;

// The PUB socket. Created and used on the daemon's loop thread only.
class ZmqPublisher {
public:
    static Result<std::unique_ptr<ZmqPublisher>> bind(const ZmqConfig& config);
    ~ZmqPublisher();
    ZmqPublisher(const ZmqPublisher&) = delete;
    ZmqPublisher& operator=(const ZmqPublisher&) = delete;

    // Never blocks: a message ZeroMQ refuses (EAGAIN) is counted in `failed`.
    void publish(const fovea_gaze_record& record);
    // Answer every pending Pupil Remote request without blocking (loop thread).
    void serve_remote();
    bool has_remote() const { return remote_ != nullptr; }
    // The bound endpoints with the real ports (ZMQ_LAST_ENDPOINT).
    const std::string& endpoint() const { return endpoint_; }
    const std::string& remote_endpoint() const { return remote_endpoint_; }
    nlohmann::json status() const;

private:
    ZmqPublisher() = default;
    void* context_ = nullptr;
    void* socket_ = nullptr;
    void* remote_ = nullptr;
    std::string endpoint_;
    std::string remote_endpoint_;
    int send_hwm_ = 0;
    uint64_t remote_requests_ = 0;
    uint64_t sent_ = 0;
    uint64_t failed_ = 0;
};

// If the configuration enables it, bind the publisher and feed it every published sample
// (Daemon::add_published_observer) and add a "zmq" status section. Called from Daemon::start.
Result<void> attach_zmq_publisher(Daemon& daemon);

}  // namespace fovea::daemon
