#include "hid/session.hpp"

#include <cmath>

#include "hid/hid_driver.hpp"

namespace fovea::drivers::hid {

Result<TrackerSession> TrackerSession::create(std::span<const uint8_t> descriptor,
                                              double fallback_screen_width_um,
                                              double fallback_screen_height_um) {
    auto desc = parse_descriptor(descriptor);
    if (!desc) return make_error("report descriptor: " + desc.error().message);
    auto layout = locate_tracker(*desc);
    if (!layout) return layout.error();
    TrackerSession s;
    s.desc_ = std::move(*desc);
    s.layout_ = std::move(*layout);
    s.fallback_w_um_ = fallback_screen_width_um;
    s.fallback_h_um_ = fallback_screen_height_um;
    return s;
}

int TrackerSession::apply_feature(std::span<const uint8_t> report) {
    return decode_feature(desc_, layout_, report, info_);
}

double TrackerSession::screen_width_um() const {
    return info_.calibrated_screen_width_um.value_or(0) > 0 ? *info_.calibrated_screen_width_um
                                                            : fallback_w_um_;
}

double TrackerSession::screen_height_um() const {
    return info_.calibrated_screen_height_um.value_or(0) > 0 ? *info_.calibrated_screen_height_um
                                                             : fallback_h_um_;
}

gaze::DeviceClock TrackerSession::clock() const {
    gaze::DeviceClock c;
    for (const auto& t : layout_.tracking) {
        if (t.timestamp.empty()) continue;
        uint32_t bits = 0;
        for (int fi : t.timestamp) bits += desc_.fields[static_cast<std::size_t>(fi)].bit_size;
        c.counter_bits = static_cast<int>(std::min<uint32_t>(bits, 64));
        c.tick_hz = t.timestamp_tick_hz;
        break;
    }
    return c;
}

TrackerSession::Outcome TrackerSession::on_report(std::span<const uint8_t> report,
                                                  int64_t t_receive_ns, uint32_t device_id,
                                                  gaze::RawSample& sample, HeadPose& pose) const {
    Outcome out;
    TrackingSample t;
    out.status = decode_tracking(desc_, layout_, report, t);
    if (out.status != DecodeStatus::kOk) return out;
    const uint64_t ticks = t.timestamp.value_or(0);
    const bool has_head = t.head_position_um || t.head_direction_point_um || t.rotation_deg;
    if (has_head) {
        pose = to_head_pose(t);
        pose.device_ticks = ticks;
        pose.t_receive_ns = t_receive_ns;
        pose.device_id = device_id;
        out.head = true;
    }
    if (t.head_tracker && !t.gaze_um) return out;  // a head-only report carries no gaze
    sample = gaze::RawSample{};
    sample.device_ticks = ticks;
    sample.t_receive_ns = t_receive_ns;
    sample.device_id = device_id;
    if (t.gaze_um) {
        const auto n = gaze_to_normalized(*t.gaze_um, screen_width_um(), screen_height_um());
        const bool ok = std::isfinite(n[0]) && std::isfinite(n[1]);
        // One gaze point for both eyes; an eye whose position is declared but null is lost.
        const TrackingReportLayout* lay = &layout_.tracking.front();
        for (const auto& candidate : layout_.tracking)
            if (candidate.report_id == t.report_id) lay = &candidate;
        const bool left_declared = lay->channel[kLeftEyeX] >= 0;
        const bool right_declared = lay->channel[kRightEyeX] >= 0;
        for (int e = 0; e < 2; ++e) {
            gaze::EyeSample& eye = e == 0 ? sample.left : sample.right;
            const bool declared = e == 0 ? left_declared : right_declared;
            const bool seen = e == 0 ? bool(t.left_eye_um) : bool(t.right_eye_um);
            eye.x = n[0];
            eye.y = n[1];
            eye.valid = ok && (!declared || seen);
        }
    }
    out.gaze = true;
    return out;
}

HeadPose to_head_pose(const TrackingSample& s) {
    HeadPose p;
    std::array<double, 3> origin{0, 0, 0};
    if (s.head_position_um) {
        origin = *s.head_position_um;
        for (int i = 0; i < 3; ++i)
            p.position_m[i] = (*s.head_position_um)[static_cast<std::size_t>(i)] * 1e-6;
        p.position_valid = std::isfinite(p.position_m[0]) && std::isfinite(p.position_m[1]);
        if (!std::isfinite(p.position_m[2])) p.position_m[2] = 0;
    }
    if (s.head_direction_point_um) {
        double d[3];
        double norm = 0;
        for (int i = 0; i < 3; ++i) {
            const double pt = (*s.head_direction_point_um)[static_cast<std::size_t>(i)];
            d[i] = (std::isfinite(pt) ? pt : 0.0) - origin[static_cast<std::size_t>(i)];
            norm += d[i] * d[i];
        }
        norm = std::sqrt(norm);
        if (norm > 0 && std::isfinite(norm)) {
            for (int i = 0; i < 3; ++i) p.direction[i] = d[i] / norm;
            p.direction_valid = true;
        }
    }
    if (s.rotation_deg) {
        constexpr double kHalfDegToRad = 0.008726646259971648;
        const double hx = (*s.rotation_deg)[0] * kHalfDegToRad;
        const double hy = (*s.rotation_deg)[1] * kHalfDegToRad;
        const double hz = (*s.rotation_deg)[2] * kHalfDegToRad;
        const double cx = std::cos(hx), sx = std::sin(hx);
        const double cy = std::cos(hy), sy = std::sin(hy);
        const double cz = std::cos(hz), sz = std::sin(hz);
        // q = qz * qy * qx
        p.rotation_quat[0] = sx * cy * cz - cx * sy * sz;
        p.rotation_quat[1] = cx * sy * cz + sx * cy * sz;
        p.rotation_quat[2] = cx * cy * sz - sx * sy * cz;
        p.rotation_quat[3] = cx * cy * cz + sx * sy * sz;
        p.rotation_valid = std::isfinite(p.rotation_quat[3]);
    }
    return p;
}

}  // namespace fovea::drivers::hid
