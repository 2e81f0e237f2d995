#include "zmq_gaze.hpp"

#include <zmq.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <string_view>

#include "fovea/msgpack_read.hpp"

namespace fovea::daemon {
namespace {

constexpr const char* kEventNames[] = {"unknown", "fixation", "saccade", "pso", "pursuit", "blink"};

// --- encoding -------------------------------------------------------------------------------

// The wire datum: msgpack-cxx writes each struct as a map keyed by its member names, so the
// keys and their count have one owner (the member list).
using Pair = std::array<double, 2>;

struct WireEye {
    Pair norm_pos;  // Pupil's origin: bottom-left
    Pair gaze_deg;
    double pupil_mm;
    bool valid;
    MSGPACK_DEFINE_MAP(norm_pos, gaze_deg, pupil_mm, valid)
};

struct WireSaccade {
    int64_t onset_ns;
    double amplitude_deg, peak_velocity_dps, direction_deg;
    MSGPACK_DEFINE_MAP(onset_ns, amplitude_deg, peak_velocity_dps, direction_deg)
};

struct WireLanding {
    Pair norm_pos, gaze_deg;
    double uncertainty_deg;
    MSGPACK_DEFINE_MAP(norm_pos, gaze_deg, uncertainty_deg)
};

// Pupil's gaze datum keys (topic, norm_pos, confidence, timestamp) and every Fovea field.
struct WireGaze {
    std::string topic;
    Pair norm_pos;
    double confidence, timestamp;
    uint64_t index;
    std::string event;
    uint64_t flags, device_id;
    int64_t t_capture_ns, t_receive_ns, t_processed_ns, t_publish_ns;
    double clock_uncertainty_us;
    WireEye left, right, combined;
    WireSaccade saccade;
    WireLanding landing;
    MSGPACK_DEFINE_MAP(topic, norm_pos, confidence, timestamp, index, event, flags, device_id,
                       t_capture_ns, t_receive_ns, t_processed_ns, t_publish_ns,
                       clock_uncertainty_us, left, right, combined, saccade, landing)
};

// Pupil's normalized coordinates have their origin bottom-left; Fovea's top-left.
double flip_y(double y) { return 1.0 - y; }

WireEye wire_eye(const fovea_eye& e) {
    return {
        {e.norm_x, flip_y(e.norm_y)}, {e.deg_x, e.deg_y}, e.pupil_mm, (e.valid & FOVEA_VALID) != 0};
}

// --- decoding -------------------------------------------------------------------------------

using msgpack_read::find;
using msgpack_read::integer;
using msgpack_read::number;
using msgpack_read::pair;

bool eye(const msgpack::object* o, fovea_eye& e) {
    double norm[2], deg[2];
    const auto pupil = number(find(*o, "pupil_mm"));
    const msgpack::object* valid = find(*o, "valid");
    if (!pair(find(*o, "norm_pos"), norm) || !pair(find(*o, "gaze_deg"), deg) || !pupil || !valid ||
        valid->type != msgpack::type::BOOLEAN)
        return false;
    e.norm_x = static_cast<float>(norm[0]);
    e.norm_y = static_cast<float>(flip_y(norm[1]));
    e.deg_x = static_cast<float>(deg[0]);
    e.deg_y = static_cast<float>(deg[1]);
    e.pupil_mm = static_cast<float>(*pupil);
    e.valid = valid->via.boolean ? FOVEA_VALID : 0;
    return true;
}

Result<void> fovea_fields(const msgpack::object& m, fovea_gaze_record& r) {
    auto need_int = [&](const char* k, auto& out) -> bool {
        auto v = integer(find(m, k));
        if (v) out = static_cast<std::remove_reference_t<decltype(out)>>(*v);
        return v.has_value();
    };
    if (!need_int("index", r.index) || !need_int("t_capture_ns", r.t_capture_ns) ||
        !need_int("t_receive_ns", r.t_receive_ns) ||
        !need_int("t_processed_ns", r.t_processed_ns) ||
        !need_int("t_publish_ns", r.t_publish_ns) || !need_int("flags", r.flags) ||
        !need_int("device_id", r.device_id))
        return make_error("a Fovea integer field is missing or not an integer");
    const msgpack::object* ev = find(m, "event");
    if (!ev || ev->type != msgpack::type::STR) return make_error("event: not a string");
    const std::string_view event(ev->via.str.ptr, ev->via.str.size);
    r.event = FOVEA_EVENT_UNKNOWN;
    for (uint32_t i = 0; i < std::size(kEventNames); ++i)
        if (event == kEventNames[i]) r.event = i;
    if (auto u = number(find(m, "clock_uncertainty_us")))
        r.clock_uncertainty_us = static_cast<float>(*u);
    for (auto [key, e] :
         {std::pair{"left", &r.left}, {"right", &r.right}, {"combined", &r.combined}}) {
        const msgpack::object* o = find(m, key);
        if (!o || !eye(o, *e)) return make_error(std::string(key) + ": malformed eye");
    }
    if (const msgpack::object* s = find(m, "saccade")) {
        auto onset = integer(find(*s, "onset_ns"));
        auto amp = number(find(*s, "amplitude_deg"));
        auto peak = number(find(*s, "peak_velocity_dps"));
        auto dir = number(find(*s, "direction_deg"));
        if (!onset || !amp || !peak || !dir) return make_error("saccade: malformed");
        r.saccade_onset_ns = *onset;
        r.saccade_amplitude_deg = static_cast<float>(*amp);
        r.saccade_peak_velocity_dps = static_cast<float>(*peak);
        r.saccade_direction_deg = static_cast<float>(*dir);
    }
    if (const msgpack::object* l = find(m, "landing")) {
        double norm[2], deg[2];
        auto unc = number(find(*l, "uncertainty_deg"));
        if (!pair(find(*l, "norm_pos"), norm) || !pair(find(*l, "gaze_deg"), deg) || !unc)
            return make_error("landing: malformed");
        r.landing_norm_x = static_cast<float>(norm[0]);
        r.landing_norm_y = static_cast<float>(flip_y(norm[1]));
        r.landing_deg_x = static_cast<float>(deg[0]);
        r.landing_deg_y = static_cast<float>(deg[1]);
        r.landing_uncertainty_deg = static_cast<float>(*unc);
    }
    return {};
}

}  // namespace

std::string zmq_error(const std::string& what) { return what + ": " + zmq_strerror(zmq_errno()); }

ZmqMessage encode_pupil_gaze(const fovea_gaze_record& r) {
    const bool lv = r.left.valid & FOVEA_VALID, rv = r.right.valid & FOVEA_VALID;
    // Pupil's eye0 is the right eye, eye1 the left; binocular (or eye-less combined) is "01".
    ZmqMessage m;
    const fovea_eye* main = &r.combined;
    m.topic = "gaze.2d.01.";
    if (rv && !lv) {
        m.topic = "gaze.2d.0.";
        main = &r.right;
    } else if (lv && !rv) {
        m.topic = "gaze.2d.1.";
        main = &r.left;
    }
    const bool tracked = main->valid & FOVEA_VALID;

    const WireGaze w{m.topic,
                     {main->norm_x, flip_y(main->norm_y)},
                     tracked ? 1.0 : 0.0,
                     static_cast<double>(r.t_capture_ns) / 1e9,
                     r.index,
                     r.event < std::size(kEventNames) ? kEventNames[r.event] : "unknown",
                     r.flags,
                     r.device_id,
                     r.t_capture_ns,
                     r.t_receive_ns,
                     r.t_processed_ns,
                     r.t_publish_ns,
                     r.clock_uncertainty_us,
                     wire_eye(r.left),
                     wire_eye(r.right),
                     wire_eye(r.combined),
                     {r.saccade_onset_ns, r.saccade_amplitude_deg, r.saccade_peak_velocity_dps,
                      r.saccade_direction_deg},
                     {{r.landing_norm_x, flip_y(r.landing_norm_y)},
                      {r.landing_deg_x, r.landing_deg_y},
                      r.landing_uncertainty_deg}};
    msgpack::sbuffer buf;
    msgpack::pack(buf, w);
    m.payload.assign(buf.data(), buf.size());
    return m;
}

Result<ZmqGaze> decode_pupil_gaze(const std::string& topic, const std::string& payload) {
    msgpack::object_handle oh;
    if (auto r = msgpack_read::unpack_one(payload, oh); !r)
        return make_error("payload is not one msgpack object: " + r.error().message);
    const msgpack::object& m = oh.get();
    if (m.type != msgpack::type::MAP) return make_error("payload is not a msgpack map");
    ZmqGaze g;
    g.topic = topic;
    const msgpack::object* t = find(m, "topic");
    if (!t || t->type != msgpack::type::STR ||
        std::string_view(t->via.str.ptr, t->via.str.size) != topic)
        return make_error("topic field missing or different from the topic frame");
    auto conf = number(find(m, "confidence"));
    auto ts = number(find(m, "timestamp"));
    if (!pair(find(m, "norm_pos"), g.norm_pos) || !conf || !ts)
        return make_error("norm_pos, confidence or timestamp missing or malformed");
    g.confidence = *conf;
    g.timestamp = *ts;
    if (find(m, "index") && find(m, "t_capture_ns")) {
        if (auto r = fovea_fields(m, g.record); !r) return r.error();
        g.fovea_fields = true;
    } else {
        g.record.combined.norm_x = static_cast<float>(g.norm_pos[0]);
        g.record.combined.norm_y = static_cast<float>(flip_y(g.norm_pos[1]));
        g.record.combined.valid = g.confidence > 0 ? FOVEA_VALID : 0;
        g.record.t_capture_ns = static_cast<int64_t>(std::llround(g.timestamp * 1e9));
    }
    return g;
}

// --- subscriber -----------------------------------------------------------------------------

Result<std::unique_ptr<ZmqGazeSubscriber>> ZmqGazeSubscriber::connect(const std::string& endpoint,
                                                                      const std::string& prefix,
                                                                      int receive_hwm) {
    std::unique_ptr<ZmqGazeSubscriber> s(new ZmqGazeSubscriber());
    s->counts_gaps_ = std::string_view("gaze.").starts_with(prefix);
    s->context_ = zmq_ctx_new();
    if (!s->context_) return make_error(zmq_error("zmq: cannot create a context"));
    s->socket_ = zmq_socket(s->context_, ZMQ_SUB);
    if (!s->socket_) return make_error(zmq_error("zmq: cannot create a SUB socket"));
    const int linger = 0;
    if (zmq_setsockopt(s->socket_, ZMQ_RCVHWM, &receive_hwm, sizeof receive_hwm) != 0 ||
        zmq_setsockopt(s->socket_, ZMQ_LINGER, &linger, sizeof linger) != 0 ||
        zmq_setsockopt(s->socket_, ZMQ_SUBSCRIBE, prefix.data(), prefix.size()) != 0)
        return make_error(zmq_error("zmq: setsockopt"));
    if (zmq_connect(s->socket_, endpoint.c_str()) != 0)
        return make_error(zmq_error("zmq: cannot connect to " + endpoint));
    return s;
}

ZmqGazeSubscriber::~ZmqGazeSubscriber() {
    if (socket_) zmq_close(socket_);
    if (context_) zmq_ctx_term(context_);
}

void ZmqGazeSubscriber::count_gap(uint64_t index) {
    if (!counts_gaps_) return;
    if (have_index_ && index + kReorderSpan < newest_index_) {  // a restarted publisher
        missed_before_ = missed();
        have_index_ = false;
    }
    if (!have_index_) {
        have_index_ = true;
        first_index_ = newest_index_ = index;
        received_ = 1;
        return;
    }
    if (index < first_index_) return;  // sent before the first one seen here
    newest_index_ = std::max(newest_index_, index);
    ++received_;
}

uint64_t ZmqGazeSubscriber::missed() const {
    const uint64_t span = have_index_ ? newest_index_ - first_index_ + 1 : 0;
    return missed_before_ + (span > received_ ? span - received_ : 0);
}

Result<std::optional<ZmqGaze>> ZmqGazeSubscriber::receive(int timeout_ms) {
    using Clock = std::chrono::steady_clock;
    const auto end = Clock::now() + std::chrono::milliseconds(timeout_ms);
    for (;;) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - Clock::now());
        zmq_pollitem_t item{socket_, 0, ZMQ_POLLIN, 0};
        const int n = zmq_poll(&item, 1, std::max<long>(0, left.count()));
        if (n < 0) return make_error(zmq_error("zmq: poll"));
        if (n == 0) return std::optional<ZmqGaze>{};
        // Read every frame of the message; Pupil messages may carry extra raw-data frames.
        std::string frames[2];
        int count = 0;
        for (bool more = true; more; ++count) {
            zmq_msg_t msg;
            zmq_msg_init(&msg);
            if (zmq_msg_recv(&msg, socket_, 0) < 0) {
                zmq_msg_close(&msg);
                return make_error(zmq_error("zmq: receive"));
            }
            if (count < 2)
                frames[count].assign(static_cast<const char*>(zmq_msg_data(&msg)),
                                     zmq_msg_size(&msg));
            more = zmq_msg_more(&msg);
            zmq_msg_close(&msg);
        }
        if (count >= 2) {
            auto g = decode_pupil_gaze(frames[0], frames[1]);
            if (g) {
                if (g->fovea_fields) count_gap(g->record.index);
                return std::optional<ZmqGaze>(std::move(g).value());
            }
        }
        ++malformed_;
        if (Clock::now() >= end) return std::optional<ZmqGaze>{};
    }
}

}  // namespace fovea::daemon
