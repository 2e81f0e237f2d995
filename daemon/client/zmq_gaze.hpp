// Fovea gaze over ZeroMQ in the shape of Pupil Labs' network API, so Pupil-ecosystem consumers
// on other machines can subscribe unchanged:
//   multipart [topic, msgpack map], topics "gaze.2d.01." (binocular), "gaze.2d.0." (right eye
//   only, Pupil's eye0), "gaze.2d.1." (left eye only, eye1); the map holds "topic", "norm_pos"
//   (Pupil convention: origin bottom-left), "confidence" (1 tracked / 0 not: Fovea trackers report
//   validity, not a confidence), "timestamp" (seconds of the host CLOCK_MONOTONIC at capture)
//   and Fovea's own fields (index, event, t_*_ns, flags, device_id, left/right/combined eyes,
//   saccade, landing).
// The message format and the subscriber; fovead's publisher is daemon/src/zmq_publisher.hpp.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "fovea/result.hpp"
#include "fovea/ring.h"

namespace fovea::daemon {

// "<what>: <zmq_strerror(zmq_errno())>", the error every ZeroMQ call here reports.
std::string zmq_error(const std::string& what);

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

// The subscriber side (`fovea watch --zmq`, tests). One thread.
class ZmqGazeSubscriber {
public:
    // Connect a SUB socket to `endpoint`, subscribed to topics starting with `prefix`, queueing
    // at most `receive_hwm` messages that were received but not yet read.
    static Result<std::unique_ptr<ZmqGazeSubscriber>> connect(const std::string& endpoint,
                                                              const std::string& prefix = "gaze.",
                                                              int receive_hwm = 1'000'000);
    ~ZmqGazeSubscriber();
    ZmqGazeSubscriber(const ZmqGazeSubscriber&) = delete;
    ZmqGazeSubscriber& operator=(const ZmqGazeSubscriber&) = delete;

    // The next well-formed message, nullopt after `timeout_ms` without one. Malformed messages
    // are skipped and counted.
    Result<std::optional<ZmqGaze>> receive(int timeout_ms);
    uint64_t malformed() const { return malformed_; }
    // Samples a Fovea publisher sent after the first message received here that have not
    // arrived: ring indices between the first and the newest received that were never seen. A
    // PUB socket drops at a slow subscriber's high-water mark without telling the sender, so
    // only the receiving side can count them. Several devices' samples may arrive out of index
    // order (each device's look-ahead is its own), so a sample still in flight counts until it
    // arrives. 0 under a prefix narrower than "gaze." (the other topics' samples are not
    // missing). An index that falls back by more than kReorderSpan is a restarted publisher:
    // what was missed before is kept and counting starts again.
    uint64_t missed() const;
    static constexpr uint64_t kReorderSpan = 1 << 16;

private:
    ZmqGazeSubscriber() = default;
    void count_gap(uint64_t index);
    void* context_ = nullptr;
    void* socket_ = nullptr;
    uint64_t malformed_ = 0;
    bool counts_gaps_ = true;
    bool have_index_ = false;
    uint64_t first_index_ = 0, newest_index_ = 0, received_ = 0;  // since the last restart
    uint64_t missed_before_ = 0;                                  // before it
};

}  // namespace fovea::daemon
