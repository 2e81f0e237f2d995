// Latency histograms as JSON: what an SDK client sends with latency.report (any local user may)
// and what `fovea report` reads back from a recording. Whatever from_json accepts must be a
// histogram whose percentiles are ordered inside [min, max], and must survive to_json/from_json
// unchanged.
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include <nlohmann/json.hpp>

#include "fovea/record/latency_stats.hpp"

namespace {

void check(bool ok) {
    if (!ok) std::abort();
}

void check_histogram(const fovea::LatencyHistogram& h) {
    if (h.count() == 0) return;
    check(h.min_ns() <= h.max_ns());
    uint64_t last = h.min_ns();
    for (double q : {0.0, 0.5, 0.9, 0.99, 0.999, 1.0}) {
        const uint64_t p = h.percentile(q);
        check(p >= last && p <= h.max_ns());
        last = p;
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const auto j =
        nlohmann::json::parse(std::string_view(reinterpret_cast<const char*>(data), size), nullptr,
                              /*allow_exceptions=*/false);
    if (j.is_discarded()) return 0;

    fovea::LatencyHistogram one;
    if (fovea::record::histogram_from_json(j, one)) {
        check_histogram(one);
        fovea::LatencyHistogram back;
        check(fovea::record::histogram_from_json(fovea::record::histogram_to_json(one), back).ok());
        check(fovea::record::histogram_to_json(back) == fovea::record::histogram_to_json(one));
    }

    auto stats = fovea::record::LatencyStats::from_json(j);
    if (!stats) return 0;
    for (int i = 0; i < fovea::record::kHopCount; ++i)
        check_histogram(stats->hop(static_cast<fovea::record::Hop>(i)));
    const auto written = stats->to_json(true);
    auto again = fovea::record::LatencyStats::from_json(written);
    check(again.ok() && again->to_json(true) == written);
    return 0;
}
