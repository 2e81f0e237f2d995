#include "saccade_model.hpp"

#include <cmath>
#include <vector>

namespace fovea::vk::post {

Image render_cps(const Image& sharp, float gx, float gy, const SaccadeExperiment& e, Image& rate) {
    const int w = sharp.width;
    const int h = sharp.height;
    Image out(w, h, 3);
    rate = Image(w, h, 1);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const float ecc =
                std::hypot(float(x) + 0.5f - gx, float(y) + 0.5f - gy) / e.pixels_per_degree;
            const int block = ecc < e.fovea_deg ? 1 : (ecc < e.periphery_deg ? 2 : 4);
            rate.at(x, y) = block == 1 ? 0.0f : (block == 2 ? 0.5f : 1.0f);
            // One shade per coarse pixel: the block's centre sample, replicated.
            const int sx = std::min(x / block * block + block / 2, w - 1);
            const int sy = std::min(y / block * block + block / 2, h - 1);
            for (int c = 0; c < 3; ++c) out.at(x, y, c) = sharp.at(sx, sy, c);
        }
    }
    return out;
}

SaccadeRecovery measure_saccade_recovery(const Image& sharp, const SaccadeExperiment& e,
                                         const TaaParams& params) {
    const float cy = 0.5f * float(sharp.height);
    const float ax = 0.5f * float(sharp.width) - 0.5f * e.jump_deg * e.pixels_per_degree;
    const float bx = 0.5f * float(sharp.width) + 0.5f * e.jump_deg * e.pixels_per_degree;
    Image depth(sharp.width, sharp.height, 1, 1.0f);
    Image rate_a, rate_b;
    const Image frame_a = render_cps(sharp, ax, cy, e, rate_a);
    const Image frame_b = render_cps(sharp, bx, cy, e, rate_b);

    TaaHistory hist;
    for (int i = 0; i < e.settle_frames; ++i) {
        (void)taa_resolve({&frame_a, &depth, nullptr, &rate_a, false}, hist, params);
    }
    // Tone-mapped luminance of the foveal region around B, per frame after the jump.
    auto region_luma = [&](const TaaHistory& h) {
        std::vector<float> v;
        for (int y = 0; y < sharp.height; ++y) {
            for (int x = 0; x < sharp.width; ++x) {
                const float ecc =
                    std::hypot(float(x) + 0.5f - bx, float(y) + 0.5f - cy) / e.pixels_per_degree;
                if (ecc >= e.fovea_deg) continue;
                v.push_back(
                    luma709(h.colour.at(x, y, 0), h.colour.at(x, y, 1), h.colour.at(x, y, 2)));
            }
        }
        return v;
    };
    std::vector<std::vector<float>> after;
    for (int i = 0; i < e.converge_frames; ++i) {
        (void)taa_resolve({&frame_b, &depth, nullptr, &rate_b, false}, hist, params);
        if (i < e.max_frames) after.push_back(region_luma(hist));
    }
    const std::vector<float> converged = region_luma(hist);
    SaccadeRecovery r;
    r.frames = e.max_frames + 1;
    for (std::size_t f = 0; f < after.size(); ++f) {
        double err = 0;
        for (std::size_t i = 0; i < converged.size(); ++i) {
            err += std::fabs(double(after[f][i]) - converged[i]);
        }
        err /= double(std::max<std::size_t>(converged.size(), 1));
        if (f == 0) r.first_error = err;
        if (err <= e.tolerance) {
            r.frames = int(f) + 1;
            break;
        }
    }
    return r;
}

}  // namespace fovea::vk::post
