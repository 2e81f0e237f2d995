// libFuzzer: the HID report-descriptor parser, the page 0x12 tracker locator, and decoding the
// same bytes as a report against whatever layout they describe.
#include <cstddef>
#include <cstdint>
#include <span>

#include "hid/descriptor.hpp"
#include "hid/session.hpp"
#include "hid/tracker.hpp"

using namespace fovea::drivers::hid;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::span<const uint8_t> bytes(data, size);
    auto desc = parse_descriptor(bytes);
    if (!desc) return 0;
    // Invariants the rest of the driver relies on.
    for (const auto& f : desc->fields) {
        const Report* r = desc->find_report(f.type, f.report_id);
        if (r == nullptr) __builtin_trap();
        if (uint64_t{f.bit_offset} + uint64_t{f.bit_size} * (f.is_variable() ? 1 : f.count) >
            r->bit_length)
            __builtin_trap();
        if (f.collection >= static_cast<int>(desc->collections.size())) __builtin_trap();
    }
    auto layout = locate_tracker(*desc);
    if (!layout) return 0;
    TrackingSample t;
    decode_tracking(*desc, *layout, bytes, t);
    TrackerInfo info;
    decode_feature(*desc, *layout, bytes, info);
    auto session = TrackerSession::create(bytes, 500000, 300000);
    if (session) {
        fovea::gaze::RawSample s;
        fovea::drivers::HeadPose p;
        session->on_report(bytes, 0, 0, s, p);
        session->apply_feature(bytes);
    }
    return 0;
}
