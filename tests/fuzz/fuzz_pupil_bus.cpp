// libFuzzer target: one message from Pupil Capture's bus as the live `pupil` driver receives it,
// [topic frame, msgpack datum frame] (decode_bus_message, then host_ticks). The first byte is the
// topic frame's length, 0xff a message of one frame only. Invariants: no crash; a sample has a
// finite Pupil time and finite coordinates for its valid eyes; what is not a sample says why.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "pupil/pupil_bus.hpp"

using namespace fovea::drivers::pupil;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size == 0) return 0;
    const char* text = reinterpret_cast<const char*>(data) + 1;
    std::vector<std::string> frames;
    if (data[0] == 0xff) {
        frames.emplace_back(text, size - 1);
    } else {
        const std::size_t topic_len = std::min<std::size_t>(data[0], size - 1);
        frames.emplace_back(text, topic_len);
        frames.emplace_back(text + topic_len, size - 1 - topic_len);
    }
    for (const double min_confidence : {0.0, 0.6}) {
        const BusMessage m = decode_bus_message(frames, min_confidence);
        if (m.kind == BusMessage::Kind::kMalformed && m.why.empty()) std::abort();
        if (m.kind != BusMessage::Kind::kSample) continue;
        if (!std::isfinite(m.pupil_time_s)) std::abort();
        for (const auto* e : {&m.sample.left, &m.sample.right})
            if (e->valid && !(std::isfinite(e->x) && std::isfinite(e->y))) std::abort();
        for (const double offset : {0.0, m.pupil_time_s, -1e300, 1e300})
            (void)host_ticks(m.pupil_time_s, offset);
    }
    return 0;
}
