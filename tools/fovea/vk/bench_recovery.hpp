// Saccade recovery measured on the GPU path (`fovea bench`, methods.cps.saccade_recovery): cps +
// TAA on the demo scene seen by a still camera, the gaze held at A and then jumping `jump_deg` to
// B, rendered in lockstep with a run whose gaze was at B from the start (the same frame indices,
// hence the same jitter). Recovery is the first frame after the jump whose display luminance
// within the foveal radius of B is within `tolerance` (mean absolute) of that run's; once with
// TAA's saccade-aware alpha and once without (taa.saccade=0). One thread.
#pragma once

#include <string>

#include "fovea/result.hpp"
#include "fovea/vk/acuity.hpp"
#include "fovea/vk/device.hpp"

namespace fovea::bench {

struct RecoveryOptions {
    vk::EyeDisplay display = vk::EyeDisplay::desktop_1080p();
    float jump_deg = 20.f;
    float tolerance = 1.f / 255.f;
    int settle_frames = 8;  // under gaze A (after the camera cut at frame 0)
    int max_frames = 32;    // counted after the jump; max_frames + 1 = never recovered
};

struct RecoveryResult {
    int frames = 0;                                   // with the saccade-aware alpha
    int frames_no_term = 0;                           // without
    double first_error = 0, first_error_no_term = 0;  // on the jump frame
};

Result<RecoveryResult> measure_saccade_recovery(const vk::Device& device,
                                                const RecoveryOptions& options);

}  // namespace fovea::bench
