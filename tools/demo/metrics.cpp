#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "fovea/demo/demo.hpp"
#include "fovea/half.hpp"
#include "fovea/metrics/image.hpp"

namespace fovea::demo {
namespace {

uint8_t to_srgb8(float c) {
    if (!(c > 0.f)) return 0;
    const float t = 1.f - std::exp(-c);  // exposure tone curve, maps [0, inf) to [0, 1)
    const float s = t <= 0.0031308f ? 12.92f * t : 1.055f * std::pow(t, 1.f / 2.4f) - 0.055f;
    return static_cast<uint8_t>(std::clamp(s * 255.f + 0.5f, 0.f, 255.f));
}

}  // namespace

Rgb8 tonemap(const std::vector<uint8_t>& raw, uint32_t w, uint32_t h) {
    Rgb8 out{w, h, std::vector<uint8_t>(size_t{w} * h * 3)};
    for (size_t i = 0; i < size_t{w} * h; ++i)
        for (int c = 0; c < 3; ++c)
            out.rgb[i * 3 + c] = to_srgb8(fovea::half_from_bytes(&raw[i * 8 + c * 2]));
    return out;
}

Rgb8 rate_map(const std::vector<uint8_t>& raw, uint32_t w, uint32_t h) {
    Rgb8 out{w, h, std::vector<uint8_t>(size_t{w} * h * 3)};
    for (size_t i = 0; i < size_t{w} * h; ++i) {
        const float s = fovea::half_from_bytes(&raw[i * 2]);
        uint8_t* p = &out.rgb[i * 3];
        if (s >= 0.99f) {
            p[0] = 200;
            p[1] = 40;
            p[2] = 40;
        } else if (s >= 0.49f) {
            p[0] = 40;
            p[1] = 170;
            p[2] = 60;
        } else {
            p[0] = 40;
            p[1] = 70;
            p[2] = 210;
        }
    }
    return out;
}

bool write_png(const std::string& path, const Rgb8& img) {
    return metrics::write_png(path, {img.width, img.height, img.rgb});
}

BandLabels band_labels(uint32_t w, uint32_t h, const vk::EyeDisplay& display,
                       const vk::ResolvedGaze& gaze, float foveal_radius_deg) {
    BandLabels l{std::vector<int8_t>(size_t{w} * h), std::vector<int8_t>(size_t{w} * h)};
    const float sx = static_cast<float>(display.width_px) / w;
    const float sy = static_cast<float>(display.height_px) / h;
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            const float e = vk::eccentricity_deg(display, (x + 0.5f) * sx, (y + 0.5f) * sy,
                                                 gaze.x_px, gaze.y_px);
            int b = 0;
            while (b + 1 < vk::kBandCount && e >= vk::kBandEdgesDeg[b + 1]) ++b;
            l.band[size_t{y} * w + x] = static_cast<int8_t>(b);
            l.fovea[size_t{y} * w + x] = e <= foveal_radius_deg ? 0 : -1;
        }
    return l;
}

void ErrorPool::add(const Rgb8& test, const Rgb8& ref, const BandLabels& labels) {
    const metrics::Rgb8View t{test.width, test.height, test.rgb}, r{ref.width, ref.height, ref.rgb};
    const std::vector<float> sq = metrics::squared_error_map(t, r);
    sq_.add(sq, labels.band);
    sq_fovea_.add(sq, labels.fovea);
    ssim_.add(metrics::ssim_map(t, r), labels.band);
}

ErrorFigures ErrorPool::figures() const {
    ErrorFigures f;
    double sq = 0, n = 0;
    for (int b = 0; b < vk::kBandCount; ++b) {
        f.psnr_bands_db[b] = metrics::psnr_db(sq_.sum(b), 3 * sq_.count(b));
        f.ssim_bands[b] = ssim_.mean(b);
        sq += sq_.sum(b);
        n += sq_.count(b);
    }
    f.psnr_db = metrics::psnr_db(sq, 3 * n);
    f.psnr_fovea_db = metrics::psnr_db(sq_fovea_.sum(0), 3 * sq_fovea_.count(0));
    return f;
}

ErrorFigures compare(const Rgb8& test, const Rgb8& ref, const vk::EyeDisplay& display,
                     const vk::ResolvedGaze& gaze, float foveal_radius_deg) {
    ErrorPool pool;
    pool.add(test, ref, band_labels(ref.width, ref.height, display, gaze, foveal_radius_deg));
    return pool.figures();
}

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const size_t m = v.size() / 2;
    return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

}  // namespace fovea::demo
