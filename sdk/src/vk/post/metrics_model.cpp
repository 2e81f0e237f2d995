#include "metrics_model.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>

namespace fovea::vk::post {

namespace {

void fft1d(std::vector<std::complex<double>>& a) {
    const std::size_t n = a.size();
    for (std::size_t i = 1, j = 0; i < n; ++i) {
        std::size_t bit = n >> 1;
        for (; j & bit; bit >>= 1) j ^= bit;
        j ^= bit;
        if (i < j) std::swap(a[i], a[j]);
    }
    for (std::size_t len = 2; len <= n; len <<= 1) {
        const double ang = -2.0 * std::numbers::pi / double(len);
        const std::complex<double> wl(std::cos(ang), std::sin(ang));
        for (std::size_t i = 0; i < n; i += len) {
            std::complex<double> w(1.0);
            for (std::size_t j = 0; j < len / 2; ++j) {
                const auto u = a[i + j];
                const auto v = a[i + j + len / 2] * w;
                a[i + j] = u + v;
                a[i + j + len / 2] = u - v;
                w *= wl;
            }
        }
    }
}

bool is_pow2(int v) { return v > 0 && (v & (v - 1)) == 0; }

}  // namespace

Image tonemapped_luminance(const Image& rgb) {
    Image y(rgb.width, rgb.height, 1);
    auto tm = [](float v) {
        if (!std::isfinite(v)) return v > 0 ? 1.0f : 0.0f;
        v = std::max(v, 0.0f);
        return v / (1.0f + v);
    };
    for (int j = 0; j < rgb.height; ++j) {
        for (int i = 0; i < rgb.width; ++i) {
            const float r = tm(rgb.at(i, j, 0));
            const float g = rgb.channels > 1 ? tm(rgb.at(i, j, 1)) : r;
            const float b = rgb.channels > 2 ? tm(rgb.at(i, j, 2)) : r;
            y.at(i, j) = luma709(r, g, b);
        }
    }
    return y;
}

AtdResult average_temporal_difference(const Image& prev_y, const Image& cur_y,
                                      const Image* motion) {
    AtdResult r;
    double sum = 0;
    for (int y = 0; y < cur_y.height; ++y) {
        for (int x = 0; x < cur_y.width; ++x) {
            const float qx = float(x) + 0.5f - (motion ? motion->at(x, y, 0) : 0.0f);
            const float qy = float(y) + 0.5f - (motion ? motion->at(x, y, 1) : 0.0f);
            if (!(qx >= 0 && qy >= 0 && qx < float(prev_y.width) && qy < float(prev_y.height))) {
                ++r.skipped;
                continue;
            }
            const float d = std::fabs(cur_y.at(x, y) - sample_bilinear(prev_y, qx, qy));
            if (!std::isfinite(d)) {
                ++r.skipped;
                continue;
            }
            sum += d;
            ++r.pixels;
        }
    }
    r.mean = r.pixels ? sum / double(r.pixels) : 0.0;
    return r;
}

int EccentricityBands::band_of(float px, float py) const {
    const float e = std::hypot(px - gaze_x, py - gaze_y) / pixels_per_degree;
    for (std::size_t b = 0; b + 1 < edges_deg.size(); ++b) {
        if (e >= edges_deg[b] && e < edges_deg[b + 1]) return int(b);
    }
    return -1;
}

WaveletStats haar_wavelet_analysis(const Image& luma, const EccentricityBands& bands, int levels) {
    WaveletStats s;
    s.mean_energy.assign(std::size_t(levels), std::vector<double>(bands.count(), 0.0));
    s.max_energy.assign(std::size_t(levels), std::vector<double>(bands.count(), 0.0));
    Image ll = luma;
    for (int l = 1; l <= levels; ++l) {
        const int w = ll.width / 2;
        const int h = ll.height / 2;
        if (w < 1 || h < 1) break;
        Image next(w, h, 1);
        std::vector<std::size_t> n(bands.count(), 0);
        auto& mean = s.mean_energy[std::size_t(l - 1)];
        auto& mx = s.max_energy[std::size_t(l - 1)];
        const float scale = float(1 << l);
        for (int y = 0; y < h; ++y) {
            for (int x = 0; x < w; ++x) {
                const float a = ll.at(2 * x, 2 * y);
                const float b = ll.at(2 * x + 1, 2 * y);
                const float c = ll.at(2 * x, 2 * y + 1);
                const float d = ll.at(2 * x + 1, 2 * y + 1);
                // Orthonormal Haar: LL carries the average × 2, the details the differences.
                next.at(x, y) = 0.5f * (a + b + c + d);
                const double lh = 0.5 * (a - b + c - d);
                const double hl = 0.5 * (a + b - c - d);
                const double hh = 0.5 * (a - b - c + d);
                const double e = lh * lh + hl * hl + hh * hh;
                const int band =
                    bands.band_of((float(x) + 0.5f) * scale, (float(y) + 0.5f) * scale);
                if (band < 0) continue;
                mean[std::size_t(band)] += e;
                mx[std::size_t(band)] = std::max(mx[std::size_t(band)], e);
                ++n[std::size_t(band)];
            }
        }
        for (std::size_t b = 0; b < n.size(); ++b) {
            if (n[b]) mean[b] /= double(n[b]);
        }
        ll = std::move(next);
    }
    return s;
}

std::vector<double> rms_contrast_by_eccentricity(const Image& luma, const EccentricityBands& bands,
                                                 int tile) {
    std::vector<double> sum(bands.count(), 0.0);
    std::vector<std::size_t> n(bands.count(), 0);
    for (int ty = 0; ty + tile <= luma.height; ty += tile) {
        for (int tx = 0; tx + tile <= luma.width; tx += tile) {
            const int band =
                bands.band_of(float(tx) + 0.5f * float(tile), float(ty) + 0.5f * float(tile));
            if (band < 0) continue;
            double m1 = 0, m2 = 0;
            for (int y = ty; y < ty + tile; ++y) {
                for (int x = tx; x < tx + tile; ++x) {
                    m1 += luma.at(x, y);
                    m2 += double(luma.at(x, y)) * luma.at(x, y);
                }
            }
            const double cnt = double(tile) * tile;
            m1 /= cnt;
            m2 /= cnt;
            const double sd = std::sqrt(std::max(m2 - m1 * m1, 0.0));
            sum[std::size_t(band)] += m1 > 1e-6 ? sd / m1 : 0.0;
            ++n[std::size_t(band)];
        }
    }
    for (std::size_t b = 0; b < sum.size(); ++b) {
        if (n[b]) sum[b] /= double(n[b]);
    }
    return sum;
}

double radial_band_energy(const Image& luma, float f_lo, float f_hi) {
    if (!is_pow2(luma.width) || !is_pow2(luma.height)) return -1.0;
    const int w = luma.width;
    const int h = luma.height;
    std::vector<std::vector<std::complex<double>>> rows(static_cast<std::size_t>(h));
    for (int y = 0; y < h; ++y) {
        rows[std::size_t(y)].resize(std::size_t(w));
        for (int x = 0; x < w; ++x) rows[std::size_t(y)][std::size_t(x)] = luma.at(x, y);
        fft1d(rows[std::size_t(y)]);
    }
    double e = 0;
    std::vector<std::complex<double>> col(static_cast<std::size_t>(h));
    for (int x = 0; x < w; ++x) {
        for (int y = 0; y < h; ++y) col[std::size_t(y)] = rows[std::size_t(y)][std::size_t(x)];
        fft1d(col);
        const double fx = double(x <= w / 2 ? x : x - w) / double(w);
        for (int y = 0; y < h; ++y) {
            const double fy = double(y <= h / 2 ? y : y - h) / double(h);
            const double f = std::hypot(fx, fy);
            if (f == 0.0 || f < f_lo || f >= f_hi) continue;
            e += std::norm(col[std::size_t(y)]);
        }
    }
    return e;
}

}  // namespace fovea::vk::post
