// The `fovea bench` sweep: configurations (display, acuity, method options, post chain, methods)
// each rendered by demo::run on the demo camera path at display rate (1/60 s between frames, so
// the G-buffer motion vectors and TAA history describe consecutive frames) with a gaze trace
// window holding a saccade, against the full-rate reference with the same post chain. Every
// (configuration, method) pair becomes one Row.
#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "fovea/demo/demo.hpp"
#include "fovea/result.hpp"
#include "fovea/vk/acuity.hpp"
#include "fovea/vk/device.hpp"

namespace fovea::bench {

struct Config {
    std::string tag;                    // "default", "taa", ... (the same tag on every display)
    std::string display_name;           // "1920x1080", "hmd-eye 1440x1600"
    vk::EyeDisplay display;
    std::vector<std::string> acuity;    // "acuity.<field>=value", applied to vk::AcuityParams
    std::vector<std::string> options;   // FoveatorConfig::options ("kfr.sigma=1.6", ...)
    std::vector<std::string> post;      // post chain, also applied to the reference
    std::vector<std::string> methods;   // foveated methods; "full" always runs as reference
};

struct Row {
    std::string method, tag, display_name;
    std::string settings;               // the acuity/options/post keys this method reads
    uint32_t width = 0, height = 0;
    int frames = 0;
    double ms_median = 0, ms_p95 = 0;   // wall time per frame, submit -> done
    double method_gpu_ms = 0;
    double shaded_fraction = 0;
    double psnr_fovea_db = 0;           // capped at 100 (identical pixels)
    std::array<double, vk::kBandCount> psnr_bands_db{}, ssim_bands{};
    double psnr_bands_mean_db = 0;      // mean of the finite band PSNRs
    double atd = 0;                     // ATD of this row's output (with its post chain)
    double atd_8bit = 0;                // the same on the 8-bit frames (rounding floor ~1/4 LSB)
    double atd_settled = 0;             // ATD from frame kAtdSettledFrom on (TAA converged)
    double skipped_tiles = 0;           // mean per frame: tiles without a host shading call
    double reused_tiles = 0;            // mean per frame: of which last frame's shading kept
    std::string error;                  // method failed to initialise; other fields empty
};

// Sets one "acuity.<field>=value" on p; false for an unknown field or a bad number.
bool apply_acuity_setting(vk::AcuityParams& p, const std::string& key_value);

struct SweepOptions {
    bool quick = false;
    bool hmd = true;                     // full sweep only
    int frames = 0;                      // 0: 3 quick, 8 full
    std::vector<std::string> methods;    // empty: every registered method
    std::vector<std::string> extra_options;  // --method-option, added to every configuration
    uint32_t width = 0, height = 0;      // 0: the presets; else a desktop-FOV display of this size
};
std::vector<Config> sweep_configs(const SweepOptions& o);

// Renders every configuration. `progress(done, total, what)` after each measured frame.
Result<std::vector<Row>> run_sweep(
    const vk::Device& device, const std::vector<Config>& configs, int frames,
    const std::function<void(int done, int total, const std::string& what)>& progress);

}  // namespace fovea::bench
