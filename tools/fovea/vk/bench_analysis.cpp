#include "bench_analysis.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "fovea/half.hpp"

namespace fovea::bench {

std::vector<size_t> pareto_front(const std::vector<CostError>& points) {
    std::vector<size_t> order;
    for (size_t i = 0; i < points.size(); ++i)
        if (std::isfinite(points[i].cost) && !std::isnan(points[i].error) &&
            points[i].error != std::numeric_limits<double>::infinity())
            order.push_back(i);
    // Cheapest first; at equal cost the lowest error first, so a sweep keeping the lowest error
    // seen so far accepts exactly the undominated points.
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
        if (points[a].cost != points[b].cost) return points[a].cost < points[b].cost;
        return points[a].error < points[b].error;
    });
    std::vector<size_t> front;
    double best = std::numeric_limits<double>::infinity();
    for (size_t i : order) {
        if (points[i].error < best) {
            front.push_back(i);
            best = points[i].error;
        }
    }
    return front;
}

double percentile(std::vector<double> v, double p) {
    if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
    std::sort(v.begin(), v.end());
    const double rank = std::ceil(std::clamp(p, 0.0, 100.0) / 100.0 * double(v.size()));
    return v[size_t(std::max(rank, 1.0)) - 1];
}

double finite_mean(const std::vector<double>& v) {
    double sum = 0.0;
    int n = 0;
    for (double x : v)
        if (std::isfinite(x)) {
            sum += x;
            ++n;
        }
    return n > 0 ? sum / n : std::numeric_limits<double>::quiet_NaN();
}

std::vector<float> luminance(const std::vector<uint8_t>& rgb, uint32_t width, uint32_t height) {
    std::vector<float> l(size_t(width) * height);
    for (size_t i = 0; i < l.size(); ++i)
        l[i] = (0.2126f * rgb[3 * i] + 0.7152f * rgb[3 * i + 1] + 0.0722f * rgb[3 * i + 2]) / 255.f;
    return l;
}

std::vector<float> luminance_rgba16f(const std::vector<uint8_t>& rgba16f, uint32_t width,
                                     uint32_t height) {
    // demo::tonemap's curve (1 - e^-c, sRGB encode) without rounding to 8 bits.
    const auto encode = [](float c) {
        if (!(c > 0.f)) return 0.f;
        const float t = 1.f - std::exp(-c);
        const float s = t <= 0.0031308f ? 12.92f * t : 1.055f * std::pow(t, 1.f / 2.4f) - 0.055f;
        return std::clamp(s, 0.f, 1.f);
    };
    std::vector<float> l(size_t(width) * height);
    for (size_t i = 0; i < l.size(); ++i) {
        float c[3];
        for (int k = 0; k < 3; ++k) {
            uint16_t h;
            std::memcpy(&h, rgba16f.data() + 8 * i + 2 * k, 2);
            c[k] = encode(fovea::half_from_bits(h));
        }
        l[i] = 0.2126f * c[0] + 0.7152f * c[1] + 0.0722f * c[2];
    }
    return l;
}

std::vector<float> decode_rg16f(const std::vector<uint8_t>& rg16f) {
    std::vector<float> out(rg16f.size() / 2);
    for (size_t i = 0; i < out.size(); ++i) {
        uint16_t h;
        std::memcpy(&h, rg16f.data() + 2 * i, 2);
        out[i] = fovea::half_from_bits(h);
    }
    return out;
}

double temporal_difference(const std::vector<float>& previous_luma,
                           const std::vector<float>& current_luma,
                           const std::vector<float>& motion_px, uint32_t width, uint32_t height) {
    double sum = 0.0;
    size_t n = 0;
    const auto at = [&](uint32_t x, uint32_t y) { return previous_luma[size_t(y) * width + x]; };
    for (uint32_t y = 0; y < height; ++y) {
        for (uint32_t x = 0; x < width; ++x) {
            const size_t i = size_t(y) * width + x;
            const float mx = motion_px[2 * i], my = motion_px[2 * i + 1];
            if (!std::isfinite(mx) || !std::isfinite(my)) continue;
            // Previous position of this pixel's centre, in continuous pixel coordinates whose
            // texel centres sit at integer + 0.5; bilinear needs both neighbours inside.
            const float px = float(x) + 0.5f - mx - 0.5f, py = float(y) + 0.5f - my - 0.5f;
            if (px < 0.f || py < 0.f || px > float(width - 1) || py > float(height - 1)) continue;
            const uint32_t x0 = uint32_t(px), y0 = uint32_t(py);
            const uint32_t x1 = std::min(x0 + 1, width - 1), y1 = std::min(y0 + 1, height - 1);
            const float fx = px - float(x0), fy = py - float(y0);
            const float prev = (at(x0, y0) * (1.f - fx) + at(x1, y0) * fx) * (1.f - fy) +
                               (at(x0, y1) * (1.f - fx) + at(x1, y1) * fx) * fy;
            sum += std::fabs(current_luma[i] - prev);
            ++n;
        }
    }
    return n > 0 ? sum / double(n) : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace fovea::bench
