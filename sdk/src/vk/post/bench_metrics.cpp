#include "bench_metrics.hpp"

#include <cmath>
#include <cstring>

#include "fovea/half.hpp"
#include "metrics_model.hpp"
#include "saccade_model.hpp"
#include "stability_model.hpp"

namespace fovea::vk::post {

Image decode_half_image(const std::vector<std::uint8_t>& bytes, int width, int height,
                        int stored_channels, int keep_channels) {
    Image img(width, height, keep_channels);
    const std::size_t texels = std::size_t(width) * height;
    if (bytes.size() < texels * stored_channels * 2) return Image();
    for (std::size_t i = 0; i < texels; ++i) {
        for (int c = 0; c < keep_channels && c < stored_channels; ++c) {
            std::uint16_t h;
            std::memcpy(&h, bytes.data() + (i * stored_channels + c) * 2, 2);
            img.data[i * keep_channels + c] = half_from_bits(h);
        }
    }
    return img;
}

ModelPostFigures model_post_figures() {
    ModelPostFigures f;
    const StabilityResult s = measure_temporal_stability({}, {});
    f.atd = s.atd_cps_taa;
    f.atd_no_taa = s.atd_cps;
    f.atd_full_taa = s.atd_full_taa;
    // Same content as the saccade test: smooth colour texture, 4 px/deg, 20° jump.
    Image sharp(160, 64, 3);
    for (int y = 0; y < sharp.height; ++y)
        for (int x = 0; x < sharp.width; ++x) {
            const float fx = float(x) * 0.45f, fy = float(y) * 0.35f;
            sharp.at(x, y, 0) = 0.5f + 0.4f * std::sin(fx) * std::cos(fy);
            sharp.at(x, y, 1) = 0.5f + 0.4f * std::sin(0.7f * fx + 1.0f) * std::sin(fy);
            sharp.at(x, y, 2) = 0.5f + 0.4f * std::cos(0.5f * fx + 0.8f * fy);
        }
    TaaParams with, without;
    without.saccade.enabled = false;
    f.saccade_recovery_frames = measure_saccade_recovery(sharp, {}, with).frames;
    f.saccade_recovery_frames_no_term = measure_saccade_recovery(sharp, {}, without).frames;
    return f;
}

void AtdAccumulator::add_frame(const Image& linear_rgb, const Image* motion) {
    Image y = tonemapped_luminance(linear_rgb);
    if (!prev_y_.empty()) {
        sum_ += average_temporal_difference(prev_y_, y, motion).mean;
        ++frames_;
    }
    prev_y_ = std::move(y);
}

std::vector<float> RecoveryCounter::luma(const Image& rgb) const {
    const Image y = tonemapped_luminance(rgb);
    std::vector<float> v;
    for (int j = 0; j < y.height; ++j)
        for (int i = 0; i < y.width; ++i)
            if (std::hypot(float(i) + 0.5f - cx_, float(j) + 0.5f - cy_) < r_)
                v.push_back(y.at(i, j));
    return v;
}

int RecoveryCounter::frames(const Image& converged) const {
    const std::vector<float> c = luma(converged);
    for (std::size_t f = 0; f < frames_.size(); ++f) {
        double err = 0;
        for (std::size_t i = 0; i < c.size(); ++i) err += std::fabs(double(frames_[f][i]) - c[i]);
        if (c.empty() || err / double(c.size()) <= tol_) return int(f) + 1;
    }
    return int(frames_.size()) + 1;
}

}  // namespace fovea::vk::post
