#include "pupil/pupil_bus.hpp"

#include <cmath>

#include "fovea/import/pupil_datum.hpp"
#include "pupil/pupil_remote.hpp"

namespace fovea::drivers::pupil {

BusMessage decode_bus_message(const std::vector<std::string>& frames, double min_confidence) {
    BusMessage m;
    if (frames.size() < 2) {
        m.why = "a message without a datum frame";
        return m;
    }
    auto d = import::decode_pupil_datum(frames[1]);
    if (!d) {
        m.why = "malformed datum on '" + frames[0] + "': " + d.error().message;
        return m;
    }
    if (d->topic.empty()) d->topic = frames[0];
    if (!import::pupil_sample(*d, min_confidence, m.sample)) {
        if (!d->is_gaze() && !d->is_pupil()) {
            m.kind = BusMessage::Kind::kOther;
            return m;
        }
        m.why = "datum on '" + frames[0] + "' without time stamp or norm_pos";
        return m;
    }
    m.kind = BusMessage::Kind::kSample;
    m.pupil_time_s = d->timestamp;
    return m;
}

uint64_t host_ticks(double pupil_time_s, double offset_s) {
    const double host_ns = (pupil_time_s - offset_s) * 1e9;
    return host_ns > 0 && host_ns < kMaxTimeSeconds * 1e9
               ? static_cast<uint64_t>(std::llround(host_ns))
               : 0;
}

}  // namespace fovea::drivers::pupil
