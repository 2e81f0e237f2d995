// The Gazepoint Open Gaze API (v2) wire format: XML-like elements, one per line, e.g.
//   <SET ID="ENABLE_SEND_POG_BEST" STATE="1" />      client -> server
//   <ACK ID="ENABLE_SEND_POG_BEST" STATE="1" />      server -> client
//   <REC CNT="12" TIME_TICK="..." BPOGX="0.51" BPOGY="0.48" BPOGV="1" ... />
// Pure code, no I/O: the driver, `fovea simulate gazepoint`, the tests and the fuzz target use it.
// Not thread-safe; each object belongs to the thread that feeds it.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "fovea/gaze/sample.hpp"

namespace fovea::drivers::gazepoint {

inline constexpr std::size_t kMaxElementSize = 8192;  // longer runs are garbage
inline constexpr int kDefaultPort = 4242;

struct Element {
    std::string tag;  // "REC", "ACK", "SET", "GET", "CAL", ...
    std::vector<std::pair<std::string, std::string>> attributes;

    // The attribute's value, or nullptr.
    const std::string* get(std::string_view name) const;
};

// Parses one element `<TAG A="1" B="x" />` (also `<TAG ...>`). nullopt when malformed.
std::optional<Element> parse_element(std::string_view text);
// Formats `<TAG A="1" />\r\n`; values must not contain '"'.
std::string format_element(const Element& element);

// Splits a byte stream into elements; text outside elements and malformed or oversized
// elements are dropped and counted. Never buffers more than kMaxElementSize.
class ElementStream {
public:
    struct Stats {
        uint64_t bytes = 0;
        uint64_t elements = 0;
        uint64_t dropped = 0;        // malformed or oversized elements
        uint64_t resyncs = 0;        // runs of stray bytes or bad elements (each run counts once)
        uint64_t garbage_bytes = 0;  // non-whitespace bytes outside elements or in dropped ones
    };

    template <typename OnElement>
    void feed(std::string_view bytes, OnElement&& on_element) {
        stats_.bytes += bytes.size();
        for (const char c : bytes) {
            if (std::optional<Element> e = push(c)) on_element(static_cast<const Element&>(*e));
        }
    }
    void reset();
    const Stats& stats() const { return stats_; }

private:
    std::optional<Element> push(char c);
    void reject(std::size_t bytes);

    std::string buf_;
    bool in_element_ = false;
    bool overflow_ = false;
    char quote_ = 0;  // inside an attribute value
    bool in_sync_ = true;
    Stats stats_;
};

// What the driver needs from the ACKs before it can interpret records.
struct ServerClock {
    double tick_hz = 0.0;  // TIME_TICK_FREQUENCY; 0 until acknowledged
};

enum class GazeSource { kEyes, kBest };

// A REC element as a raw sample. device_ticks from TIME_TICK (64-bit, tick_hz from
// TIME_TICK_FREQUENCY), else from TIME (seconds) at 1 MHz. Left/right from LPOG*/RPOG*
// (falling back to BPOG* for a missing eye) or, with kBest, BPOG* in both. Pupil in mm from
// LPUPILD/RPUPILD (metres, ENABLE_SEND_EYE_*); LPD/RPD are camera pixels and are not used.
// `cnt` receives CNT when present. nullopt with `why` when a value is absurd or missing.
std::optional<gaze::RawSample> decode_record(const Element& rec, const ServerClock& clock,
                                             GazeSource source, std::optional<uint64_t>* cnt,
                                             std::string* why = nullptr);

// Commands the driver sends on connect: every ENABLE_SEND_* it uses, the tick frequency query,
// and ENABLE_SEND_DATA last.
std::vector<Element> startup_commands();

}  // namespace fovea::drivers::gazepoint
