// The Fovea serial tracker protocol v1 (drivers/serial/PROTOCOL.md): COBS-framed, CRC-32-checked
// frames. Pure code, no I/O: the serial driver, the USB driver (same frames over bulk/interrupt
// transfers), `fovea simulate serial`, the tests and the fuzz target all use it.
// Not thread-safe; each object belongs to the thread that feeds it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "fovea/gaze/sample.hpp"

namespace fovea::drivers::serial {

inline constexpr uint8_t kProtocolVersion = 1;
inline constexpr std::size_t kHeaderSize = 4;      // version, type, seq (u16 LE)
inline constexpr std::size_t kCrcSize = 4;         // CRC-32 (IEEE 802.3), LE
inline constexpr std::size_t kMaxFrameSize = 255;  // decoded: header + payload + CRC
inline constexpr std::size_t kMaxEncodedSize = kMaxFrameSize + 2;  // + COBS overhead, no delimiter

enum class FrameType : uint8_t {
    kHello = 0x01,         // device -> host: capabilities and current configuration
    kSample = 0x02,        // device -> host: one binocular sample
    kConfigure = 0x03,     // host -> device: set rate and/or baud; device answers with kHello
    kHelloRequest = 0x04,  // host -> device: ask for kHello
};

struct Hello {
    uint8_t protocol_version = kProtocolVersion;
    bool binocular = true;
    bool has_pupil = true;
    uint8_t counter_bits = 32;
    uint32_t tick_hz = 1'000'000;
    uint32_t rate_mhz = 1'000'000;  // sampling rate in milli-hertz
    uint32_t baud = 921'600;
    std::string name;  // <= 48 bytes of UTF-8
};

struct Configure {
    uint32_t rate_mhz = 0;  // 0: unchanged
    uint32_t baud = 0;      // 0: unchanged
};

// One frame after COBS decoding and CRC check; payload points into the decoder's buffer and is
// valid until the next feed().
struct Frame {
    uint8_t type = 0;
    uint16_t seq = 0;
    std::span<const uint8_t> payload;
};

uint32_t crc32(std::span<const uint8_t> data, uint32_t crc = 0);

// Encoding: appends 0x00, COBS(header | payload | CRC), 0x00.
void encode_frame(FrameType type, uint16_t seq, std::span<const uint8_t> payload,
                  std::vector<uint8_t>& out);
void encode_hello(const Hello& hello, uint16_t seq, std::vector<uint8_t>& out);
// `raw.left/right` in normalized display coordinates; invalid eyes are sent as NaN.
void encode_sample(const gaze::RawSample& raw, uint16_t seq, std::vector<uint8_t>& out);
void encode_configure(const Configure& config, uint16_t seq, std::vector<uint8_t>& out);
void encode_hello_request(uint16_t seq, std::vector<uint8_t>& out);

// Payload decoding; nullopt with `why` set when the payload is too short or values are absurd.
std::optional<Hello> decode_hello(std::span<const uint8_t> payload, std::string* why = nullptr);
std::optional<gaze::RawSample> decode_sample(std::span<const uint8_t> payload,
                                             std::string* why = nullptr);
std::optional<Configure> decode_configure(std::span<const uint8_t> payload);

// Splits a byte stream into frames. Garbage, truncated frames, oversized runs and CRC errors are
// dropped and counted; the decoder resynchronises at the next 0x00 and never loses a good frame
// that follows.
class FrameDecoder {
public:
    struct Stats {
        uint64_t bytes = 0;
        uint64_t frames = 0;         // good frames
        uint64_t dropped = 0;        // delimited chunks rejected (COBS, length, CRC, version)
        uint64_t resyncs = 0;        // times sync was lost (a run of bad chunks counts once)
        uint64_t garbage_bytes = 0;  // bytes in rejected chunks
    };
    enum class Reject { kNone, kOversize, kCobs, kShort, kCrc, kVersion };

    // Calls on_frame(const Frame&) for each good frame, on_reject(Reject) for each bad chunk.
    template <typename OnFrame, typename OnReject>
    void feed(std::span<const uint8_t> bytes, OnFrame&& on_frame, OnReject&& on_reject) {
        stats_.bytes += bytes.size();
        for (const uint8_t b : bytes) {
            if (b != 0) {
                if (encoded_.size() < kMaxEncodedSize) {
                    encoded_.push_back(b);
                } else {
                    ++overflow_;
                }
                continue;
            }
            Frame frame;
            const Reject r = finish_chunk(frame);
            if (r == Reject::kNone) {
                if (frame.type != 0) on_frame(static_cast<const Frame&>(frame));
            } else {
                on_reject(r);
            }
        }
    }
    // Drops a partial frame (the port was closed mid-frame).
    void reset();

    const Stats& stats() const { return stats_; }

private:
    Reject finish_chunk(Frame& frame);

    std::vector<uint8_t> encoded_;
    std::vector<uint8_t> decoded_ = std::vector<uint8_t>(kMaxEncodedSize);
    uint64_t overflow_ = 0;  // bytes beyond kMaxEncodedSize in the current chunk
    bool in_sync_ = true;
    Stats stats_;
};

// Sequence tracking for one connection: counts frames missing from the device's 16-bit sequence.
class SequenceTracker {
public:
    // Returns how many frames are missing before `seq` (0 when in order or on the first frame).
    uint32_t on_seq(uint16_t seq);
    void reset() { have_ = false; }

private:
    bool have_ = false;
    uint16_t expected_ = 0;
};

const char* to_string(FrameDecoder::Reject reject);

}  // namespace fovea::drivers::serial
