// LDR-FLIP of every method's frames in `fovea bench`, on the device (fovea::metrics::GpuFlip):
// against the full-rate reference of the same frame at the ppd each pixel is seen at (the
// display's geometry) and at the FLIP tool's 67 ppd, and against the method's own previous frame
// back-projected along the motion (temporal FLIP). Maps are pooled per eccentricity band on the
// CPU with the same labels as PSNR. One thread; one configuration at a time.
#pragma once

#include <array>
#include <memory>
#include <utility>
#include <vector>

#include "fovea/demo/demo.hpp"
#include "fovea/metrics/gpu_flip.hpp"
#include "fovea/metrics/pooling.hpp"
#include "fovea/result.hpp"
#include "gpu.hpp"

namespace fovea::bench {

// What one method's frames gave, pooled over them.
struct FlipSums {
    metrics::RegionSums display{vk::kBandCount};   // FLIP at the display's ppd, per band
    metrics::RegionSums tool{vk::kBandCount};      // at 67 ppd
    metrics::RegionSums ppd{vk::kBandCount};       // the ppd each band's pixels are seen at
    std::vector<std::pair<int, double>> temporal;  // (frame, mean temporal FLIP), frames > 0
    std::vector<double> gpu_ms;                    // per frame: one compare at the display's ppd
};

class BenchFlip {
public:
    // Pipelines and buffers for one display (slow on lavapipe: keep it while the display stays).
    static Result<std::unique_ptr<BenchFlip>> create(const vk::Device& device,
                                                     const vk::EyeDisplay& display);
    // Starts a configuration of `methods` methods (including "full"): sums and history cleared.
    void begin(size_t methods);
    // Called for every method's frame, "full" (method 0) first in each frame. `motion`: per
    // pixel, current - previous position of the displayed pixel centre (motion + jitter).
    // reference: this output is what the methods after it are compared with (method 0; the glTF
    // scene's "full-forward" for its forward paths).
    void add_frame(size_t method, int frame, const vk::ImageRef& output,
                   const demo::BandLabels& labels, const std::vector<float>& motion,
                   bool reference);
    const FlipSums& sums(size_t method) const { return sums_[method]; }

private:
    BenchFlip(const vk::Device& device, metrics::GpuFlip flip, std::vector<float> ppd_map);
    enum Slot { kDisplay = 0, kTemporal = 1, kTool = 2 };

    const vk::Device* device_;
    metrics::GpuFlip flip_;
    std::vector<float> ppd_map_;       // geometric mean of the per-axis ppd, per pixel
    std::vector<vk::Image> previous_;  // each method's last output
    std::vector<int> previous_frame_;  // its frame index (-1: none)
    std::vector<FlipSums> sums_;
};

}  // namespace fovea::bench
