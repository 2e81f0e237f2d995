// Stengel et al. 2016: per-pixel sampling probability P = max(F_M, F_O, F_H, F_S) · S (Eq. 12),
// its 5×5 dilation through a low-resolution map, and the stable pseudo-random sampling pattern.
// Pure C++ (no Vulkan): the reference for shaders/adaptive_*.glsl and for the unit tests.
// All free functions are pure (any thread); ExposureAdapter is owned by one render thread.
#pragma once

#include <cstdint>
#include <vector>

namespace fovea::vk::methods {

struct AdaptiveParams {
    // Eq. 1–2, the paper's calibrated values (§6.1). Eccentricity there is in "normalized device
    // space"; we normalise degrees by the half vertical field of view (NDC y = 1 at the top edge),
    // which reproduces the paper's HMD numbers: fovea f = 0.07, floor from e = 0.47.
    double omega0 = 1.1715;
    double slope = -2.45;
    double omega_p = 0.02;
    double gamma = 20.0;         // highlight exponent, Eq. 8
    double adapt_rate = 0.05;    // a_r, Eq. 10
    double auto_exposure = 0.5;  // A: target mean tone-mapped luminance, Eq. 10
    double t_dark = 0.15;        // Eq. 11
    double t_bright = 0.9;       // Eq. 11
    // The paper's silhouette filter has no constants: relative depth step and normal angle that
    // count as a full silhouette (F_S = 1). 5 % depth change, 1 - cos = 0.25 (~41°).
    double silhouette_depth = 0.05;
    double silhouette_normal = 0.25;
};

struct ScreenFov {
    int width_px = 1920;
    int height_px = 1080;
    double fov_h_deg = 46.8;  // Guenter's desktop: 2·atan(51 / (2·59))
    double fov_v_deg = 27.3;
};

struct Vec2f64 {
    double x = 0.0;
    double y = 0.0;
};

// Eq. 3 per axis (signed, so opposite sides of the centre do not fold together): degrees.
Vec2f64 angular_position(Vec2f64 pixel, const ScreenFov& s);
double eccentricity_deg(Vec2f64 pixel, Vec2f64 gaze, const ScreenFov& s);
// §4.1.2: gaze as the segment from g_i to g_i + (g_i - g_{i-1}) (expected motion over the
// frame); eccentricity is the angular distance to that segment.
double eccentricity_to_gaze_line_deg(Vec2f64 pixel, Vec2f64 gaze_prev, Vec2f64 gaze,
                                     const ScreenFov& s);
// Eq. 1–2 with e normalised by the half vertical FOV.
double acuity_probability(double ecc_deg, const ScreenFov& s, const AdaptiveParams& p);
// Eq. 5: sensitivity against retinal speed in degrees per second.
double motion_gain(double speed_deg_per_s);
// Eq. 8 for one light: max(0, <L, R>)^γ · I (the caller sums over lights and clamps to 1).
double highlight_term(const double light_dir[3], const double reflect_dir[3], double intensity,
                      double gamma);
// Silhouette response of a pixel against its 4 neighbours: max of the relative depth step and
// the normal deviation, each scaled to 1 at the thresholds in AdaptiveParams, clamped to [0, 1].
double silhouette_response(double depth, const double neighbour_depth[4], const double normal[3],
                           const double neighbour_normal[4][3], const AdaptiveParams& p);
double luminance(double r, double g, double b);  // Eq. 9
double tonemap(double lum, double exposure);     // Reinhard: E L / (1 + E L)
double brightness_scale(double tonemapped_lum, const AdaptiveParams& p);  // Eq. 11
// Eq. 12 (before dilation).
double sampling_probability(double f_m, double f_o, double f_h, double f_s, double scale);

// Eq. 10, with the mean taken over the tone-mapped luminance at the previous exposure, weighted
// by F_M and normalised by ΣF_M: the literal Σ L·F_M / N never feeds back through E and drifts.
class ExposureAdapter {
public:
    explicit ExposureAdapter(double initial_exposure = 1.0) : exposure_(initial_exposure) {}
    // Called once per frame with Σ tonemap(L, E_{i-1})·F_M and Σ F_M; returns E_i.
    double update(double weighted_sum, double weight_sum, const AdaptiveParams& p);
    double exposure() const { return exposure_; }

private:
    double exposure_;
};

// Stable per-pixel threshold in [0, 1): a pixel is shaded when threshold < P. The same integer
// hash runs in shaders/adaptive_common.glsl, so CPU and GPU choose identical samples.
std::uint32_t sample_hash(std::uint32_t x, std::uint32_t y, std::uint32_t seed);
double sample_threshold(std::uint32_t x, std::uint32_t y, std::uint32_t seed);

// Row-major single-channel map.
struct ProbabilityMap {
    int width = 0;
    int height = 0;
    std::vector<float> values;
    float at(int x, int y) const {
        return values[std::size_t(y) * std::size_t(width) + std::size_t(x)];
    }
};

// §5: the 5×5 dilation computed cheaply: max-reduce 2×2 blocks to half resolution, 3×3 max
// there, read back per pixel. Covers at least every pixel's 5×5 neighbourhood (at most 6×6).
ProbabilityMap dilate_via_low_res(const ProbabilityMap& full);
ProbabilityMap dilate_exact(const ProbabilityMap& full, int radius);  // reference for tests

}  // namespace fovea::vk::methods
