// The little linear algebra the viewer needs: column-major 4x4 matrices (GLSL layout, as
// fovea::vk::Mat4), vectors, quaternions from glTF nodes, a Vulkan perspective projection.
#pragma once

#include <array>
#include <cmath>

namespace gltfv {

using Vec3 = std::array<float, 3>;
using Mat4 = std::array<float, 16>;  // column-major: element [col * 4 + row]

inline Vec3 operator+(Vec3 a, Vec3 b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline Vec3 operator-(Vec3 a, Vec3 b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Vec3 operator*(Vec3 a, float s) { return {a[0] * s, a[1] * s, a[2] * s}; }
inline float dot(Vec3 a, Vec3 b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3 cross(Vec3 a, Vec3 b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline float length(Vec3 a) { return std::sqrt(dot(a, a)); }
inline Vec3 normalize(Vec3 a) {
    const float l = length(a);
    return l > 0.f ? a * (1.f / l) : Vec3{0.f, 0.f, 1.f};
}
inline Vec3 lerp(Vec3 a, Vec3 b, float t) { return a + (b - a) * t; }

inline Mat4 identity() { return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}; }
Mat4 multiply(const Mat4& a, const Mat4& b);
Vec3 transform_point(const Mat4& m, Vec3 p);
// Translation * rotation (unit quaternion x, y, z, w) * scale, as glTF composes a node.
Mat4 trs(Vec3 t, std::array<float, 4> q, Vec3 s);
Mat4 rotation_xyz_deg(Vec3 degrees);  // Euler angles applied X, then Y, then Z
Mat4 inverse(const Mat4& m);
Mat4 transpose(const Mat4& m);
float determinant3(const Mat4& m);  // of the upper-left 3x3

// Right-handed view looking from `eye` at `target` (y up); view space looks down -z.
Mat4 look_at(Vec3 eye, Vec3 target, Vec3 up = {0.f, 1.f, 0.f});
// Vulkan clip space (y down, depth 0 at near .. 1 at far), vertical field of view.
Mat4 perspective(float fov_y_rad, float aspect, float near_z, float far_z);

}  // namespace gltfv
