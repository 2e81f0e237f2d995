// The pure geometry of display profiles: projection centres, pixels per degree, gaze directions
// to display coordinates and back, the binocular vergence point. No I/O: also linked by the
// OpenXR layer (sdk/openxr), which must not carry the TOML loader into every OpenXR app.
#include <algorithm>
#include <cmath>

#include "profiles/display_profile.hpp"

namespace fovea::drivers::profiles {
namespace {

constexpr double kDegToRad = 0.017453292519943295;
constexpr double kRadToDeg = 57.29577951308232;

double tan_deg(double d) { return std::tan(d * kDegToRad); }

double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3 add_scaled(const Vec3& a, const Vec3& d, double s) {
    return {a[0] + d[0] * s, a[1] + d[1] * s, a[2] + d[2] * s};
}

}  // namespace

double EyeView::center_x() const {
    const double l = tan_deg(fov_left_deg), r = tan_deg(fov_right_deg);
    return l / (l + r);
}
double EyeView::center_y() const {
    const double u = tan_deg(fov_up_deg), d = tan_deg(fov_down_deg);
    return u / (u + d);
}
double EyeView::pixels_per_degree_x() const {
    return width_px / (tan_deg(fov_left_deg) + tan_deg(fov_right_deg)) * tan_deg(1.0);
}
double EyeView::pixels_per_degree_y() const {
    return height_px / (tan_deg(fov_up_deg) + tan_deg(fov_down_deg)) * tan_deg(1.0);
}

gaze::DisplayGeometry DisplayProfile::display_geometry(int eye_index) const {
    gaze::DisplayGeometry g;
    const EyeView& v = eye(eye_index);
    g.width_px = v.width_px;
    g.height_px = v.height_px;
    if (kind == DisplayKind::kMonitor && width_m > 0) {
        g.width_m = width_m;
        g.height_m = height_m;
        g.distance_m = distance_m;
    } else {  // the virtual image plane at 1 m
        g.distance_m = 1.0;
        g.width_m = tan_deg(v.fov_left_deg) + tan_deg(v.fov_right_deg);
        g.height_m = tan_deg(v.fov_up_deg) + tan_deg(v.fov_down_deg);
    }
    return g;
}

EyePoint map_direction(const EyeView& view, const Vec3& d) {
    EyePoint p;
    if (!(std::isfinite(d[0]) && std::isfinite(d[1]) && std::isfinite(d[2])) || !(d[2] > 0))
        return p;  // behind or level with the eye: no point on the display
    const double tx = d[0] / d[2], ty = d[1] / d[2];
    const double l = tan_deg(view.fov_left_deg), r = tan_deg(view.fov_right_deg);
    const double u = tan_deg(view.fov_up_deg), dn = tan_deg(view.fov_down_deg);
    p.norm_x = (tx + l) / (l + r);
    p.norm_y = (ty + u) / (u + dn);
    p.px_x = p.norm_x * view.width_px;
    p.px_y = p.norm_y * view.height_px;
    p.deg_x = std::atan(tx) * kRadToDeg;
    p.deg_y = std::atan(ty) * kRadToDeg;
    p.valid = std::isfinite(p.norm_x) && std::isfinite(p.norm_y);
    p.inside = p.valid && p.norm_x >= 0 && p.norm_x <= 1 && p.norm_y >= 0 && p.norm_y <= 1;
    return p;
}

ViewTangents tangents(const EyeView& view) {
    return {tan_deg(view.fov_left_deg), tan_deg(view.fov_right_deg), tan_deg(view.fov_up_deg),
            tan_deg(view.fov_down_deg)};
}

Vec3 direction_from_normalized(const ViewTangents& t, double nx, double ny) {
    const double tx = nx * (t.left + t.right) - t.left, ty = ny * (t.up + t.down) - t.up;
    const double n = std::sqrt(tx * tx + ty * ty + 1.0);
    return {tx / n, ty / n, 1.0 / n};
}

Vec3 direction_from_normalized(const EyeView& view, double nx, double ny) {
    return direction_from_normalized(tangents(view), nx, ny);
}

VergencePoint vergence(const Vec3& p1, const Vec3& d1, const Vec3& p2, const Vec3& d2) {
    VergencePoint v;
    const double a = dot(d1, d1), b = dot(d1, d2), c = dot(d2, d2);
    if (!(a > 0) || !(c > 0)) return v;
    const double cosang = std::clamp(b / std::sqrt(a * c), -1.0, 1.0);
    v.vergence_deg = std::acos(cosang) * kRadToDeg;
    const Vec3 w0 = sub(p1, p2);
    const double d = dot(d1, w0), e = dot(d2, w0);
    const double den = a * c - b * b;
    // Parallel rays (relative to their lengths) meet at infinity: no 3D point.
    if (!(den > 1e-12 * a * c)) return v;
    const double s = (b * e - c * d) / den, t = (a * e - b * d) / den;
    if (!(s > 0) || !(t > 0)) return v;  // the rays diverge: they met behind the eyes
    const Vec3 q1 = add_scaled(p1, d1, s), q2 = add_scaled(p2, d2, t);
    const Vec3 gap = sub(q1, q2);
    v.miss_m = std::sqrt(dot(gap, gap));
    v.point_m = {(q1[0] + q2[0]) / 2, (q1[1] + q2[1]) / 2, (q1[2] + q2[2]) / 2};
    const Vec3 mid{(p1[0] + p2[0]) / 2, (p1[1] + p2[1]) / 2, (p1[2] + p2[2]) / 2};
    const Vec3 to = sub(v.point_m, mid);
    v.distance_m = std::sqrt(dot(to, to));
    if (v.distance_m > 0)
        v.cyclopean = {to[0] / v.distance_m, to[1] / v.distance_m, to[2] / v.distance_m};
    v.valid = std::isfinite(v.distance_m);
    return v;
}

VergencePoint vergence(const DisplayProfile& profile, const Vec3& left_dir, const Vec3& right_dir) {
    const double h = profile.ipd_m / 2;
    return vergence({-h, 0, 0}, left_dir, {h, 0, 0}, right_dir);
}

}  // namespace fovea::drivers::profiles
