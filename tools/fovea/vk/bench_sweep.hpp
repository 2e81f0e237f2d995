// The `fovea bench` sweep: configurations (display, acuity, method options, post chain, methods)
// each rendered by demo::run on the demo camera path at display rate (1/60 s between frames, so
// the G-buffer motion vectors and TAA history describe consecutive frames) with a gaze trace
// window holding a saccade, against the full-rate reference with the same post chain. Every
// (configuration, method) pair becomes one Row; its errors are pooled over its frames: PSNR and
// SSIM (fovea::metrics), LDR-FLIP on the device (bench_flip.hpp), ATD and temporal FLIP. With
// --scene the frames come from the glTF viewer's host code instead (bench_scene.hpp) and the
// methods are its integration paths.
#pragma once

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "fovea/demo/demo.hpp"
#include "fovea/result.hpp"
#include "fovea/vk/acuity.hpp"
#include "fovea/vk/device.hpp"

namespace fovea::bench {

struct Config {
    std::string tag;           // "default", "taa", ... (the same tag on every display)
    std::string display_name;  // "1920x1080", "hmd-eye 1440x1600"
    vk::EyeDisplay display;
    std::vector<std::string> acuity;   // "acuity.<field>=value", applied to vk::AcuityParams
    std::vector<std::string> options;  // FoveatorConfig::options ("kfr.sigma=1.6", ...)
    std::vector<std::string> post;     // post chain, also applied to the reference
    std::vector<std::string> methods;  // foveated methods; "full" always runs as reference
    int frames = 0;                    // 0: the sweep's frame count
};

struct Row {
    std::string method, tag, display_name;
    std::string settings;  // the acuity/options/post keys this method reads
    uint32_t width = 0, height = 0;
    int frames = 0;
    double ms_median = 0, ms_p95 = 0;  // wall time per frame, submit -> done
    double method_gpu_ms = 0;
    double gbuffer_gpu_ms = 0;  // the host's G-buffer passes (0: the runner does not time them)
    double shaded_fraction = 0;
    // Against the full-rate reference, pooled over the frames; no caps (+inf: identical).
    double psnr_db = 0;  // the whole frame
    double psnr_fovea_db = 0;
    std::array<double, vk::kBandCount> psnr_bands_pooled{}, ssim_bands{};
    double flip_mean = 0;  // LDR-FLIP at the ppd each pixel is seen at (display geometry)
    std::array<double, vk::kBandCount> flip_bands{};
    double flip_mean_67ppd = 0;  // at the FLIP tool's default 67 ppd, for published figures
    std::array<double, vk::kBandCount> flip_bands_67ppd{};
    std::array<double, vk::kBandCount> band_ppd{};  // mean ppd of each band's pixels
    double flip_gpu_ms = 0;  // median GPU time of one FLIP compare at the display's ppd
    // Temporal stability of this row's own output: consecutive frames, the previous one
    // back-projected with the G-buffer motion and the frame's jitter. _cut: the frame pairs after
    // the camera cut at frame 0, before kSettledFrom; _settled: from kSettledFrom on (NaN in
    // shorter runs).
    double atd = 0;       // Patney's average temporal difference of display luminance
    double atd_8bit = 0;  // the same on the 8-bit frames (rounding floor ~1/4 LSB)
    double atd_settled = 0, atd_cut = 0;
    double tflip = 0;  // mean FLIP between consecutive frames (display ppd)
    double tflip_settled = 0, tflip_cut = 0;
    double skipped_tiles = 0;  // mean per frame: tiles without a host shading call
    double reused_tiles = 0;   // mean per frame: of which last frame's shading kept
    std::string error;         // method failed to initialise; other fields empty
};

// TAA (alpha = 0.1) keeps ~0.9^n of the frame after the camera cut at frame 0: "settled" figures
// average the frame pairs from here on.
inline constexpr int kSettledFrom = 10;

// Sets one "acuity.<field>=value" on p; false for an unknown field or a bad number.
bool apply_acuity_setting(vk::AcuityParams& p, const std::string& key_value);

struct SweepOptions {
    bool quick = false;
    bool hmd = true;                         // full sweep only
    bool temporal = true;                    // the settled / camera-cut runs (kTemporalFrames)
    std::vector<std::string> methods;        // empty: every registered method
    std::vector<std::string> extra_options;  // --method-option, added to every configuration
    uint32_t width = 0, height = 0;  // 0: the presets; else a desktop-FOV display of this size
    // --scene: every configuration on this display (the scene file's field of view) and named
    // so; the preset displays (study monitor, HMD eye) are left out.
    std::optional<vk::EyeDisplay> scene_display;
};
std::vector<Config> sweep_configs(const SweepOptions& o);

// What renders one configuration's frames: demo::run's contract (results[0] the full-rate
// reference). Empty: demo::run on `device`, the demo scene.
using FrameRunner =
    std::function<Result<std::vector<demo::MethodResult>>(const demo::RunOptions& options)>;

// Renders every configuration. `progress(done, total, what)` after each measured frame.
Result<std::vector<Row>> run_sweep(
    const vk::Device& device, const std::vector<Config>& configs, int frames,
    const std::function<void(int done, int total, const std::string& what)>& progress,
    const FrameRunner& runner = {});

}  // namespace fovea::bench
