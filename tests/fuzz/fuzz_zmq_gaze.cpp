// libFuzzer target: the ZeroMQ fan-out's decoder (`fovea watch`, any SUB client of ours) on a
// [topic, payload] message from the network: the first byte splits the input into the two frames.
// Invariants: no crash; what decodes re-encodes and decodes to the same Fovea fields.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "zmq_gaze.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size == 0) return 0;
    const std::size_t topic_len = std::min<std::size_t>(data[0], size - 1);
    const std::string topic(reinterpret_cast<const char*>(data) + 1, topic_len);
    const std::string payload(reinterpret_cast<const char*>(data) + 1 + topic_len,
                              size - 1 - topic_len);
    auto g = fovea::daemon::decode_pupil_gaze(topic, payload);
    if (!g || !g->fovea_fields) return 0;
    const auto m = fovea::daemon::encode_pupil_gaze(g->record);
    auto again = fovea::daemon::decode_pupil_gaze(m.topic, m.payload);
    if (!again || !again->fovea_fields) std::abort();
    const auto &a = g->record, &b = again->record;
    if (a.index != b.index || a.t_capture_ns != b.t_capture_ns || a.flags != b.flags ||
        a.device_id != b.device_id || a.saccade_onset_ns != b.saccade_onset_ns)
        std::abort();
    return 0;
}
