#include "fovea/record/latency_stats.hpp"

#include <limits>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "fovea/gaze/sample.hpp"
#include "fovea/json_integer.hpp"

namespace fovea::record {

namespace {
constexpr std::array<std::string_view, kHopCount> kHopNames = {
    "capture_to_receive",  "receive_to_processed",  "processed_to_publish", "publish_to_read",
    "read_to_frame_begin", "frame_begin_to_submit", "submit_to_present"};

double us(uint64_t ns) { return static_cast<double>(ns) / 1000.0; }
}  // namespace

std::string_view hop_name(Hop hop) { return kHopNames[static_cast<std::size_t>(hop)]; }

std::optional<Hop> hop_from_name(std::string_view name) {
    for (int i = 0; i < kHopCount; ++i) {
        if (kHopNames[static_cast<std::size_t>(i)] == name) return static_cast<Hop>(i);
    }
    return std::nullopt;
}

void LatencyStats::record_published(const gaze::GazeSample& s, int64_t t_publish_ns) {
    hop(Hop::kCaptureToReceive).record(s.t_receive_ns - s.t_capture_ns);
    hop(Hop::kReceiveToProcessed).record(s.t_processed_ns - s.t_receive_ns);
    hop(Hop::kProcessedToPublish).record(t_publish_ns - s.t_processed_ns);
}

void LatencyStats::merge(const LatencyStats& o) {
    for (std::size_t i = 0; i < hops_.size(); ++i) hops_[i].merge(o.hops_[i]);
}

void LatencyStats::reset() {
    for (auto& h : hops_) h.reset();
}

nlohmann::json histogram_to_json(const LatencyHistogram& h, bool include_buckets) {
    const auto s = h.sparse();
    nlohmann::json j = {
        {"count", s.count},
        {"negative", s.negative},
        {"p50_us", us(h.percentile(0.50))},
        {"p90_us", us(h.percentile(0.90))},
        {"p99_us", us(h.percentile(0.99))},
        {"p999_us", us(h.percentile(0.999))},
        {"max_us", us(s.max_ns)},
        {"min_us", us(s.min_ns)},
        {"mean_us", h.mean_ns() / 1000.0},
    };
    if (include_buckets) {
        j["sum_ns"] = s.sum_ns;
        j["min_ns"] = s.min_ns;
        j["max_ns"] = s.max_ns;
        auto& b = j["buckets"] = nlohmann::json::array();
        for (const auto& [i, c] : s.buckets) b.push_back({i, c});
    }
    return j;
}

Result<void> histogram_from_json(const nlohmann::json& j, LatencyHistogram& out) {
    if (!j.is_object() || !j.contains("buckets") || !j["buckets"].is_array()) {
        return make_error("latency histogram JSON needs a \"buckets\" array (status with buckets)");
    }
    auto count = [](const nlohmann::json& v, const std::string& what) {
        const auto c = json_count(v);
        if (!c) throw std::invalid_argument(what + " is not a count");
        return *c;
    };
    LatencyHistogram::Sparse s;
    try {
        s.count = count(j.at("count"), "count");
        s.negative = j.contains("negative") ? count(j["negative"], "negative") : 0;
        s.sum_ns = count(j.at("sum_ns"), "sum_ns");
        s.min_ns = count(j.at("min_ns"), "min_ns");
        s.max_ns = count(j.at("max_ns"), "max_ns");
        for (const auto& b : j["buckets"]) {
            const auto index = json_integer(b.at(0), std::numeric_limits<int>::min(),
                                            std::numeric_limits<int>::max());
            if (!index) throw std::invalid_argument("bucket index");
            s.buckets.emplace_back(static_cast<int>(*index), count(b.at(1), "bucket count"));
        }
    } catch (const std::exception& e) {  // nlohmann's exceptions and the checks above
        return make_error(std::string("latency histogram JSON: ") + e.what());
    }
    if (s.count && s.min_ns > s.max_ns) {  // percentile() clamps into [min, max]
        out.reset();
        return make_error("latency histogram JSON: min_ns above max_ns");
    }
    if (!out.assign(s)) {
        return make_error("latency histogram JSON: bucket index out of range or counts != count");
    }
    return {};
}

nlohmann::json LatencyStats::to_json(bool include_buckets) const {
    nlohmann::json j = nlohmann::json::object();
    for (int i = 0; i < kHopCount; ++i) {
        const auto& h = hops_[static_cast<std::size_t>(i)];
        if (h.count() == 0) continue;
        j[std::string(kHopNames[static_cast<std::size_t>(i)])] =
            histogram_to_json(h, include_buckets);
    }
    return j;
}

Result<LatencyStats> LatencyStats::from_json(const nlohmann::json& j) {
    if (!j.is_object()) return make_error("latency JSON must be an object of hops");
    LatencyStats stats;
    for (const auto& [key, value] : j.items()) {
        const auto h = hop_from_name(key);
        if (!h) continue;
        if (auto r = histogram_from_json(value, stats.hop(*h)); !r) {
            return make_error(key + ": " + r.error().message);
        }
    }
    return stats;
}

}  // namespace fovea::record
