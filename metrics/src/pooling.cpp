#include "fovea/metrics/pooling.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace fovea::metrics {
namespace {

// Separable 11-tap Gaussian (sd 1.5) with clamped borders.
std::vector<float> blur(const std::vector<float>& in, uint32_t w, uint32_t h) {
    static const float k[11] = {0.00102818f, 0.00759876f, 0.03600077f, 0.10936069f,
                                0.21300554f, 0.26601172f, 0.21300554f, 0.10936069f,
                                0.03600077f, 0.00759876f, 0.00102818f};
    std::vector<float> tmp(in.size()), out(in.size());
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            float s = 0.f;
            for (int i = -5; i <= 5; ++i)
                s += k[i + 5] * in[size_t(y) * w + std::clamp(int(x) + i, 0, int(w) - 1)];
            tmp[size_t(y) * w + x] = s;
        }
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            float s = 0.f;
            for (int i = -5; i <= 5; ++i)
                s += k[i + 5] * tmp[size_t(std::clamp(int(y) + i, 0, int(h) - 1)) * w + x];
            out[size_t(y) * w + x] = s;
        }
    return out;
}

std::vector<float> luma601(const Rgb8View& v) {
    std::vector<float> l(size_t(v.width) * v.height);
    for (size_t i = 0; i < l.size(); ++i)
        l[i] = 0.299f * v.rgb[3 * i] + 0.587f * v.rgb[3 * i + 1] + 0.114f * v.rgb[3 * i + 2];
    return l;
}

void check_sizes(const Rgb8View& a, const Rgb8View& b) {
    assert(a.width == b.width && a.height == b.height);
    assert(a.rgb.size() >= size_t(a.width) * a.height * 3);
    assert(b.rgb.size() >= size_t(b.width) * b.height * 3);
    (void)a;
    (void)b;
}

}  // namespace

std::vector<float> squared_error_map(const Rgb8View& test, const Rgb8View& reference) {
    check_sizes(test, reference);
    std::vector<float> e(size_t(test.width) * test.height);
    for (size_t i = 0; i < e.size(); ++i) {
        int s = 0;
        for (int c = 0; c < 3; ++c) {
            const int d = int(test.rgb[3 * i + c]) - int(reference.rgb[3 * i + c]);
            s += d * d;
        }
        e[i] = float(s);  // exact: at most 3 * 255^2
    }
    return e;
}

std::vector<float> ssim_map(const Rgb8View& test, const Rgb8View& reference) {
    check_sizes(test, reference);
    const uint32_t w = test.width, h = test.height;
    const std::vector<float> lt = luma601(test), lr = luma601(reference);
    const size_t n = lt.size();
    std::vector<float> tt(n), rr(n), tr(n);
    for (size_t i = 0; i < n; ++i) {
        tt[i] = lt[i] * lt[i];
        rr[i] = lr[i] * lr[i];
        tr[i] = lt[i] * lr[i];
    }
    const auto mt = blur(lt, w, h), mr = blur(lr, w, h), stt = blur(tt, w, h), srr = blur(rr, w, h),
               str = blur(tr, w, h);
    const double c1 = (0.01 * 255) * (0.01 * 255), c2 = (0.03 * 255) * (0.03 * 255);
    std::vector<float> s(n);
    for (size_t i = 0; i < n; ++i) {
        const double a = mt[i], b = mr[i];
        const double va = stt[i] - a * a, vb = srr[i] - b * b, cov = str[i] - a * b;
        s[i] = float(((2 * a * b + c1) * (2 * cov + c2)) / ((a * a + b * b + c1) * (va + vb + c2)));
    }
    return s;
}

void RegionSums::add(std::span<const float> values, std::span<const int8_t> labels) {
    assert(values.size() == labels.size());
    for (size_t i = 0; i < values.size(); ++i) {
        const int r = labels[i];
        if (r < 0 || r >= regions() || !std::isfinite(values[i])) continue;
        sum_[r] += values[i];
        count_[r] += 1.0;
    }
}

double RegionSums::mean(int region) const {
    return count_.at(region) > 0 ? sum_[region] / count_[region]
                                 : std::numeric_limits<double>::quiet_NaN();
}

double psnr_db(double squared_error_sum, double samples, double peak) {
    if (!(samples > 0)) return std::numeric_limits<double>::quiet_NaN();
    if (squared_error_sum <= 0) return std::numeric_limits<double>::infinity();
    return 10.0 * std::log10(peak * peak * samples / squared_error_sum);
}

}  // namespace fovea::metrics
