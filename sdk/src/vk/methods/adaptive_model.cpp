#include "adaptive_model.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace fovea::vk::methods {
namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kDegToRad = kPi / 180.0;
constexpr double kRadToDeg = 180.0 / kPi;

double dot3(const double a[3], const double b[3]) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
}  // namespace

Vec2f64 angular_position(Vec2f64 pixel, const ScreenFov& s) {
    const double sx = 0.5 * s.width_px / std::tan(0.5 * s.fov_h_deg * kDegToRad);
    const double sy = 0.5 * s.height_px / std::tan(0.5 * s.fov_v_deg * kDegToRad);
    return {std::atan((pixel.x - 0.5 * s.width_px) / sx) * kRadToDeg,
            std::atan((pixel.y - 0.5 * s.height_px) / sy) * kRadToDeg};
}

double eccentricity_deg(Vec2f64 pixel, Vec2f64 gaze, const ScreenFov& s) {
    const Vec2f64 p = angular_position(pixel, s);
    const Vec2f64 g = angular_position(gaze, s);
    return std::hypot(p.x - g.x, p.y - g.y);
}

double eccentricity_to_gaze_line_deg(Vec2f64 pixel, Vec2f64 gaze_prev, Vec2f64 gaze,
                                     const ScreenFov& s) {
    const Vec2f64 p = angular_position(pixel, s);
    const Vec2f64 a = angular_position(gaze, s);
    const Vec2f64 ahead{2.0 * gaze.x - gaze_prev.x, 2.0 * gaze.y - gaze_prev.y};
    const Vec2f64 b = angular_position(ahead, s);
    const double abx = b.x - a.x;
    const double aby = b.y - a.y;
    const double len2 = abx * abx + aby * aby;
    // A fixation (len2 = 0) degenerates to the point distance of Eq. 3.
    const double t =
        len2 > 0.0 ? std::clamp(((p.x - a.x) * abx + (p.y - a.y) * aby) / len2, 0.0, 1.0) : 0.0;
    return std::hypot(p.x - (a.x + t * abx), p.y - (a.y + t * aby));
}

double acuity_probability(double ecc_deg, const ScreenFov& s, const AdaptiveParams& p) {
    const double e_norm = ecc_deg / (0.5 * s.fov_v_deg);
    return std::clamp(p.omega0 + p.slope * e_norm, p.omega_p, 1.0);
}

double motion_gain(double v) {
    if (!(v > 0.83)) return 1.0;  // also catches NaN: no motion information, full acuity
    if (v > 118.0) return 0.002;
    return 0.962 - 0.463 * std::log10(v);
}

double highlight_term(const double light_dir[3], const double reflect_dir[3], double intensity,
                      double gamma) {
    const double c = std::max(0.0, dot3(light_dir, reflect_dir));
    return std::pow(c, gamma) * intensity;
}

double silhouette_response(double depth, const double nd[4], const double normal[3],
                           const double nn[4][3], const AdaptiveParams& p) {
    double depth_step = 0.0;
    double normal_step = 0.0;
    for (int i = 0; i < 4; ++i) {
        const double denom = std::max(std::min(depth, nd[i]), 1e-6);
        depth_step = std::max(depth_step, std::abs(depth - nd[i]) / denom);
        normal_step = std::max(normal_step, 1.0 - dot3(normal, nn[i]));
    }
    return std::clamp(std::max(depth_step / p.silhouette_depth, normal_step / p.silhouette_normal),
                      0.0, 1.0);
}

double luminance(double r, double g, double b) { return 0.299 * r + 0.587 * g + 0.114 * b; }

double tonemap(double lum, double exposure) {
    const double x = std::max(0.0, lum * exposure);
    return x / (1.0 + x);
}

double brightness_scale(double l, const AdaptiveParams& p) {
    return std::clamp(std::min(1.0, l / p.t_dark) * std::min(1.0, (1.0 - l) / (1.0 - p.t_bright)),
                      0.0, 1.0);
}

double sampling_probability(double f_m, double f_o, double f_h, double f_s, double scale) {
    return std::clamp(std::max({f_m, f_o, f_h, f_s}) * scale, 0.0, 1.0);
}

double ExposureAdapter::update(double weighted_sum, double weight_sum, const AdaptiveParams& p) {
    if (weight_sum > 0.0 && std::isfinite(weighted_sum) && std::isfinite(weight_sum)) {
        const double l_avg = weighted_sum / weight_sum;
        exposure_ += p.adapt_rate * (p.auto_exposure - l_avg);  // Eq. 10
        // E stays positive: a blown-out frame must not flip the tone curve.
        exposure_ = std::clamp(exposure_, 1e-3, 1e3);
    }
    return exposure_;
}

std::uint32_t sample_hash(std::uint32_t x, std::uint32_t y, std::uint32_t seed) {
    // PCG-style integer hash (Jarzynski & Olano 2020, "pcg3d" reduced to one output).
    std::uint32_t v = x * 1664525u + 1013904223u;
    std::uint32_t w = y * 1664525u + 1013904223u;
    std::uint32_t z = seed * 1664525u + 1013904223u;
    v += w * z;
    w += z * v;
    z += v * w;
    v ^= v >> 16u;
    w ^= w >> 16u;
    z ^= z >> 16u;
    v += w * z;
    return v;
}

double sample_threshold(std::uint32_t x, std::uint32_t y, std::uint32_t seed) {
    return double(sample_hash(x, y, seed) >> 8) * (1.0 / 16777216.0);  // 24 bits, exact in float
}

ProbabilityMap dilate_via_low_res(const ProbabilityMap& full) {
    const int lw = (full.width + 1) / 2;
    const int lh = (full.height + 1) / 2;
    std::vector<float> low(std::size_t(lw) * std::size_t(lh), 0.0f);
    for (int y = 0; y < full.height; ++y)
        for (int x = 0; x < full.width; ++x) {
            float& m = low[std::size_t(y / 2) * std::size_t(lw) + std::size_t(x / 2)];
            m = std::max(m, full.at(x, y));
        }
    ProbabilityMap out{full.width, full.height, std::vector<float>(full.values.size())};
    for (int y = 0; y < full.height; ++y)
        for (int x = 0; x < full.width; ++x) {
            float m = 0.0f;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int lx = std::clamp(x / 2 + dx, 0, lw - 1);
                    const int ly = std::clamp(y / 2 + dy, 0, lh - 1);
                    m = std::max(m, low[std::size_t(ly) * std::size_t(lw) + std::size_t(lx)]);
                }
            out.values[std::size_t(y) * std::size_t(full.width) + std::size_t(x)] = m;
        }
    return out;
}

ProbabilityMap dilate_exact(const ProbabilityMap& full, int radius) {
    ProbabilityMap out{full.width, full.height, std::vector<float>(full.values.size())};
    for (int y = 0; y < full.height; ++y)
        for (int x = 0; x < full.width; ++x) {
            float m = 0.0f;
            for (int dy = -radius; dy <= radius; ++dy)
                for (int dx = -radius; dx <= radius; ++dx) {
                    const int sx = x + dx;
                    const int sy = y + dy;
                    if (sx >= 0 && sy >= 0 && sx < full.width && sy < full.height)
                        m = std::max(m, full.at(sx, sy));
                }
            out.values[std::size_t(y) * std::size_t(full.width) + std::size_t(x)] = m;
        }
    return out;
}

}  // namespace fovea::vk::methods
