#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-function"
#endif
#include <stb/stb_image_write.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "fovea/demo/demo.hpp"

namespace fovea::demo {
namespace {

float half_to_float(const uint8_t* p) {
    uint16_t h;
    std::memcpy(&h, p, 2);
    const uint32_t s = (h >> 15) & 1, e = (h >> 10) & 31, m = h & 1023;
    float v;
    if (e == 0) v = std::ldexp(static_cast<float>(m), -24);
    else if (e == 31) v = m ? std::numeric_limits<float>::quiet_NaN() : INFINITY;
    else v = std::ldexp(static_cast<float>(m | 1024), static_cast<int>(e) - 25);
    return s ? -v : v;
}

uint8_t to_srgb8(float c) {
    if (!(c > 0.f)) return 0;
    const float t = 1.f - std::exp(-c);  // exposure tone curve, maps [0, inf) to [0, 1)
    const float s = t <= 0.0031308f ? 12.92f * t : 1.055f * std::pow(t, 1.f / 2.4f) - 0.055f;
    return static_cast<uint8_t>(std::clamp(s * 255.f + 0.5f, 0.f, 255.f));
}

// Separable 11-tap Gaussian (sigma 1.5) blur with clamped borders.
std::vector<float> blur(const std::vector<float>& in, uint32_t w, uint32_t h) {
    static const float k[11] = {0.00102818f, 0.00759876f, 0.03600077f, 0.10936069f, 0.21300554f,
                                0.26601172f, 0.21300554f, 0.10936069f, 0.03600077f, 0.00759876f,
                                0.00102818f};
    std::vector<float> tmp(in.size()), out(in.size());
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            float s = 0.f;
            for (int i = -5; i <= 5; ++i) {
                const int xx = std::clamp(static_cast<int>(x) + i, 0, static_cast<int>(w) - 1);
                s += k[i + 5] * in[size_t{y} * w + xx];
            }
            tmp[size_t{y} * w + x] = s;
        }
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            float s = 0.f;
            for (int i = -5; i <= 5; ++i) {
                const int yy = std::clamp(static_cast<int>(y) + i, 0, static_cast<int>(h) - 1);
                s += k[i + 5] * tmp[size_t(yy) * w + x];
            }
            out[size_t{y} * w + x] = s;
        }
    return out;
}

double psnr(double sq_err, double count) {
    if (count <= 0) return std::numeric_limits<double>::quiet_NaN();
    const double mse = sq_err / count;
    if (mse <= 0) return 100.0;
    return std::min(100.0, 10.0 * std::log10(255.0 * 255.0 / mse));
}

}  // namespace

Rgb8 tonemap(const std::vector<uint8_t>& raw, uint32_t w, uint32_t h) {
    Rgb8 out{w, h, std::vector<uint8_t>(size_t{w} * h * 3)};
    for (size_t i = 0; i < size_t{w} * h; ++i)
        for (int c = 0; c < 3; ++c) out.rgb[i * 3 + c] = to_srgb8(half_to_float(&raw[i * 8 + c * 2]));
    return out;
}

Rgb8 rate_map(const std::vector<uint8_t>& raw, uint32_t w, uint32_t h) {
    Rgb8 out{w, h, std::vector<uint8_t>(size_t{w} * h * 3)};
    for (size_t i = 0; i < size_t{w} * h; ++i) {
        const float s = half_to_float(&raw[i * 2]);
        uint8_t* p = &out.rgb[i * 3];
        if (s >= 0.99f) { p[0] = 200; p[1] = 40; p[2] = 40; }
        else if (s >= 0.49f) { p[0] = 40; p[1] = 170; p[2] = 60; }
        else { p[0] = 40; p[1] = 70; p[2] = 210; }
    }
    return out;
}

bool write_png(const std::string& path, const Rgb8& img) {
    return stbi_write_png(path.c_str(), static_cast<int>(img.width), static_cast<int>(img.height),
                          3, img.rgb.data(), static_cast<int>(img.width * 3)) != 0;
}

ErrorFigures compare(const Rgb8& test, const Rgb8& ref, const vk::EyeDisplay& display,
                     const vk::ResolvedGaze& gaze, float foveal_radius_deg) {
    const uint32_t w = ref.width, h = ref.height;
    const size_t n = size_t{w} * h;
    std::vector<int8_t> band(n);
    std::vector<uint8_t> fovea(n);
    // The metrics work in the rendered image's pixels; the model in the display's.
    const float sx = static_cast<float>(display.width_px) / w;
    const float sy = static_cast<float>(display.height_px) / h;
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            const float e = vk::eccentricity_deg(display, (x + 0.5f) * sx, (y + 0.5f) * sy,
                                                 gaze.x_px, gaze.y_px);
            int b = 0;
            while (b + 1 < vk::kBandCount && e >= vk::kBandEdgesDeg[b + 1]) ++b;
            band[size_t{y} * w + x] = static_cast<int8_t>(b);
            fovea[size_t{y} * w + x] = e <= foveal_radius_deg;
        }
    double fov_err = 0, fov_n = 0;
    std::array<double, vk::kBandCount> err{}, cnt{}, ssim_sum{};
    std::vector<float> lt(n), lr(n);
    for (size_t i = 0; i < n; ++i) {
        double e2 = 0;
        for (int c = 0; c < 3; ++c) {
            const double d = double(test.rgb[i * 3 + c]) - ref.rgb[i * 3 + c];
            e2 += d * d;
        }
        err[band[i]] += e2;
        cnt[band[i]] += 3;
        if (fovea[i]) {
            fov_err += e2;
            fov_n += 3;
        }
        lt[i] = 0.299f * test.rgb[i * 3] + 0.587f * test.rgb[i * 3 + 1] + 0.114f * test.rgb[i * 3 + 2];
        lr[i] = 0.299f * ref.rgb[i * 3] + 0.587f * ref.rgb[i * 3 + 1] + 0.114f * ref.rgb[i * 3 + 2];
    }
    // SSIM (Wang et al. 2004) on luminance, Gaussian window, averaged within each band.
    std::vector<float> tt(n), rr(n), tr(n);
    for (size_t i = 0; i < n; ++i) {
        tt[i] = lt[i] * lt[i];
        rr[i] = lr[i] * lr[i];
        tr[i] = lt[i] * lr[i];
    }
    const auto mt = blur(lt, w, h), mr = blur(lr, w, h), stt = blur(tt, w, h),
               srr = blur(rr, w, h), str = blur(tr, w, h);
    const double c1 = (0.01 * 255) * (0.01 * 255), c2 = (0.03 * 255) * (0.03 * 255);
    for (size_t i = 0; i < n; ++i) {
        const double a = mt[i], b = mr[i];
        const double va = stt[i] - a * a, vb = srr[i] - b * b, cov = str[i] - a * b;
        ssim_sum[band[i]] += ((2 * a * b + c1) * (2 * cov + c2)) /
                             ((a * a + b * b + c1) * (va + vb + c2));
    }
    ErrorFigures f;
    f.psnr_fovea_db = psnr(fov_err, fov_n);
    for (int b = 0; b < vk::kBandCount; ++b) {
        f.psnr_bands_db[b] = psnr(err[b], cnt[b]);
        f.ssim_bands[b] = cnt[b] > 0 ? ssim_sum[b] / (cnt[b] / 3)
                                     : std::numeric_limits<double>::quiet_NaN();
    }
    return f;
}

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const size_t m = v.size() / 2;
    return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

}  // namespace fovea::demo
