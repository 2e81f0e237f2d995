#include "stability_model.hpp"

#include <cmath>

#include "metrics_model.hpp"

namespace fovea::vk::post {

namespace {

// Detailed content with energy up to and beyond Nyquist (a zone-plate-like chirp plus
// gratings), so point sampling aliases the way shading does.
Vec3 scene(float x, float y) {
    const float r2 = (x - 40.0f) * (x - 40.0f) + (y - 48.0f) * (y - 48.0f);
    const float a = 0.5f + 0.35f * std::cos(r2 * 0.004f);
    const float b = 0.5f + 0.3f * std::sin(0.9f * x + 0.2f * y) * std::cos(0.5f * y);
    const float c = 0.5f + 0.3f * std::cos(0.35f * x - 0.6f * y);
    return {a * 1.5f, b, 0.6f * c + 0.4f * a};
}

Image render(const StabilityExperiment& e, int frame, bool coarse, Image& rate) {
    const Jitter j =
        e.jitter_length ? halton_jitter(std::uint64_t(frame), e.jitter_length) : Jitter{};
    const float off = e.pan_px_per_frame * float(frame);
    const float gx = 0.5f * float(e.width);
    const float gy = 0.5f * float(e.height);
    Image out(e.width, e.height, 3);
    rate = Image(e.width, e.height, 1, 0.0f);
    for (int y = 0; y < e.height; ++y) {
        for (int x = 0; x < e.width; ++x) {
            int block = 1;
            if (coarse) {
                const float ecc = std::hypot(float(x) + 0.5f - gx, float(y) + 0.5f - gy) /
                                  e.rates.pixels_per_degree;
                block = ecc < e.rates.fovea_deg ? 1 : (ecc < e.rates.periphery_deg ? 2 : 4);
                rate.at(x, y) = block == 1 ? 0.0f : (block == 2 ? 0.5f : 1.0f);
            }
            // One jittered shade per coarse pixel at its centre.
            const float sx = float(x / block * block) + 0.5f * float(block) + j.x + off;
            const float sy = float(y / block * block) + 0.5f * float(block) + j.y;
            const Vec3 c = scene(sx, sy);
            out.at(x, y, 0) = c.x;
            out.at(x, y, 1) = c.y;
            out.at(x, y, 2) = c.z;
        }
    }
    return out;
}

double run(const StabilityExperiment& e, bool coarse, bool taa, const TaaParams& params) {
    Image depth(e.width, e.height, 1, 0.5f);
    Image motion(e.width, e.height, 2, 0.0f);
    for (int i = 0; i < e.width * e.height; ++i) {
        motion.data[std::size_t(i) * 2] = -e.pan_px_per_frame;  // content slides left
    }
    TaaHistory hist;
    Image prev_y;
    double sum = 0;
    int n = 0;
    for (int f = 0; f < e.frames; ++f) {
        Image rate;
        const Image frame = render(e, f, coarse, rate);
        const Image out =
            taa ? taa_resolve({&frame, &depth, &motion, &rate, false}, hist, params) : frame;
        Image y = tonemapped_luminance(out);
        if (f >= e.warmup && !prev_y.empty()) {
            sum += average_temporal_difference(prev_y, y, &motion).mean;
            ++n;
        }
        prev_y = std::move(y);
    }
    return n ? sum / n : 0.0;
}

}  // namespace

StabilityResult measure_temporal_stability(const StabilityExperiment& e, const TaaParams& taa) {
    StabilityResult r;
    r.atd_cps = run(e, true, false, taa);
    r.atd_cps_taa = run(e, true, true, taa);
    r.atd_full = run(e, false, false, taa);
    r.atd_full_taa = run(e, false, true, taa);
    return r;
}

}  // namespace fovea::vk::post
