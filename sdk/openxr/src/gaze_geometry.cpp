#include "gaze_geometry.hpp"

#include <cmath>

namespace fovea::openxr {
namespace {

namespace profiles = drivers::profiles;

bool finite_point(double x, double y) { return std::isfinite(x) && std::isfinite(y); }
bool tracked(const fovea_eye& e) {
    return (e.valid & FOVEA_VALID) != 0 && finite_point(e.norm_x, e.norm_y);
}

// A direction from degrees of visual angle from the display centre (+x right, +y down).
Vec3 from_degrees(double deg_x, double deg_y) {
    constexpr double kDegToRad = 0.017453292519943295;
    return normalized(eye_to_view({std::tan(deg_x * kDegToRad), std::tan(deg_y * kDegToRad), 1.0}));
}

}  // namespace

GazeGeometry::GazeGeometry(const fovea_eye_geometry& g) {
    if (!(g.ipd_m > 0)) return;
    for (int e = 0; e < 2; ++e) {
        profiles::EyeView v;
        v.fov_left_deg = g.fov_deg[e][0];
        v.fov_right_deg = g.fov_deg[e][1];
        v.fov_up_deg = g.fov_deg[e][2];
        v.fov_down_deg = g.fov_deg[e][3];
        eyes_[e] = profiles::tangents(v);
    }
    mean_ = {(eyes_[0].left + eyes_[1].left) / 2, (eyes_[0].right + eyes_[1].right) / 2,
             (eyes_[0].up + eyes_[1].up) / 2, (eyes_[0].down + eyes_[1].down) / 2};
    has_views_ = true;
    ipd_m_ = g.ipd_m;
}

Vec3 GazeGeometry::through_mean_view(double nx, double ny) const {
    return normalized(eye_to_view(profiles::direction_from_normalized(mean_, nx, ny)));
}

std::optional<Vec3> GazeGeometry::combined(const fovea_gaze_record& r) const {
    if (r.event == FOVEA_EVENT_BLINK) return std::nullopt;  // lids over the pupil drag the gaze
    if (!has_views_) {
        if (!(r.combined.valid & FOVEA_VALID) || !finite_point(r.combined.deg_x, r.combined.deg_y))
            return std::nullopt;
        return from_degrees(r.combined.deg_x, r.combined.deg_y);
    }
    const bool l = tracked(r.left), rt = tracked(r.right);
    if (l && rt) {
        const auto dl = profiles::direction_from_normalized(eyes_[0], r.left.norm_x, r.left.norm_y);
        const auto dr =
            profiles::direction_from_normalized(eyes_[1], r.right.norm_x, r.right.norm_y);
        const profiles::VergencePoint v =
            profiles::vergence({-ipd_m_ / 2, 0, 0}, dl, {ipd_m_ / 2, 0, 0}, dr);
        if (v.valid) return normalized(eye_to_view(v.cyclopean));
        return normalized(eye_to_view({dl[0] + dr[0], dl[1] + dr[1], dl[2] + dr[2]}));
    }
    if (l || rt) {
        const fovea_eye& e = l ? r.left : r.right;
        return normalized(
            eye_to_view(profiles::direction_from_normalized(eyes_[l ? 0 : 1], e.norm_x, e.norm_y)));
    }
    if (tracked(r.combined)) return through_mean_view(r.combined.norm_x, r.combined.norm_y);
    return std::nullopt;
}

std::optional<Vec3> GazeGeometry::landing(const fovea_gaze_record& r, const Vec3& current) const {
    if (!(r.flags & FOVEA_FLAG_LANDING_VALID)) return std::nullopt;
    Vec3 from, to;
    if (has_views_) {
        if (!finite_point(r.landing_norm_x, r.landing_norm_y) ||
            !finite_point(r.combined.norm_x, r.combined.norm_y))
            return std::nullopt;
        from = through_mean_view(r.combined.norm_x, r.combined.norm_y);
        to = through_mean_view(r.landing_norm_x, r.landing_norm_y);
    } else {
        if (!finite_point(r.landing_deg_x, r.landing_deg_y) ||
            !finite_point(r.combined.deg_x, r.combined.deg_y))
            return std::nullopt;
        from = from_degrees(r.combined.deg_x, r.combined.deg_y);
        to = from_degrees(r.landing_deg_x, r.landing_deg_y);
    }
    return normalized(rotate(rotation_between(from, to), current));
}

}  // namespace fovea::openxr
