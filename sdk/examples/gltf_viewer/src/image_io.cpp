#include "gltf_viewer/image_io.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <stb_image_write.h>  // Debian's libstb (pkg-config stb)
#include <fovea/half.hpp>

namespace gltfv {

namespace {

uint8_t to_srgb8(float linear) {
    const float c = std::clamp(linear, 0.f, 1.f);
    const float s = c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.f / 2.4f) - 0.055f;
    return uint8_t(std::lround(s * 255.f));
}

}  // namespace

Rgb8 tonemap(const std::vector<uint8_t>& px, uint32_t w, uint32_t h) {
    Rgb8 out{w, h, std::vector<uint8_t>(size_t(w) * h * 3)};
    for (size_t i = 0; i < size_t(w) * h; ++i)
        for (int c = 0; c < 3; ++c) {
            uint16_t v;
            std::memcpy(&v, &px[i * 8 + size_t(c) * 2], 2);
            const float f = fovea::half_from_bits(v);
            out.rgb[i * 3 + size_t(c)] =
                std::isfinite(f) ? to_srgb8(f / (1.f + std::max(f, 0.f))) : 0;
        }
    return out;
}

Rgb8 rate_colours(const std::vector<uint8_t>& px, uint32_t w, uint32_t h) {
    Rgb8 out{w, h, std::vector<uint8_t>(size_t(w) * h * 3)};
    for (size_t i = 0; i < size_t(w) * h; ++i) {
        uint16_t v;
        std::memcpy(&v, &px[i * 2], 2);
        const float s = std::clamp(fovea::half_from_bits(v), 0.f, 1.f);
        const uint8_t rgb[3] = {uint8_t(255 * std::max(0.f, 2 * s - 1)),
                                uint8_t(255 * (1 - std::abs(2 * s - 1))),
                                uint8_t(255 * std::max(0.f, 1 - 2 * s))};
        std::memcpy(&out.rgb[i * 3], rgb, 3);
    }
    return out;
}

bool write_png(const std::string& path, const Rgb8& im) {
    return stbi_write_png(path.c_str(), int(im.width), int(im.height), 3, im.rgb.data(),
                          int(im.width * 3)) != 0;
}

FrameHealth frame_health(const std::vector<uint8_t>& px) {
    FrameHealth f;
    for (size_t i = 0; i + 8 <= px.size(); i += 8) {
        bool black = true;
        for (int c = 0; c < 3; ++c) {
            uint16_t v;
            std::memcpy(&v, &px[i + size_t(c) * 2], 2);
            const float x = fovea::half_from_bits(v);
            f.non_finite += !std::isfinite(x);
            black &= x == 0.f;
        }
        f.black += black;
    }
    return f;
}

Psnr psnr(const Rgb8& test, const Rgb8& ref, const fovea::vk::EyeDisplay& d,
          const fovea::vk::ResolvedGaze& gaze, float foveal_radius_deg) {
    double fovea_se = 0, fovea_n = 0;
    std::array<double, fovea::vk::kBandCount> se{}, n{};
    for (uint32_t y = 0; y < test.height; ++y)
        for (uint32_t x = 0; x < test.width; ++x) {
            const size_t i = (size_t(y) * test.width + x) * 3;
            double e = 0;
            for (int c = 0; c < 3; ++c) {
                const double diff = double(test.rgb[i + size_t(c)]) - ref.rgb[i + size_t(c)];
                e += diff * diff;
            }
            const float ecc =
                fovea::vk::eccentricity_deg(d, x + 0.5f, y + 0.5f, gaze.x_px, gaze.y_px);
            if (ecc <= foveal_radius_deg) {
                fovea_se += e;
                fovea_n += 3;
            }
            for (int b = 0; b < fovea::vk::kBandCount; ++b)
                if (ecc >= fovea::vk::kBandEdgesDeg[b] && ecc < fovea::vk::kBandEdgesDeg[b + 1]) {
                    se[size_t(b)] += e;
                    n[size_t(b)] += 3;
                }
        }
    const auto db = [](double sum, double count, double empty) {
        if (count == 0) return empty;
        const double mse = sum / count;
        return mse <= 0 ? 100.0 : std::min(100.0, 10.0 * std::log10(255.0 * 255.0 / mse));
    };
    Psnr p;
    p.fovea_db = db(fovea_se, fovea_n, NAN);
    for (int b = 0; b < fovea::vk::kBandCount; ++b)
        p.bands_db[size_t(b)] = db(se[size_t(b)], n[size_t(b)], NAN);
    return p;
}

}  // namespace gltfv
