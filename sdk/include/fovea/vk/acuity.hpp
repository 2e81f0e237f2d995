// The acuity and eccentricity model on the CPU. The maths is shaders/fovea_acuity.glsl compiled
// as C++ (sdk/src/vk/acuity.cpp), so these functions agree with the GPU texel by texel.
// All functions are pure and thread-safe.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "fovea/ring.h"

namespace fovea::vk {

// One eye's display. Flat screens: from_size(); HMD eyes: from_fov().
struct EyeDisplay {
    uint32_t width_px = 1920;
    uint32_t height_px = 1080;
    float fov_h_deg = 47.8f;  // 24" 16:9 (0.531 m wide) at 0.60 m, like gaze::DisplayGeometry
    float fov_v_deg = 28.0f;

    static EyeDisplay from_size(uint32_t width_px, uint32_t height_px, double width_m,
                                double height_m, double distance_m);
    static EyeDisplay from_fov(uint32_t width_px, uint32_t height_px, double fov_h_deg,
                               double fov_v_deg);
    // Presets the demo and bench use: a 24" 1920x1080 monitor at 60 cm, and one eye of an HMD
    // with 1440x1600 per eye and a 98 x 104 degree field of view.
    static EyeDisplay desktop_1080p();
    static EyeDisplay hmd_eye();

    float pixels_per_degree() const;  // at the display centre
};

// Guenter's MAR line and Patney's piecewise-linear rate (shaders/fovea_acuity.glsl).
struct AcuityParams {
    float mar_slope = 0.022f;         // m: Guenter's quality-B slope; 0.034 is more aggressive
    float mar_omega0 = 1.0f / 48.0f;  // w0, degrees
    float foveal_radius_deg = 5.0f;   // full rate inside (Patney: 7.5 desktop, 15 HMD; 5 is
                                      // aggressive-but-acceptable per his §4.4 note)
    float transition_deg = 5.0f;      // linear ramp to the MAR-limited rate
    float max_rate = 4.0f;            // coarsest coarse-pixel edge: 1, 2 or 4
    uint32_t tile_size = 16;          // pixels per rate-tile edge (multiple of max_rate)
    float uncertainty_sigmas = 2.0f;  // fovea widened by this many gaze 1-sigma
    float drift_dps = 1.0f;           // and by sample age times this (fixational eye motion)
    float max_margin_deg = 10.0f;     // cap on the widening
};

// The gaze a frame is rendered for: one eye (or the combined gaze) in normalized display
// coordinates (0..1, origin top-left; off-screen values are fine; NaN means no gaze this frame,
// e.g. a blink: GazeResolver holds the last valid gaze, resolve_gaze() falls back to the centre).
struct GazeState {
    float x = 0.5f;
    float y = 0.5f;
    float uncertainty_deg = 0.0f;  // 1-sigma of the estimate
    float age_s = 0.0f;            // capture -> display time (latency plus frame time)
    bool in_saccade = false;
    bool landing_valid = false;  // saccade landing prediction, used as centre in a saccade
    float landing_x = 0.5f, landing_y = 0.5f;
    float landing_uncertainty_deg = 0.0f;

    enum class Eye { kLeft, kRight, kCombined };
    // From a ring record; display_time_ns is the CLOCK_MONOTONIC time the frame will be seen.
    static GazeState from_record(const fovea_gaze_record& record, int64_t display_time_ns,
                                 Eye eye = Eye::kCombined);
};

// The centre and widening the shaders use.
struct ResolvedGaze {
    float x_px = 0.0f, y_px = 0.0f;  // rate centre in pixels (may lie off screen)
    float margin_deg = 0.0f;         // eccentricity subtracted before the rate model
    bool fell_back = false;          // NaN/inf gaze and none valid before: screen centre used
    bool held = false;               // NaN/inf gaze: the last valid gaze held (GazeResolver)
    bool used_landing = false;       // in a saccade with a landing prediction
};

// The widening rule. margin_deg is subtracted from every pixel's eccentricity before the rate
// model, so the full-rate disc grows by it:
//   margin = uncertainty_sigmas * sigma + drift_dps * age_s, clamped to [0, max_margin_deg]
//   (defaults: 2 sigma, 1 deg/s, 10 deg cap)
// - sigma: the tracker's 1-sigma error, 0.5 deg from from_record() (the ring carries no
//   per-sample figure); in a saccade with a landing prediction, the larger of it and the
//   prediction's sigma. 2 sigma holds ~95 % of a fixation's samples.
// - age_s: the gaze's age, capture -> frame. Hosts on the SDK take it from fovea_frame_begin()
//   (fovea/client.h), which measures capture -> frame begin and counts the frame as stale past
//   its threshold; from_record(record, t) computes the same from the same time t.
// - Why drift_dps is small: during fixation the eye moves slowly (drift, tremor, microsaccades,
//   below ~1 deg/s on average), so at the 20-40 ms of latency Albert et al. 2017 found tolerable
//   the age term adds only 0.02-0.04 deg. Saccades are deliberately NOT covered by widening:
//   their peak velocities reach ~500 deg/s, so 40 ms of age would need a 20 deg margin, i.e. no
//   foveation. What hides them is saccadic suppression (vision is degraded for tens of ms around
//   a saccade, which is why 20-40 ms is tolerable and 80-150 ms is not); during the flight the
//   landing prediction is the centre. Gaze older than that budget is a latency problem to
//   measure, not to widen away: fovea_frame_latency counts those frames (stale threshold,
//   default FOVEA_STALE_GAZE_DEFAULT_NS = 40 ms) and `fovea latency` shows the count.
// Resolves the gaze for a frame. Non-finite coordinates fall back to the screen centre and set
// fell_back. Off-screen gaze is clamped to 4 screen sizes away. Stateless: frame-to-frame hosts
// use GazeResolver, which holds the last valid gaze through blinks.
ResolvedGaze resolve_gaze(const GazeState& gaze, const EyeDisplay& display,
                          const AcuityParams& acuity);

// resolve_gaze() frame after frame, holding the last valid gaze through non-finite samples (a
// blink, a lost pupil) instead of jumping to the screen centre: the held gaze ages by the frame
// time (time_s), so its margin widens at drift_dps up to max_margin_deg, and sets `held`. Before
// the first valid gaze it falls back to the centre (fell_back). The Foveator owns one; hosts on
// the rate-image path (VrsAttachment) use their own. Not thread-safe: one per view, one thread.
class GazeResolver {
public:
    GazeResolver(const EyeDisplay& display, const AcuityParams& acuity)
        : display_(display), acuity_(acuity) {}
    // time_s: the frame's time (FrameInputs::time_s), non-decreasing; 0 for all frames is fine
    // (the held gaze then keeps the age it had).
    ResolvedGaze resolve(const GazeState& gaze, double time_s);
    void reset() { has_valid_ = false; }

private:
    EyeDisplay display_;
    AcuityParams acuity_;
    bool has_valid_ = false;
    GazeState last_valid_;
    double last_valid_time_s_ = 0.0;
};

float eccentricity_deg(const EyeDisplay& display, float px, float py, float gaze_px, float gaze_py);
float pixel_size_deg(const EyeDisplay& display, float px, float py);  // the larger of both axes
// Angular size of one pixel along x and along y (each depends on that coordinate only).
std::array<float, 2> pixel_size_deg_axes(const EyeDisplay& display, float px, float py);
float mar_deg(const AcuityParams& acuity, float eccentricity_deg);
// Continuous rate (coarse pixel edge, >= 1) at a pixel; quantized rate of a tile.
float rate_at(const EyeDisplay& display, const AcuityParams& acuity, const ResolvedGaze& gaze,
              float px, float py);
float tile_rate(const EyeDisplay& display, const AcuityParams& acuity, const ResolvedGaze& gaze,
                uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1);
float normalized_rate(float rate);  // S_t: 0, 0.5, 1

// Rate per tile (values 1, 2, 4), row-major, ceil(width/tile) x ceil(height/tile): what the
// coarse-pixel-shading classification pass writes.
std::vector<uint8_t> cpu_rate_tiles(const EyeDisplay& display, const AcuityParams& acuity,
                                    const ResolvedGaze& gaze, uint32_t tile_w, uint32_t tile_h);
// The VK_KHR_fragment_shading_rate attachment texels: (log2 w << 2) | log2 h.
std::vector<uint8_t> cpu_vrs_texels(const EyeDisplay& display, const AcuityParams& acuity,
                                    const ResolvedGaze& gaze, uint32_t texel_w, uint32_t texel_h);

// Halton(2,3) sub-pixel jitter in pixels, in [-0.5, 0.5), for frame `index` of a sequence of
// `length` (0 = no jitter). Hosts add it to their projection; TAA reads it from the frame.
void halton_jitter(uint64_t index, uint32_t length, float& jx, float& jy);

// Eccentricity bands used by every metric: 0-5, 5-10, 10-20, 20-30, >30 degrees.
inline constexpr int kBandCount = 5;
inline constexpr float kBandEdgesDeg[kBandCount + 1] = {0.f, 5.f, 10.f, 20.f, 30.f, 1e9f};
const char* band_name(int band);

}  // namespace fovea::vk
