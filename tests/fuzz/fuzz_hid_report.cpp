// libFuzzer: decoding input and feature reports against fixed, valid tracker descriptors
// (numbered with a 64-bit split timestamp, unnumbered with packed 12-bit fields, eye + head
// tracker behind a mouse). The first input byte picks the descriptor; the rest is the report.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "hid/session.hpp"
#include "hid/tracker_descriptors.hpp"

using namespace fovea::drivers::hid;

namespace {

const std::vector<TrackerSession>& sessions() {
    static const std::vector<TrackerSession> all = [] {
        std::vector<TrackerSession> v;
        for (const auto& bytes : fovea::test::fuzz_descriptors()) {
            auto s = TrackerSession::create(bytes, 531000, 299000);
            if (!s) __builtin_trap();  // the fixed descriptors must be valid
            v.push_back(std::move(*s));
        }
        return v;
    }();
    return all;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    const auto& all = sessions();
    TrackerSession session = all[data[0] % all.size()];
    const std::span<const uint8_t> report(data + 1, size - 1);
    fovea::gaze::RawSample s;
    fovea::drivers::HeadPose p;
    const auto out = session.on_report(report, 0, 0, s, p);
    if (out.gaze && s.left.valid && !(std::isfinite(s.left.x) && std::isfinite(s.left.y)))
        __builtin_trap();  // a valid eye always has finite coordinates
    if (out.head && p.direction_valid) {
        const double n = p.direction[0] * p.direction[0] + p.direction[1] * p.direction[1] +
                         p.direction[2] * p.direction[2];
        if (std::fabs(n - 1.0) > 1e-6) __builtin_trap();
    }
    session.apply_feature(report);
    return 0;
}
