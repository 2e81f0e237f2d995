// Saccade recovery experiment on the TAA reference model: a scene rendered with coarse pixel
// shading (1×1 / 2×2 / 4×4 by eccentricity, S_t = 0 / 0.5 / 1), converged under gaze A, then the
// gaze jumps by `jump_deg`; counts frames until the new foveal region is within `tolerance` (mean
// absolute tone-mapped luminance) of the image TAA converges to under gaze B.
// Used by tests and by `fovea bench`; any thread.
#pragma once

#include "image_model.hpp"
#include "taa_model.hpp"

namespace fovea::vk::post {

struct SaccadeExperiment {
    float pixels_per_degree = 4.0f;
    float jump_deg = 20.0f;
    float fovea_deg = 5.0f;       // S = 0 inside
    float periphery_deg = 15.0f;  // S = 1 beyond; 0.5 in between
    float tolerance = 1.0f / 255.0f;
    int settle_frames = 80;     // frames under gaze A before the jump
    int converge_frames = 160;  // frames under gaze B that define "converged"
    int max_frames = 60;        // recovery counted up to this; max_frames + 1 = never
};

// Renders `sharp` (linear RGB) as coarse pixel shading around a gaze point: shading rate per pixel
// from eccentricity, colour replicated over 2×2 / 4×4 blocks. Returns colour; `rate` gets S_t.
Image render_cps(const Image& sharp, float gaze_x, float gaze_y, const SaccadeExperiment& e,
                 Image& rate);

struct SaccadeRecovery {
    int frames = 0;          // first frame after the jump (1 = the jump frame) within tolerance
    double first_error = 0;  // error on the jump frame
};
// The gaze starts 0.5·jump left of centre and lands 0.5·jump right of it (horizontal jump).
SaccadeRecovery measure_saccade_recovery(const Image& sharp, const SaccadeExperiment& e,
                                         const TaaParams& params);

}  // namespace fovea::vk::post
