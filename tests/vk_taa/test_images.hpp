// Synthetic test content with known structure for the post-process tests.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>

#include "image_model.hpp"

namespace fovea::vk::post::testing {

// Smooth, moderately detailed colour texture in [0.1, 0.9] (linear RGB).
inline Image texture(int w, int h, float scale = 1.0f) {
    Image img(w, h, 3);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const float fx = float(x) * 0.45f;
            const float fy = float(y) * 0.35f;
            img.at(x, y, 0) = scale * (0.5f + 0.4f * std::sin(fx) * std::cos(fy));
            img.at(x, y, 1) = scale * (0.5f + 0.4f * std::sin(0.7f * fx + 1.0f) * std::sin(fy));
            img.at(x, y, 2) = scale * (0.5f + 0.4f * std::cos(0.5f * fx + 0.8f * fy));
        }
    }
    return img;
}

// Zone plate cos(π r² / n): local frequency r / n cycles per pixel, 0 … 0.5 across the image.
inline Image zone_plate(int n, float contrast = 0.4f) {
    Image img(n, n, 1);
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
            const float dx = float(x) - 0.5f * float(n);
            const float dy = float(y) - 0.5f * float(n);
            img.at(x, y) = 0.5f + contrast * std::cos(std::numbers::pi_v<float> *
                                                      (dx * dx + dy * dy) / float(n));
        }
    }
    return img;
}

// Natural-image-like 1/f content: random-phase gratings with amplitude ∝ 1/f, mean 0.5.
inline Image pink_noise(int w, int h, float contrast = 0.12f, unsigned seed = 7) {
    Image img(w, h, 1, 0.5f);
    unsigned s = seed;
    auto rnd = [&s] {
        s = s * 1664525u + 1013904223u;
        return float(s >> 8) / 16777216.0f;
    };
    constexpr int kWaves = 160;
    for (int k = 0; k < kWaves; ++k) {
        const float f = 0.01f * std::pow(45.0f, rnd());  // 0.01 … 0.45 cycles per pixel
        const float th = 2 * std::numbers::pi_v<float> * rnd();
        const float ph = 2 * std::numbers::pi_v<float> * rnd();
        const float amp = contrast * 0.01f / f * 2.5f / std::sqrt(float(kWaves)) * 4.0f;
        const float fx = f * std::cos(th), fy = f * std::sin(th);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                img.at(x, y) +=
                    amp * std::cos(2 * std::numbers::pi_v<float> * (fx * x + fy * y) + ph);
    }
    for (float& v : img.data) v = std::clamp(v, 0.02f, 0.98f);
    return img;
}

// Exact separable Gaussian blur (σ in pixels), clamp-to-edge; σ ≤ 0 copies.
inline Image gaussian_blur(const Image& src, float sigma) {
    if (!(sigma > 0)) return src;
    const int r = int(std::ceil(3.5f * sigma));
    std::vector<float> k(std::size_t(2 * r + 1));
    float sum = 0;
    for (int i = -r; i <= r; ++i)
        sum += k[std::size_t(i + r)] = std::exp(-0.5f * float(i * i) / (sigma * sigma));
    for (float& v : k) v /= sum;
    Image tmp(src.width, src.height, src.channels), dst(src.width, src.height, src.channels);
    for (int y = 0; y < src.height; ++y)
        for (int x = 0; x < src.width; ++x)
            for (int c = 0; c < src.channels; ++c) {
                float a = 0;
                for (int i = -r; i <= r; ++i) a += k[std::size_t(i + r)] * src.fetch(x + i, y, c);
                tmp.at(x, y, c) = a;
            }
    for (int y = 0; y < src.height; ++y)
        for (int x = 0; x < src.width; ++x)
            for (int c = 0; c < src.channels; ++c) {
                float a = 0;
                for (int i = -r; i <= r; ++i) a += k[std::size_t(i + r)] * tmp.fetch(x, y + i, c);
                dst.at(x, y, c) = a;
            }
    return dst;
}

}  // namespace fovea::vk::post::testing
