// Per-hop latency histograms and their JSON form (the "latency" object of `status`).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>

#include <nlohmann/json_fwd.hpp>

#include "fovea/latency_histogram.hpp"
#include "fovea/result.hpp"

namespace fovea::gaze {
struct GazeSample;
}

namespace fovea::record {

// The hops of a gaze sample's life, in order. The daemon measures the first three, the client
// (SDK or `fovea latency`) the rest.
enum class Hop : int {
    kCaptureToReceive = 0,    // device capture (mapped to host clock) -> host receive
    kReceiveToProcessed = 1,  // host receive -> gaze chain done
    kProcessedToPublish = 2,  // gaze chain done -> written into the ring
    kPublishToRead = 3,       // ring -> read by a client
    kReadToFrameBegin = 4,    // client read -> frame that uses it begins
    kFrameBeginToSubmit = 5,  // frame begin -> command buffer submitted
    kSubmitToPresent = 6,     // submitted -> presented (where the host reports it)
};
inline constexpr int kHopCount = 7;

// Stable JSON key of a hop, e.g. "capture_to_receive".
std::string_view hop_name(Hop hop);
std::optional<Hop> hop_from_name(std::string_view name);

// One histogram per hop. Threading: each hop has one writer thread (the daemon loop for the
// device hops); to_json() may run on any thread.
class LatencyStats {
public:
    LatencyHistogram& hop(Hop h) { return hops_[static_cast<std::size_t>(h)]; }
    const LatencyHistogram& hop(Hop h) const { return hops_[static_cast<std::size_t>(h)]; }

    // Record the device-side hops of a processed sample published at t_publish_ns.
    void record_published(const gaze::GazeSample& s, int64_t t_publish_ns);
    void merge(const LatencyStats& o);
    void reset();

    // {"<hop>": {count, negative, p50_us, p90_us, p99_us, p999_us, max_us, min_us, mean_us,
    //            buckets: [[index, count], ...]}, ...} -- empty hops are left out.
    // With include_buckets = false only the summary numbers are written.
    nlohmann::json to_json(bool include_buckets = true) const;
    // Accepts what to_json(true) wrote; unknown hop names are ignored. Replaces *this.
    static Result<LatencyStats> from_json(const nlohmann::json& j);

private:
    std::array<LatencyHistogram, kHopCount> hops_;
};

nlohmann::json histogram_to_json(const LatencyHistogram& h, bool include_buckets = true);
Result<void> histogram_from_json(const nlohmann::json& j, LatencyHistogram& out);

}  // namespace fovea::record
