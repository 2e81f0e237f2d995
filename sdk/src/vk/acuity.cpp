#include "fovea/vk/acuity.hpp"

#include <algorithm>
#include <cmath>

namespace fovea::vk {
namespace glsl {

// Just enough GLSL for shaders/fovea_acuity.glsl to compile as C++ with float maths, so the CPU
// and the GPU evaluate the same expressions in the same order.
using uint = uint32_t;
struct vec2 {
    float x = 0.f, y = 0.f;
    vec2() = default;
    vec2(float a, float b) : x(a), y(b) {}
};
inline vec2 operator+(vec2 a, vec2 b) { return {a.x + b.x, a.y + b.y}; }
inline vec2 operator-(vec2 a, vec2 b) { return {a.x - b.x, a.y - b.y}; }
inline vec2 operator*(vec2 a, float s) { return {a.x * s, a.y * s}; }
inline vec2 operator/(vec2 a, vec2 b) { return {a.x / b.x, a.y / b.y}; }
inline float abs(float v) { return std::fabs(v); }
inline float sqrt(float v) { return std::sqrt(v); }
inline float max(float a, float b) { return a > b ? a : b; }  // GLSL max: NaN handling as the
inline float min(float a, float b) { return a < b ? a : b; }  // shaders see it on lavapipe
inline float clamp(float v, float lo, float hi) { return min(max(v, lo), hi); }
inline vec2 clamp(vec2 v, vec2 lo, vec2 hi) {
    return {clamp(v.x, lo.x, hi.x), clamp(v.y, lo.y, hi.y)};
}

#define precise  // GLSL's no-contraction qualifier; C++ here is compiled without FP contraction
#include "fovea_acuity.glsl"
#undef precise

}  // namespace glsl

namespace {

glsl::FoveaDisplay to_glsl(const EyeDisplay& d) {
    constexpr double kDegToRad = 0.017453292519943295;
    glsl::FoveaDisplay g;
    g.size_px = glsl::vec2(static_cast<float>(d.width_px), static_cast<float>(d.height_px));
    g.half_tan = glsl::vec2(static_cast<float>(std::tan(d.fov_h_deg * 0.5 * kDegToRad)),
                            static_cast<float>(std::tan(d.fov_v_deg * 0.5 * kDegToRad)));
    return g;
}

glsl::FoveaAcuity to_glsl(const AcuityParams& a, float margin_deg) {
    glsl::FoveaAcuity g;
    g.mar_slope = a.mar_slope;
    g.mar_omega0 = a.mar_omega0;
    g.foveal_radius_deg = a.foveal_radius_deg;
    g.transition_deg = a.transition_deg;
    g.margin_deg = margin_deg;
    g.max_rate = a.max_rate;
    g.tile_size = static_cast<float>(a.tile_size);
    g.reserved = 0.f;
    return g;
}

}  // namespace

EyeDisplay EyeDisplay::from_size(uint32_t w, uint32_t h, double width_m, double height_m,
                                 double distance_m) {
    constexpr double kRadToDeg = 57.29577951308232;
    EyeDisplay d;
    d.width_px = w;
    d.height_px = h;
    d.fov_h_deg = static_cast<float>(2.0 * std::atan(0.5 * width_m / distance_m) * kRadToDeg);
    d.fov_v_deg = static_cast<float>(2.0 * std::atan(0.5 * height_m / distance_m) * kRadToDeg);
    return d;
}

EyeDisplay EyeDisplay::from_fov(uint32_t w, uint32_t h, double fov_h, double fov_v) {
    EyeDisplay d;
    d.width_px = w;
    d.height_px = h;
    d.fov_h_deg = static_cast<float>(fov_h);
    d.fov_v_deg = static_cast<float>(fov_v);
    return d;
}

EyeDisplay EyeDisplay::desktop_1080p() { return from_size(1920, 1080, 0.531, 0.299, 0.60); }
EyeDisplay EyeDisplay::hmd_eye() { return from_fov(1440, 1600, 98.0, 104.0); }

float EyeDisplay::pixels_per_degree() const {
    const glsl::FoveaDisplay g = to_glsl(*this);
    return 1.0f / glsl::fovea_pixel_size_deg(g, g.size_px * 0.5f);
}

GazeState GazeState::from_record(const fovea_gaze_record& r, int64_t display_time_ns, Eye eye) {
    const fovea_eye& e = eye == Eye::kLeft ? r.left : eye == Eye::kRight ? r.right : r.combined;
    GazeState g;
    constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
    g.x = (e.valid & FOVEA_VALID) ? e.norm_x : kNaN;
    g.y = (e.valid & FOVEA_VALID) ? e.norm_y : kNaN;
    g.age_s = static_cast<float>(std::max<int64_t>(0, display_time_ns - r.t_capture_ns) * 1e-9);
    g.uncertainty_deg = 0.5f;  // typical tracker accuracy; the ring carries no per-sample figure
    g.in_saccade = r.event == FOVEA_EVENT_SACCADE;
    g.landing_valid = (r.flags & FOVEA_FLAG_LANDING_VALID) != 0;
    g.landing_x = r.landing_norm_x;
    g.landing_y = r.landing_norm_y;
    g.landing_uncertainty_deg = r.landing_uncertainty_deg;
    return g;
}

ResolvedGaze resolve_gaze(const GazeState& gaze, const EyeDisplay& d, const AcuityParams& a) {
    ResolvedGaze out;
    float x = gaze.x, y = gaze.y, unc = gaze.uncertainty_deg;
    if (gaze.in_saccade && gaze.landing_valid && std::isfinite(gaze.landing_x) &&
        std::isfinite(gaze.landing_y)) {
        x = gaze.landing_x;
        y = gaze.landing_y;
        unc = std::max(unc, gaze.landing_uncertainty_deg);
        out.used_landing = true;
    }
    if (!std::isfinite(x) || !std::isfinite(y)) {
        x = 0.5f;
        y = 0.5f;
        out.fell_back = true;
        out.used_landing = false;
    }
    x = std::clamp(x, -4.0f, 5.0f);
    y = std::clamp(y, -4.0f, 5.0f);
    out.x_px = x * static_cast<float>(d.width_px);
    out.y_px = y * static_cast<float>(d.height_px);
    float margin = a.uncertainty_sigmas * (std::isfinite(unc) ? std::max(unc, 0.f) : 0.f) +
                   (std::isfinite(gaze.age_s) ? std::max(gaze.age_s, 0.f) : 0.f) * a.drift_dps;
    out.margin_deg = std::clamp(margin, 0.f, a.max_margin_deg);
    return out;
}

ResolvedGaze GazeResolver::resolve(const GazeState& gaze, double time_s) {
    const bool finite_landing = gaze.in_saccade && gaze.landing_valid &&
                                std::isfinite(gaze.landing_x) && std::isfinite(gaze.landing_y);
    if ((std::isfinite(gaze.x) && std::isfinite(gaze.y)) || finite_landing) {
        has_valid_ = true;
        last_valid_ = gaze;
        last_valid_time_s_ = time_s;
        return resolve_gaze(gaze, display_, acuity_);
    }
    if (!has_valid_) return resolve_gaze(gaze, display_, acuity_);
    GazeState held = last_valid_;
    const double since = std::isfinite(time_s) ? time_s - last_valid_time_s_ : 0.0;
    held.age_s += static_cast<float>(std::max(since, 0.0));
    ResolvedGaze out = resolve_gaze(held, display_, acuity_);
    out.held = true;
    return out;
}

float eccentricity_deg(const EyeDisplay& d, float px, float py, float gx, float gy) {
    return glsl::fovea_eccentricity_deg(to_glsl(d), glsl::vec2(px, py), glsl::vec2(gx, gy));
}

float pixel_size_deg(const EyeDisplay& d, float px, float py) {
    return glsl::fovea_pixel_size_deg(to_glsl(d), glsl::vec2(px, py));
}

std::array<float, 2> pixel_size_deg_axes(const EyeDisplay& d, float px, float py) {
    const glsl::vec2 a = glsl::fovea_pixel_size_deg_axes(to_glsl(d), glsl::vec2(px, py));
    return {a.x, a.y};
}

float mar_deg(const AcuityParams& a, float e) { return glsl::fovea_mar_deg(to_glsl(a, 0.f), e); }

float rate_at(const EyeDisplay& d, const AcuityParams& a, const ResolvedGaze& g, float px,
              float py) {
    const auto gd = to_glsl(d);
    const glsl::vec2 p(px, py);
    const float e = glsl::fovea_eccentricity_deg(gd, p, glsl::vec2(g.x_px, g.y_px));
    return glsl::fovea_rate_at(to_glsl(a, g.margin_deg), e, glsl::fovea_pixel_size_deg(gd, p));
}

float tile_rate(const EyeDisplay& d, const AcuityParams& a, const ResolvedGaze& g, uint32_t x0,
                uint32_t y0, uint32_t x1, uint32_t y1) {
    return glsl::fovea_tile_rate(to_glsl(d), to_glsl(a, g.margin_deg),
                                 glsl::vec2(static_cast<float>(x0), static_cast<float>(y0)),
                                 glsl::vec2(static_cast<float>(x1), static_cast<float>(y1)),
                                 glsl::vec2(g.x_px, g.y_px));
}

float normalized_rate(float rate) { return glsl::fovea_normalized_rate(rate); }

std::vector<uint8_t> cpu_rate_tiles(const EyeDisplay& d, const AcuityParams& a,
                                    const ResolvedGaze& g, uint32_t tw, uint32_t th) {
    const uint32_t nx = (d.width_px + tw - 1) / tw, ny = (d.height_px + th - 1) / th;
    std::vector<uint8_t> out(static_cast<size_t>(nx) * ny);
    for (uint32_t ty = 0; ty < ny; ++ty)
        for (uint32_t tx = 0; tx < nx; ++tx)
            out[static_cast<size_t>(ty) * nx + tx] = static_cast<uint8_t>(
                tile_rate(d, a, g, tx * tw, ty * th, std::min((tx + 1) * tw, d.width_px),
                          std::min((ty + 1) * th, d.height_px)));
    return out;
}

std::vector<uint8_t> cpu_vrs_texels(const EyeDisplay& d, const AcuityParams& a,
                                    const ResolvedGaze& g, uint32_t tw, uint32_t th) {
    std::vector<uint8_t> rates = cpu_rate_tiles(d, a, g, tw, th);
    for (uint8_t& r : rates) r = static_cast<uint8_t>(glsl::fovea_vrs_encode(r));
    return rates;
}

namespace {
float radical_inverse(uint64_t i, uint32_t base) {
    float f = 1.f, r = 0.f;
    while (i > 0) {
        f /= static_cast<float>(base);
        r += f * static_cast<float>(i % base);
        i /= base;
    }
    return r;
}
}  // namespace

void halton_jitter(uint64_t index, uint32_t length, float& jx, float& jy) {
    if (length == 0) {
        jx = jy = 0.f;
        return;
    }
    const uint64_t i = index % length + 1;  // skip index 0 (= 0, 0) of the sequence
    jx = radical_inverse(i, 2) - 0.5f;
    jy = radical_inverse(i, 3) - 0.5f;
}

const char* band_name(int band) {
    static const char* const kNames[kBandCount] = {"0-5", "5-10", "10-20", "20-30", ">30"};
    return band >= 0 && band < kBandCount ? kNames[band] : "?";
}

}  // namespace fovea::vk
