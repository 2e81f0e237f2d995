// The [zmq] table of the daemon configuration (the publisher itself: zmq_publisher.hpp):
//   [zmq]
//   publish = "tcp://127.0.0.1:50020"   # any ZeroMQ bind endpoint; port "*" picks a free one
//   send_hwm = 100000                   # messages queued per subscriber before ZeroMQ drops
//   remote = "tcp://127.0.0.1:50021"    # optional Pupil Remote (REQ/REP): "SUB_PORT", "t", "v"
// With `remote`, Pupil tools that first ask Pupil Remote for the SUB_PORT connect unchanged.
#pragma once

#include <string>

#include <toml++/toml.h>

#include "fovea/result.hpp"

namespace fovea::daemon {

struct ZmqConfig {
    std::string publish;     // bind endpoint; "" disables the publisher
    int send_hwm = 100'000;  // ZMQ_SNDHWM: ~100 s of 1 kHz gaze per slow subscriber
    std::string remote;      // Pupil Remote REP endpoint; "" = none
};

// Validate the [zmq] table; errors name the key ("zmq.publish: ...").
Result<ZmqConfig> parse_zmq_config(const toml::table& table, const std::string& origin);

}  // namespace fovea::daemon
