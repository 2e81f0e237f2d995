// Rigid-pose arithmetic on OpenXR's XrPosef (unit quaternion x, y, z, w; metres), in double.
// Pure functions: any thread.
#pragma once

#include <array>
#include <cmath>

#include "xr_includes.hpp"

namespace fovea::openxr {

using Vec3 = std::array<double, 3>;

struct Quat {
    double x = 0, y = 0, z = 0, w = 1;
};

struct Pose {
    Quat q;
    Vec3 p{0, 0, 0};
};

inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }
inline Vec3 scaled(const Vec3& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
inline Vec3 add(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline Vec3 normalized(const Vec3& a) {
    const double n = norm(a);
    return n > 0 ? scaled(a, 1.0 / n) : Vec3{0, 0, -1};
}
// Angle between two directions, degrees (atan2 form: accurate for tiny angles too).
inline double angle_deg(const Vec3& a, const Vec3& b) {
    return std::atan2(norm(cross(a, b)), dot(a, b)) * 57.29577951308232;
}

inline Quat mul(const Quat& a, const Quat& b) {
    return {a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
            a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
            a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w,
            a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z};
}
inline Quat conjugate(const Quat& q) { return {-q.x, -q.y, -q.z, q.w}; }
inline Quat normalized(const Quat& q) {
    const double n = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
    return n > 0 ? Quat{q.x / n, q.y / n, q.z / n, q.w / n} : Quat{};
}
inline Vec3 rotate(const Quat& q, const Vec3& v) {
    const Vec3 u{q.x, q.y, q.z};
    const Vec3 t = scaled(cross(u, v), 2.0);
    return add(add(v, scaled(t, q.w)), cross(u, t));
}

// The shortest rotation taking unit vector `from` to unit vector `to`.
inline Quat rotation_between(const Vec3& from, const Vec3& to) {
    const double d = dot(from, to);
    if (d < -0.999999) {  // opposite: any axis perpendicular to `from`
        Vec3 axis = cross({1, 0, 0}, from);
        if (norm(axis) < 1e-6) axis = cross({0, 1, 0}, from);
        axis = normalized(axis);
        return {axis[0], axis[1], axis[2], 0};
    }
    const Vec3 c = cross(from, to);
    return normalized(Quat{c[0], c[1], c[2], 1.0 + d});
}

// Orientation whose -Z axis points along `direction` (OpenXR's forward), with the least roll
// from the view's own axes: the rotation of (0, 0, -1) onto the direction.
inline Quat look_rotation(const Vec3& direction) {
    return rotation_between({0, 0, -1}, normalized(direction));
}

inline Vec3 forward(const Quat& q) { return rotate(q, {0, 0, -1}); }

// a * b: b expressed in a's frame, then a in its parent.
inline Pose compose(const Pose& a, const Pose& b) {
    return {normalized(mul(a.q, b.q)), add(a.p, rotate(a.q, b.p))};
}
inline Pose inverse(const Pose& a) {
    const Quat qi = conjugate(a.q);
    return {qi, scaled(rotate(qi, a.p), -1.0)};
}

// Spherical interpolation of unit directions, t in [0, 1].
inline Vec3 slerp(const Vec3& a, const Vec3& b, double t) {
    const double d = std::fmax(-1.0, std::fmin(1.0, dot(a, b)));
    const double theta = std::acos(d);
    if (theta < 1e-9) return normalized(add(scaled(a, 1 - t), scaled(b, t)));
    const double s = std::sin(theta);
    return normalized(
        add(scaled(a, std::sin((1 - t) * theta) / s), scaled(b, std::sin(t * theta) / s)));
}

inline Pose from_xr(const XrPosef& p) {
    return {normalized(Quat{p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w}),
            {p.position.x, p.position.y, p.position.z}};
}
inline XrPosef to_xr(const Pose& p) {
    XrPosef r{};
    r.orientation = {static_cast<float>(p.q.x), static_cast<float>(p.q.y),
                     static_cast<float>(p.q.z), static_cast<float>(p.q.w)};
    r.position = {static_cast<float>(p.p[0]), static_cast<float>(p.p[1]),
                  static_cast<float>(p.p[2])};
    return r;
}

}  // namespace fovea::openxr
