// CPU float images and the sampling rules the post-process reference models share with the GPU
// passes (clamp-to-edge texel fetch, manual bilinear, pyramid reduction). Plain C++, no Vulkan;
// any thread may use these, nothing is shared.
#pragma once

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "fovea/half.hpp"

namespace fovea::vk::post {

// Interleaved float image, row-major, `channels` floats per pixel.
struct Image {
    int width = 0;
    int height = 0;
    int channels = 1;
    std::vector<float> data;

    Image() = default;
    Image(int w, int h, int c, float fill = 0.0f)
        : width(w), height(h), channels(c), data(std::size_t(w) * h * c, fill) {}

    float& at(int x, int y, int c = 0) {
        assert(x >= 0 && y >= 0 && x < width && y < height && c < channels);
        return data[(std::size_t(y) * width + x) * channels + c];
    }
    float at(int x, int y, int c = 0) const {
        assert(x >= 0 && y >= 0 && x < width && y < height && c < channels);
        return data[(std::size_t(y) * width + x) * channels + c];
    }
    // Clamp-to-edge fetch: the GPU passes use texelFetch with clamped coordinates.
    float fetch(int x, int y, int c = 0) const {
        return at(std::clamp(x, 0, width - 1), std::clamp(y, 0, height - 1), c);
    }
    bool empty() const { return data.empty(); }
};

// Bilinear sample at continuous texel coordinates (texel centres at i + 0.5), clamp-to-edge.
inline float sample_bilinear(const Image& img, float tx, float ty, int c = 0) {
    const float fx = tx - 0.5f;
    const float fy = ty - 0.5f;
    const float x0f = std::floor(fx);
    const float y0f = std::floor(fy);
    const float ax = fx - x0f;
    const float ay = fy - y0f;
    const int x0 = int(x0f);
    const int y0 = int(y0f);
    const float a = img.fetch(x0, y0, c) * (1 - ax) + img.fetch(x0 + 1, y0, c) * ax;
    const float b = img.fetch(x0, y0 + 1, c) * (1 - ax) + img.fetch(x0 + 1, y0 + 1, c) * ax;
    return a * (1 - ay) + b * ay;
}

// 2×2 box reduction with Vulkan's mip sizes (floor, at least 1); a 1-texel-wide source repeats
// its texel (clamp), as the GPU does.
inline Image reduce_box2(const Image& src) {
    Image dst(std::max(1, src.width / 2), std::max(1, src.height / 2), src.channels);
    for (int y = 0; y < dst.height; ++y) {
        for (int x = 0; x < dst.width; ++x) {
            for (int c = 0; c < src.channels; ++c) {
                dst.at(x, y, c) =
                    0.25f * (src.fetch(2 * x, 2 * y, c) + src.fetch(2 * x + 1, 2 * y, c) +
                             src.fetch(2 * x, 2 * y + 1, c) + src.fetch(2 * x + 1, 2 * y + 1, c));
            }
        }
    }
    return dst;
}

// A mip chain: level 0 is the source; level l has size max(1, floor(size / 2^l)) (Vulkan's).
using MipChain = std::vector<Image>;

inline MipChain build_box_mips(Image level0, int levels) {
    MipChain chain;
    chain.push_back(std::move(level0));
    while (int(chain.size()) < levels && (chain.back().width > 1 || chain.back().height > 1)) {
        chain.push_back(reduce_box2(chain.back()));
    }
    return chain;
}

// Trilinear sample of a chain at pixel centre (px, py) of level 0 and a fractional LOD.
inline float sample_trilinear(const MipChain& chain, float px, float py, float lod, int c) {
    const float max_lod = float(chain.size() - 1);
    lod = std::clamp(lod, 0.0f, max_lod);
    const int l0 = int(std::floor(lod));
    const int l1 = std::min(l0 + 1, int(chain.size()) - 1);
    const float t = lod - float(l0);
    auto at_level = [&](int l) {
        const Image& m = chain[std::size_t(l)];
        const float u = px / float(chain[0].width);
        const float v = py / float(chain[0].height);
        return sample_bilinear(m, u * float(m.width), v * float(m.height), c);
    };
    const float a = at_level(l0);
    return t > 0.0f ? a + (at_level(l1) - a) * t : a;
}

// Rec. 709 luma weights; the models apply them to whatever space they are given.
inline float luma709(float r, float g, float b) { return 0.2126f * r + 0.7152f * g + 0.0722f * b; }

}  // namespace fovea::vk::post
