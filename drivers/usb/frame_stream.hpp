// The serial protocol's frames (drivers/serial/PROTOCOL.md) as they arrive in USB IN transfers:
// transfer payloads are concatenated into one byte stream and split by the serial driver's
// FrameDecoder (no second parser). Hello before samples, sequence gaps counted. No I/O.
// Owned by the USB event thread.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "fovea/gaze/sample.hpp"
#include "serial/protocol.hpp"

namespace fovea::drivers::usb {

class FrameStream {
public:
    struct Counters {
        uint64_t samples = 0;
        uint64_t dropped = 0;  // rejected chunks + undecodable payloads + samples before hello
        uint64_t lost = 0;     // gaps in the device's sequence counter
        uint64_t resyncs = 0;
    };

    // Feeds one transfer's bytes; appends good samples (device_id and t_receive_ns set).
    void feed(std::span<const uint8_t> bytes, int64_t t_receive_ns, uint32_t device_id,
              std::vector<gaze::RawSample>& out);
    // A new device session: partial frames, hello and sequence state are dropped.
    void reset();

    const std::optional<serial::Hello>& hello() const { return hello_; }
    Counters counters() const;

private:
    serial::FrameDecoder decoder_;
    serial::SequenceTracker seq_;
    std::optional<serial::Hello> hello_;
    uint64_t payload_dropped_ = 0, lost_ = 0, samples_ = 0;
};

}  // namespace fovea::drivers::usb
