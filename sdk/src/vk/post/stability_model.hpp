// Temporal-stability experiment on the reference models (Patney §4.4.3): an analytic, detailed
// texture panning slowly under a fixed gaze, point-sampled with Halton(2,3) jitter either at full
// rate or with coarse pixel shading (1×1 / 2×2 / 4×4 by eccentricity, one jittered shade per
// coarse pixel), with and without TAA; ATD of consecutive tone-mapped frames after
// back-projection. The GPU bench measures the same on the demo scene; any thread.
#pragma once

#include "saccade_model.hpp"
#include "taa_model.hpp"

namespace fovea::vk::post {

struct StabilityExperiment {
    int width = 128;
    int height = 96;
    int frames = 96;
    int warmup = 32;                 // frames before ATD is accumulated (TAA convergence)
    float pan_px_per_frame = 0.37f;  // slow camera pan
    std::uint32_t jitter_length = 8;
    SaccadeExperiment rates;  // eccentricity → rate, pixels per degree
};

struct StabilityResult {
    double atd_cps = 0;       // coarse shading, no TAA
    double atd_cps_taa = 0;   // coarse shading + TAA          (Fovea's "atd")
    double atd_full_taa = 0;  // full-rate reference + TAA
    double atd_full = 0;      // full rate, no TAA
};

StabilityResult measure_temporal_stability(const StabilityExperiment& e, const TaaParams& taa);

}  // namespace fovea::vk::post
