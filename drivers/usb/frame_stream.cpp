#include "usb/frame_stream.hpp"

namespace fovea::drivers::usb {

void FrameStream::feed(std::span<const uint8_t> bytes, int64_t t_receive_ns, uint32_t device_id,
                       std::vector<gaze::RawSample>& out) {
    decoder_.feed(
        bytes,
        [&](const serial::Frame& f) {
            if (f.type == static_cast<uint8_t>(serial::FrameType::kHello)) {
                if (auto h = serial::decode_hello(f.payload)) {
                    hello_ = std::move(*h);
                } else {
                    ++payload_dropped_;
                }
                return;
            }
            if (f.type != static_cast<uint8_t>(serial::FrameType::kSample)) return;
            auto s = serial::decode_sample(f.payload);
            if (!s || !hello_) {  // without the hello the counter width is unknown
                ++payload_dropped_;
                return;
            }
            lost_ += seq_.on_seq(f.seq);
            if (hello_->counter_bits < 64) s->device_ticks &= (1ULL << hello_->counter_bits) - 1;
            s->t_receive_ns = t_receive_ns;
            s->device_id = device_id;
            ++samples_;
            out.push_back(*s);
        },
        [](serial::FrameDecoder::Reject) {});
}

void FrameStream::reset() {
    decoder_.reset();
    seq_.reset();
    hello_.reset();
}

FrameStream::Counters FrameStream::counters() const {
    Counters c;
    c.samples = samples_;
    c.dropped = decoder_.stats().dropped + payload_dropped_;
    c.lost = lost_;
    c.resyncs = decoder_.stats().resyncs;
    return c;
}

}  // namespace fovea::drivers::usb
