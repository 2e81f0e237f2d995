// libFuzzer target: the serial protocol's frame decoder and payload decoders on arbitrary bytes.
// Invariants: no crash, bounded buffering, every delivered frame re-encodes to the same payload,
// every accepted sample has finite coordinates for its valid eyes.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "serial/protocol.hpp"

using namespace fovea::drivers::serial;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    FrameDecoder whole, split;
    std::vector<std::vector<uint8_t>> a, b;
    const auto on_frame = [](std::vector<std::vector<uint8_t>>& out) {
        return [&out](const Frame& f) {
            std::vector<uint8_t> p(f.payload.begin(), f.payload.end());
            if (f.type == static_cast<uint8_t>(FrameType::kSample)) {
                if (auto s = decode_sample(f.payload)) {
                    for (const auto* e : {&s->left, &s->right}) {
                        if (e->valid && !(std::isfinite(e->x) && std::isfinite(e->y))) std::abort();
                    }
                }
            } else if (f.type == static_cast<uint8_t>(FrameType::kHello)) {
                (void)decode_hello(f.payload);
            } else if (f.type == static_cast<uint8_t>(FrameType::kConfigure)) {
                (void)decode_configure(f.payload);
            }
            // Re-encoding a delivered frame and decoding it again gives the same payload.
            std::vector<uint8_t> bytes;
            encode_frame(static_cast<FrameType>(f.type), f.seq, f.payload, bytes);
            FrameDecoder again;
            int n = 0;
            again.feed(
                bytes,
                [&](const Frame& g) {
                    if (g.seq != f.seq || g.type != f.type ||
                        std::vector<uint8_t>(g.payload.begin(), g.payload.end()) != p)
                        std::abort();
                    ++n;
                },
                [](FrameDecoder::Reject) { std::abort(); });
            if (n != 1) std::abort();
            out.push_back(std::move(p));
        };
    };
    whole.feed({data, size}, on_frame(a), [](FrameDecoder::Reject) {});
    // Fed in two pieces at an input-chosen split point, the decoder must see the same frames.
    const size_t cut = size == 0 ? 0 : data[0] % (size + 1);
    split.feed({data, cut}, on_frame(b), [](FrameDecoder::Reject) {});
    split.feed({data + cut, size - cut}, on_frame(b), [](FrameDecoder::Reject) {});
    if (a != b) std::abort();
    return 0;
}
