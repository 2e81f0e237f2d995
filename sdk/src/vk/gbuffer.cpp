// The CPU side of shaders/fovea_gbuffer.glsl: the surface texel's packing, step for step.
#include <algorithm>
#include <cmath>

#include "fovea/half.hpp"
#include "fovea/vk/gbuffer.hpp"
#include "post/image_model.hpp"

namespace fovea::vk {
namespace {

using fovea::half_bits;
using fovea::half_from_bits;

float sign_not_zero(float v) { return v >= 0.f ? 1.f : -1.f; }

// GLSL packSnorm2x16 / packUnorm4x8 round to nearest; NaN clamps to 0 (never reached: callers
// pass finite values).
uint32_t snorm16(float v) {
    const float c = std::nearbyint(std::clamp(v, -1.f, 1.f) * 32767.f);
    return static_cast<uint32_t>(static_cast<uint16_t>(static_cast<int16_t>(c)));
}
float from_snorm16(uint32_t b) {
    const auto i = static_cast<int16_t>(static_cast<uint16_t>(b));
    return std::clamp(float(i) / 32767.f, -1.f, 1.f);
}
uint32_t unorm8(float v) {
    const float c = std::isnan(v) ? 0.f : std::clamp(v, 0.f, 1.f);
    return static_cast<uint32_t>(std::nearbyint(c * 255.f));
}

}  // namespace

SurfaceTexel pack_surface(const SurfaceSample& s) {
    const auto& n = s.normal;
    const float l1 = std::fabs(n[0]) + std::fabs(n[1]) + std::fabs(n[2]);
    float ex = 0.f, ey = 0.f;
    if (l1 > 0.f && l1 < 3.0e38f) {
        const float px = n[0] / l1, py = n[1] / l1;
        if (n[2] >= 0.f) {
            ex = px, ey = py;
        } else {
            ex = (1.f - std::fabs(py)) * sign_not_zero(px);
            ey = (1.f - std::fabs(px)) * sign_not_zero(py);
        }
    }
    const float id = std::isnan(s.material[0]) ? 0.f : s.material[0];
    SurfaceTexel t{};
    t[0] = snorm16(ex) | snorm16(ey) << 16;
    t[1] = unorm8(s.albedo[0]) | unorm8(s.albedo[1]) << 8 | unorm8(s.albedo[2]) << 16 |
           unorm8(s.albedo_a) << 24;
    t[2] = static_cast<uint32_t>(std::clamp(id + 0.5f, 0.f, 65535.f)) |
           uint32_t{half_bits(s.material[1])} << 16;
    t[3] = uint32_t{half_bits(s.material[2])} | uint32_t{half_bits(s.material[3])} << 16;
    return t;
}

SurfaceSample unpack_surface(const SurfaceTexel& t) {
    SurfaceSample s;
    float x = from_snorm16(t[0] & 0xffffu), y = from_snorm16(t[0] >> 16);
    float z = 1.f - std::fabs(x) - std::fabs(y);
    const float fold = std::max(-z, 0.f);
    x += x >= 0.f ? -fold : fold;
    y += y >= 0.f ? -fold : fold;
    const float len = std::sqrt(x * x + y * y + z * z);
    s.normal = {x / len, y / len, z / len};
    for (int c = 0; c < 3; ++c) s.albedo[size_t(c)] = float((t[1] >> (8 * c)) & 0xffu) / 255.f;
    s.albedo_a = float(t[1] >> 24) / 255.f;
    s.material = {float(t[2] & 0xffffu), half_from_bits(uint16_t(t[2] >> 16)),
                  half_from_bits(uint16_t(t[3] & 0xffffu)), half_from_bits(uint16_t(t[3] >> 16))};
    return s;
}

}  // namespace fovea::vk
