#include "enhance_model.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace fovea::vk::post {

namespace {

constexpr float kPi = std::numbers::pi_v<float>;

// Tariq 2022 Table 2.
constexpr std::array<float, 3> kBlurRates{0.11f, 0.34f, 0.57f};
constexpr std::array<float, 3> kFe{0.15f, 0.23f, 0.28f};
constexpr std::array<float, 3> kSk{22.4f, 21.02f, 18.68f};
constexpr std::array<float, 3> kSf{3.45f, 2.21f, 2.19f};

// Tariq 2022 Table 3 (Thibos et al. 1996), cycles per degree.
constexpr std::array<float, 7> kEcc{0, 5, 10, 15, 20, 25, 30};
constexpr std::array<float, 7> kTl{60, 27, 10.5f, 8, 5.5f, 4.8f, 4};
constexpr std::array<float, 7> kTh{60, 40, 26, 24, 23, 21, 20.5f};

template <std::size_t N>
float interp(const std::array<float, N>& xs, const std::array<float, N>& ys, float x) {
    if (!(x > xs[0])) return ys[0];  // also catches NaN
    for (std::size_t i = 1; i < N; ++i) {
        if (x <= xs[i]) {
            const float t = (x - xs[i - 1]) / (xs[i] - xs[i - 1]);
            return ys[i - 1] + (ys[i] - ys[i - 1]) * t;
        }
    }
    return ys[N - 1];  // beyond the measurements: hold the last value
}

Image reduce_minmax(const Image& src, bool take_max) {
    Image dst(std::max(1, src.width / 2), std::max(1, src.height / 2), 1);  // Vulkan mip sizes
    for (int y = 0; y < dst.height; ++y) {
        for (int x = 0; x < dst.width; ++x) {
            const float a = src.fetch(2 * x, 2 * y);
            const float b = src.fetch(2 * x + 1, 2 * y);
            const float c = src.fetch(2 * x, 2 * y + 1);
            const float d = src.fetch(2 * x + 1, 2 * y + 1);
            dst.at(x, y) = take_max ? std::max({a, b, c, d}) : std::min({a, b, c, d});
        }
    }
    return dst;
}

// Sample `level` of a chain at full-resolution pixel centre (px, py).
float sample_level(const MipChain& chain, int level, float px, float py) {
    level = std::clamp(level, 0, int(chain.size()) - 1);
    const Image& m = chain[std::size_t(level)];
    return sample_bilinear(m, px / float(chain[0].width) * float(m.width),
                           py / float(chain[0].height) * float(m.height));
}

float sanitize01(float v) { return std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f; }

}  // namespace

EnhanceCalibration calibration_for_blur_rate(float r) {
    return {interp(kBlurRates, kFe, r), interp(kBlurRates, kSk, r), interp(kBlurRates, kSf, r)};
}

ThibosLimits thibos_limits(float e) {
    e = std::fabs(e);
    return {interp(kEcc, kTl, e), interp(kEcc, kTh, e)};
}

NoiseBand noise_band(float ecc, float sigma_px, float ppd, float s_f) {
    NoiseBand b;
    const ThibosLimits t = thibos_limits(ecc);
    // σ → 0 means nothing was removed: the cut-off 3/(2πσ) is infinite and the band is empty.
    const float cutoff = sigma_px > 1e-6f ? 3.0f / (2.0f * kPi * sigma_px) : INFINITY;
    b.f_low = std::max(t.low_cpd / ppd, cutoff);
    b.f_high = std::min(t.high_cpd / ppd, 0.5f);
    if (b.empty()) return b;
    b.mu_n = 0.5f * (std::log(b.f_low) + std::log(b.f_high));
    b.sigma_n = 0.5f * s_f * (b.mu_n - std::log(b.f_low));
    return b;
}

float approx_erf(float x) {
    const float s = x < 0 ? -1.0f : 1.0f;
    x = std::fabs(x);
    const float t = 1.0f / (1.0f + 0.3275911f * x);
    const float y =
        1.0f - (((((1.061405429f * t - 1.453152027f) * t) + 1.421413741f) * t - 0.284496736f) * t +
                0.254829592f) *
                   t * std::exp(-x * x);
    return s * y;
}

float approx_erfinv(float x) {
    x = std::clamp(x, -0.999999f, 0.999999f);
    float w = -std::log((1.0f - x) * (1.0f + x));
    float p;
    if (w < 5.0f) {
        w -= 2.5f;
        p = 2.81022636e-08f;
        p = 3.43273939e-07f + p * w;
        p = -3.5233877e-06f + p * w;
        p = -4.39150654e-06f + p * w;
        p = 0.00021858087f + p * w;
        p = -0.00125372503f + p * w;
        p = -0.00417768164f + p * w;
        p = 0.246640727f + p * w;
        p = 1.50140941f + p * w;
    } else {
        w = std::sqrt(w) - 3.0f;
        p = -0.000200214257f;
        p = 0.000100950558f + p * w;
        p = 0.00134934322f + p * w;
        p = -0.00367342844f + p * w;
        p = 0.00573950773f + p * w;
        p = -0.0076224613f + p * w;
        p = 0.00943887047f + p * w;
        p = 1.00167406f + p * w;
        p = 2.83297682f + p * w;
    }
    return p * x;
}

float sample_band_frequency(const NoiseBand& b, float u) {
    if (b.empty()) return 0.0f;
    const float lo = std::log(b.f_low);
    const float hi = std::log(b.f_high);
    if (!(b.sigma_n > 1e-6f)) return std::exp(b.mu_n);
    // Φ(z) = (1 + erf(z/√2))/2; sample uniformly between Φ(z_lo) and Φ(z_hi), invert.
    const float r2 = std::numbers::sqrt2_v<float>;
    const float e_lo = approx_erf((lo - b.mu_n) / (b.sigma_n * r2));
    const float e_hi = approx_erf((hi - b.mu_n) / (b.sigma_n * r2));
    const float z = approx_erfinv(e_lo + (e_hi - e_lo) * u) * r2;
    return std::exp(std::clamp(b.mu_n + b.sigma_n * z, lo, hi));
}

MipChain gaussian_pyramid(const Image& luma, int levels) {
    constexpr float kW[5] = {1 / 16.0f, 4 / 16.0f, 6 / 16.0f, 4 / 16.0f, 1 / 16.0f};
    MipChain chain;
    chain.push_back(luma);
    while (int(chain.size()) < levels && (chain.back().width > 1 || chain.back().height > 1)) {
        const Image& src = chain.back();
        // Separable blur evaluated only at the even (kept) positions.
        Image dst(std::max(1, src.width / 2), std::max(1, src.height / 2), 1);  // Vulkan mip sizes
        for (int y = 0; y < dst.height; ++y) {
            for (int x = 0; x < dst.width; ++x) {
                float acc = 0.0f;
                for (int j = 0; j < 5; ++j) {
                    float row = 0.0f;
                    for (int i = 0; i < 5; ++i)
                        row += kW[i] * src.fetch(2 * x + i - 2, 2 * y + j - 2);
                    acc += kW[j] * row;
                }
                dst.at(x, y) = acc;
            }
        }
        chain.push_back(std::move(dst));
    }
    return chain;
}

MipChain laplacian_pyramid(const MipChain& g) {
    MipChain lap;
    for (std::size_t l = 0; l + 1 < g.size(); ++l) {
        Image d(g[l].width, g[l].height, 1);
        const Image& coarse = g[l + 1];
        for (int y = 0; y < d.height; ++y) {
            for (int x = 0; x < d.width; ++x) {
                const float up = sample_bilinear(
                    coarse, (float(x) + 0.5f) / float(d.width) * float(coarse.width),
                    (float(y) + 0.5f) / float(d.height) * float(coarse.height));
                d.at(x, y) = g[l].at(x, y) - up;
            }
        }
        lap.push_back(std::move(d));
    }
    lap.push_back(g.back());
    return lap;
}

MipChain min_pyramid(const Image& luma, int levels) {
    MipChain c{luma};
    while (int(c.size()) < levels) c.push_back(reduce_minmax(c.back(), false));
    return c;
}

MipChain max_pyramid(const Image& luma, int levels) {
    MipChain c{luma};
    while (int(c.size()) < levels) c.push_back(reduce_minmax(c.back(), true));
    return c;
}

float laplacian_level_for_blur(float sigma_px, float p) {
    if (!(sigma_px > 1e-6f)) return 0.0f;
    // Blur attenuates f by exp(−(2πσf)²/2); it equals p at f_p = sqrt(−2 ln p)/(2πσ).
    // Laplacian level l is centred on 2^−(l+0.5) cycles per pixel (Tariq Eq. 6).
    const float f_p = std::sqrt(-2.0f * std::log(p)) / (2.0f * kPi * sigma_px);
    return std::max(0.0f, -std::log2(f_p) - 0.5f);
}

float blur_lod(float sigma_px) {
    if (!(sigma_px > 0.0f)) return 0.0f;
    return std::log2(1.0f + std::numbers::sqrt2_v<float> * std::min(sigma_px, 1e6f));
}

float blur_sigma_for_rate(float s) {
    s = std::isfinite(s) ? std::clamp(s, 0.0f, 1.0f) : 1.0f;
    const float edge = std::exp2(2.0f * s);
    return std::sqrt(std::max(edge * edge - 1.0f, 0.0f) / 12.0f);
}

float display_encode(float c) {
    c = std::isfinite(c) ? std::max(c, 0.0f) : (c > 0 ? 3e38f : 0.0f);
    return std::pow(c / (1.0f + c), 1.0f / 2.2f);
}

float display_decode(float d) {
    const float t = std::pow(std::clamp(d, 0.0f, 1.0f), 2.2f);
    return std::min(t, 0.99999f) / (1.0f - std::min(t, 0.99999f));
}

Image contrast_enhance(const Image& luma, const Image& sigma_px, float f_e) {
    const int levels = 8;
    const MipChain g = gaussian_pyramid(luma, levels);
    Image out(luma.width, luma.height, 1);
    for (int y = 0; y < luma.height; ++y) {
        for (int x = 0; x < luma.width; ++x) {
            const float i = sanitize01(luma.at(x, y));
            float s = sigma_px.at(x, y);
            s = std::isfinite(s) ? std::clamp(s, 0.0f, 1e6f) : 0.0f;
            const float px = float(x) + 0.5f;
            const float py = float(y) + 0.5f;
            const float lod = std::min(blur_lod(s), float(g.size() - 1));
            const int l0 = int(std::floor(lod));
            const float t = lod - float(l0);
            float avg = sample_level(g, l0, px, py);
            if (t > 0.0f) avg += (sample_level(g, l0 + 1, px, py) - avg) * t;
            // Gain grows with the blur it compensates; capped so huge σ cannot explode.
            const float gain = f_e * std::min(1.0f + s, 16.0f);
            out.at(x, y) = std::clamp(i + gain * (i - sanitize01(avg)), 0.0f, 1.0f);
        }
    }
    return out;
}

std::uint32_t hash_u32(std::uint32_t x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

float hash_to_unit(std::uint32_t h) { return float(h >> 8) * (1.0f / 16777216.0f); }

float gabor_radius(float a) { return std::sqrt(-std::log(0.05f) / kPi) / a; }

int impulses_per_cell(int impulses_per_kernel) {
    // Cell side = kernel radius r, kernel area πr²: λπr² impulses per kernel.
    return std::max(1, int(std::lround(float(impulses_per_kernel) / kPi)));
}

Image noise_parameters(const NoiseInputs& in, const NoiseParams& p) {
    const Image& luma = *in.luma;
    const int w = luma.width;
    const int h = luma.height;
    Image clean(w, h, 1);
    for (std::size_t i = 0; i < clean.data.size(); ++i) clean.data[i] = sanitize01(luma.data[i]);
    const int levels = 8;
    const MipChain g = gaussian_pyramid(clean, levels);
    const MipChain lap = laplacian_pyramid(g);
    const MipChain mn = min_pyramid(clean, p.minmax_level + 1);
    const MipChain mx = max_pyramid(clean, p.minmax_level + 1);

    // Sobel on the Gaussian level used for orientation.
    const int ol = std::min(p.orientation_level, int(g.size()) - 1);
    const Image& go = g[std::size_t(ol)];
    Image grad(go.width, go.height, 2);
    for (int y = 0; y < go.height; ++y) {
        for (int x = 0; x < go.width; ++x) {
            auto f = [&](int dx, int dy) { return go.fetch(x + dx, y + dy); };
            grad.at(x, y, 0) =
                (f(1, -1) + 2 * f(1, 0) + f(1, 1)) - (f(-1, -1) + 2 * f(-1, 0) + f(-1, 1));
            grad.at(x, y, 1) =
                (f(-1, 1) + 2 * f(0, 1) + f(1, 1)) - (f(-1, -1) + 2 * f(0, -1) + f(1, -1));
        }
    }

    Image out(w, h, 4);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            float s = in.sigma_px->at(x, y);
            s = std::isfinite(s) ? std::clamp(s, 0.0f, 1e6f) : 0.0f;
            float e = in.ecc_deg->at(x, y);
            e = std::isfinite(e) ? e : 1e3f;
            const NoiseBand band = noise_band(e, s, p.pixels_per_degree, p.s_f);
            const float px = float(x) + 0.5f;
            const float py = float(y) + 0.5f;
            float k = 0.0f;
            if (!band.empty()) {
                const float lp =
                    std::min(laplacian_level_for_blur(s, p.attenuation_p), float(lap.size() - 2));
                const int l0 = int(std::floor(lp));
                const float t = lp - float(l0);
                constexpr float kTiny = 1e-6f;  // log-domain blend of |L| needs > 0
                const float a = std::log(std::fabs(sample_level(lap, l0, px, py)) + kTiny);
                const float b = std::log(std::fabs(sample_level(lap, l0 + 1, px, py)) + kTiny);
                k = p.s_k * std::max(std::exp(a + (b - a) * t) - kTiny, 0.0f);
                // Headroom to black and white in the 2^l neighbourhood; noise std K ≤ room/3.
                const float room = std::min(1.0f - sample_level(mx, p.minmax_level, px, py),
                                            sample_level(mn, p.minmax_level, px, py));
                k = std::clamp(k, 0.0f, std::max(room, 0.0f) / 3.0f);
            }
            // Orientation: bicubic (Catmull-Rom) upsampling of the level's gradient field.
            const float gx = px / float(w) * float(go.width) - 0.5f;
            const float gy = py / float(h) * float(go.height) - 0.5f;
            const float bx = std::floor(gx);
            const float by = std::floor(gy);
            const float tx = gx - bx;
            const float ty = gy - by;
            float vx = 0.0f;
            float vy = 0.0f;
            {
                const float t2x = tx * tx, t3x = t2x * tx, t2y = ty * ty, t3y = t2y * ty;
                const float wx[4] = {-0.5f * t3x + t2x - 0.5f * tx, 1.5f * t3x - 2.5f * t2x + 1.0f,
                                     -1.5f * t3x + 2.0f * t2x + 0.5f * tx, 0.5f * t3x - 0.5f * t2x};
                const float wy[4] = {-0.5f * t3y + t2y - 0.5f * ty, 1.5f * t3y - 2.5f * t2y + 1.0f,
                                     -1.5f * t3y + 2.0f * t2y + 0.5f * ty, 0.5f * t3y - 0.5f * t2y};
                for (int j = 0; j < 4; ++j) {
                    for (int i = 0; i < 4; ++i) {
                        vx += wx[i] * wy[j] * grad.fetch(int(bx) - 1 + i, int(by) - 1 + j, 0);
                        vy += wx[i] * wy[j] * grad.fetch(int(bx) - 1 + i, int(by) - 1 + j, 1);
                    }
                }
            }
            out.at(x, y, 0) = k;
            out.at(x, y, 1) = (vx * vx + vy * vy) > 1e-12f ? std::atan2(vy, vx) : 0.0f;
            out.at(x, y, 2) = band.empty() ? 0.0f : band.f_low;
            out.at(x, y, 3) = band.empty() ? 0.0f : band.f_high;
        }
    }
    return out;
}

Image gabor_noise(const NoiseInputs& in, const NoiseParams& p) {
    return synthesize_gabor_noise(noise_parameters(in, p), p);
}

Image synthesize_gabor_noise(const Image& params, const NoiseParams& p) {
    const int w = params.width;
    const int h = params.height;
    const float a = p.kernel_bandwidth;
    const float r = gabor_radius(a);
    const int per_cell = impulses_per_cell(p.impulses_per_kernel);
    // Sum of λ·E[w²]·∫g² = (n/r²)(1/3)(1/(4a²)); dividing by its root gives noise std ≈ K.
    const float norm = 1.0f / std::sqrt(float(per_cell) / (r * r) / 3.0f / (4.0f * a * a));
    const float s_f = p.s_f;
    Image out(w, h, 1);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const float px = float(x) + 0.5f;
            const float py = float(y) + 0.5f;
            const int cx = int(std::floor(px / r));
            const int cy = int(std::floor(py / r));
            float acc = 0.0f;
            for (int dj = -1; dj <= 1; ++dj) {
                for (int di = -1; di <= 1; ++di) {
                    const int ci = cx + di;
                    const int cj = cy + dj;
                    std::uint32_t st = hash_u32(std::uint32_t(ci) * 73856093u ^
                                                std::uint32_t(cj) * 19349663u ^ p.seed);
                    for (int k = 0; k < per_cell; ++k) {
                        st = hash_u32(st);
                        const float ix = (float(ci) + hash_to_unit(st)) * r;
                        st = hash_u32(st);
                        const float iy = (float(cj) + hash_to_unit(st)) * r;
                        st = hash_u32(st);
                        const float wgt = 2.0f * hash_to_unit(st) - 1.0f;
                        st = hash_u32(st);
                        const float u = hash_to_unit(st);
                        const float dx = px - ix;
                        const float dy = py - iy;
                        const float d2 = dx * dx + dy * dy;
                        if (d2 >= r * r) continue;
                        const int qx = std::clamp(int(ix), 0, w - 1);
                        const int qy = std::clamp(int(iy), 0, h - 1);
                        const float amp = params.at(qx, qy, 0);
                        if (!(amp > 0.0f)) continue;
                        NoiseBand band;
                        band.f_low = params.at(qx, qy, 2);
                        band.f_high = params.at(qx, qy, 3);
                        band.mu_n = 0.5f * (std::log(band.f_low) + std::log(band.f_high));
                        band.sigma_n = 0.5f * s_f * (band.mu_n - std::log(band.f_low));
                        const float f = sample_band_frequency(band, u);
                        const float om = params.at(qx, qy, 1);
                        const float phase =
                            2.0f * kPi * f * (dx * std::cos(om) + dy * std::sin(om));
                        acc += amp * wgt * std::exp(-kPi * a * a * d2) * std::cos(phase);
                    }
                }
            }
            out.at(x, y) = acc * norm;
        }
    }
    return out;
}

}  // namespace fovea::vk::post
