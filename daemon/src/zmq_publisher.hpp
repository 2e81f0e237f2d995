// Optional fan-out of published gaze over ZeroMQ in the shape of Pupil Labs' network API, so
// Pupil-ecosystem consumers on other machines can subscribe unchanged:
//   multipart [topic, msgpack map], topics "gaze.2d.01." (binocular), "gaze.2d.0." (right eye
//   only, Pupil's eye0), "gaze.2d.1." (left eye only, eye1); the map holds "topic", "norm_pos"
//   (Pupil convention: origin bottom-left), "confidence" (1 tracked / 0 not: Fovea trackers report
//   validity, not a confidence), "timestamp" (seconds of the host CLOCK_MONOTONIC at capture)
//   and Fovea's own fields (index, event, t_*_ns, flags, device_id, left/right/combined eyes,
//   saccade, landing).
// Enabled by the daemon configuration:
//   [zmq]
//   publish = "tcp://127.0.0.1:50020"   # any ZeroMQ bind endpoint; port "*" picks a free one
//   send_hwm = 100000                   # messages queued per subscriber before ZeroMQ drops
//   remote = "tcp://127.0.0.1:50021"    # optional Pupil Remote (REQ/REP): "SUB_PORT", "t", "v"
// With `remote`, Pupil tools that first ask Pupil Remote for the SUB_PORT connect unchanged.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include <toml++/toml.h>
#include <nlohmann/json.hpp>

#include "fovea/result.hpp"
#include "fovea/ring.h"

namespace fovea::daemon {

class Daemon;

struct ZmqConfig {
    std::string publish;     // bind endpoint; "" disables the publisher
    int send_hwm = 100'000;  // ZMQ_SNDHWM: ~100 s of 1 kHz gaze per slow subscriber
    std::string remote;      // Pupil Remote REP endpoint; "" = none
};

// Validate the [zmq] table; errors name the key ("zmq.publish: ...").
Result<ZmqConfig> parse_zmq_config(const toml::table& table, const std::string& origin);

// One decoded message. `record` is rebuilt from Fovea's fields when present; for a foreign
// (e.g. real Pupil) publisher only combined norm (top-left origin) and t_capture_ns are set.
struct ZmqGaze {
    std::string topic;
    double norm_pos[2] = {0, 0};  // as sent: Pupil convention, origin bottom-left
    double confidence = 0;
    double timestamp = 0;
    bool fovea_fields = false;
    fovea_gaze_record record{};
};

// The two frames of one Pupil-style message for a ring record. Pure; any thread.
struct ZmqMessage {
    std::string topic;
    std::string payload;  // msgpack
};
ZmqMessage encode_pupil_gaze(const fovea_gaze_record& record);
// Parse a message; an error for anything that is not a msgpack map with the Pupil keys.
Result<ZmqGaze> decode_pupil_gaze(const std::string& topic, const std::string& payload);

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

// The subscriber side (`fovea watch --zmq`, tests). One thread.
class ZmqGazeSubscriber {
public:
    // Connect a SUB socket to `endpoint`, subscribed to topics starting with `prefix`.
    static Result<std::unique_ptr<ZmqGazeSubscriber>> connect(const std::string& endpoint,
                                                              const std::string& prefix = "gaze.");
    ~ZmqGazeSubscriber();
    ZmqGazeSubscriber(const ZmqGazeSubscriber&) = delete;
    ZmqGazeSubscriber& operator=(const ZmqGazeSubscriber&) = delete;

    // The next well-formed message, nullopt after `timeout_ms` without one. Malformed messages
    // are skipped and counted.
    Result<std::optional<ZmqGaze>> receive(int timeout_ms);
    uint64_t malformed() const { return malformed_; }

private:
    ZmqGazeSubscriber() = default;
    void* context_ = nullptr;
    void* socket_ = nullptr;
    uint64_t malformed_ = 0;
};

}  // namespace fovea::daemon
