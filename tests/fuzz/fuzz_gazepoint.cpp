// libFuzzer target: the Open Gaze API element stream, element parser and record decoder.
// Invariants: no crash, bounded buffering, parsed elements survive format -> parse unchanged,
// accepted samples have finite coordinates for their valid eyes.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "gazepoint/opengaze.hpp"

using namespace fovea::drivers::gazepoint;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    ElementStream stream;
    stream.feed(text, [](const Element& e) {
        for (const ServerClock clock : {ServerClock{}, ServerClock{1e7}}) {
            for (const GazeSource src : {GazeSource::kEyes, GazeSource::kBest}) {
                std::optional<uint64_t> cnt;
                if (auto s = decode_record(e, clock, src, &cnt)) {
                    for (const auto* eye : {&s->left, &s->right}) {
                        if (eye->valid && !(std::isfinite(eye->x) && std::isfinite(eye->y)))
                            std::abort();
                    }
                }
            }
        }
        std::string formatted = format_element(e);
        formatted.resize(formatted.size() - 2);  // "\r\n"
        const auto again = parse_element(formatted);
        if (!again || again->tag != e.tag || again->attributes != e.attributes) std::abort();
    });
    (void)parse_element(text);
    return 0;
}
