// What `fovea bench` needs from the post-process work, as small accumulators over frames the
// bench reads back (any thread, one accumulator per run):
//   atd / atd_no_taa:        AtdAccumulator fed with each frame's output colour and the G-buffer
//                            motion (Patney §4.4.3); mean() over the camera path.
//   saccade_recovery_frames: RecoveryCounter fed with the frames after a gaze jump, then the
//                            converged frame; frames() = first frame within 1/255.
//   taa_enhance_ms:          median of FrameStats::post_gpu_ms with post_chain {"taa", ...}.
// read_linear_rgb() turns a read-back RGBA16F / RG16F image into a post::Image.
#pragma once

#include <cstdint>
#include <vector>

#include "image_model.hpp"

namespace fovea::vk::post {

// Decodes tightly packed half-float texels (Device::read_image of RGBA16F, RG16F, R16F).
Image decode_half_image(const std::vector<std::uint8_t>& bytes, int width, int height,
                        int stored_channels, int keep_channels);

// The same figures from the reference-model experiments (coarse pixel shading emulated on an
// analytic scene: stability_model.hpp, saccade_model.hpp), for when the bench has no per-frame
// read-back yet. Deterministic; takes ~10 s of CPU.
struct ModelPostFigures {
    double atd = 0;                   // cps + TAA, slow pan
    double atd_no_taa = 0;            // cps, slow pan
    double atd_full_taa = 0;          // full rate + TAA, slow pan
    int saccade_recovery_frames = 0;  // 20° jump, 1/255, saccade-aware α
    int saccade_recovery_frames_no_term = 0;
};
ModelPostFigures model_post_figures();

class AtdAccumulator {
public:
    // `linear_rgb`: this frame's output (≥ 3 channels); `motion`: current − previous, pixels.
    void add_frame(const Image& linear_rgb, const Image* motion);
    double mean() const { return frames_ ? sum_ / double(frames_) : 0.0; }
    int frames() const { return frames_; }

private:
    Image prev_y_;
    double sum_ = 0;
    int frames_ = 0;  // frame pairs measured
};

// Mean absolute tone-mapped luminance error over a region between each frame after a gaze jump
// and the converged image; frames() is the 1-based index of the first within `tolerance`.
class RecoveryCounter {
public:
    RecoveryCounter(float centre_x, float centre_y, float radius_px,
                    float tolerance = 1.0f / 255.0f)
        : cx_(centre_x), cy_(centre_y), r_(radius_px), tol_(tolerance) {}
    void add_frame(const Image& linear_rgb) { frames_.push_back(luma(linear_rgb)); }
    // Returns frames to recovery, or frames added + 1 when never within tolerance.
    int frames(const Image& converged_linear_rgb) const;

private:
    std::vector<float> luma(const Image& rgb) const;
    float cx_, cy_, r_, tol_;
    std::vector<std::vector<float>> frames_;
};

}  // namespace fovea::vk::post
