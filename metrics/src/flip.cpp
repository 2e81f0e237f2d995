#include "fovea/metrics/flip.hpp"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <limits>

#include "flip_filters.hpp"

namespace fovea::metrics {
namespace detail {
namespace {

using std::numbers::pi;

// The paper's Table 1 / Eq. 2: contrast sensitivity of each opponent channel as one or two
// Gaussians a * sqrt(pi / b) * exp(-pi^2 x^2 / b), x in degrees.
struct Csf {
    double a1, b1, a2, b2;
};
constexpr Csf kAchromatic{1.0, 0.0047, 0.0, 1e-5};
constexpr Csf kRedGreen{1.0, 0.0053, 0.0, 1e-5};
constexpr Csf kBlueYellow{34.1, 0.04, 13.5, 0.025};
constexpr double kWidestB = 0.04;  // the widest Gaussian decides the colour kernels' radius
constexpr double kFeatureWidthDeg = 0.082;  // peak to trough of the edge detector (2 sd)

// Linear sRGB -> CIE XYZ (D65), the exact rationals of the sRGB primaries.
constexpr Mat3 kRgbToXyz = {{{10135552.0 / 24577794, 8788810.0 / 24577794, 4435075.0 / 24577794},
                             {2613072.0 / 12288897, 8788810.0 / 12288897, 887015.0 / 12288897},
                             {1425312.0 / 73733382, 8788810.0 / 73733382, 70074185.0 / 73733382}}};

Vec3 mul(const Mat3& m, const Vec3& v) {
    return {m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
            m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
            m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2]};
}

Mat3 inverse(const Mat3& m) {
    const double c00 = m[1][1] * m[2][2] - m[1][2] * m[2][1];
    const double c01 = m[1][2] * m[2][0] - m[1][0] * m[2][2];
    const double c02 = m[1][0] * m[2][1] - m[1][1] * m[2][0];
    const double det = m[0][0] * c00 + m[0][1] * c01 + m[0][2] * c02;
    return {{{c00 / det, (m[0][2] * m[2][1] - m[0][1] * m[2][2]) / det,
              (m[0][1] * m[1][2] - m[0][2] * m[1][1]) / det},
             {c01 / det, (m[0][0] * m[2][2] - m[0][2] * m[2][0]) / det,
              (m[0][2] * m[1][0] - m[0][0] * m[1][2]) / det},
             {c02 / det, (m[0][1] * m[2][0] - m[0][0] * m[2][1]) / det,
              (m[0][0] * m[1][1] - m[0][1] * m[1][0]) / det}}};
}

}  // namespace

const Mat3& rgb_to_xyz() { return kRgbToXyz; }

const Mat3& xyz_to_rgb() {
    static const Mat3 m = inverse(kRgbToXyz);
    return m;
}

const Vec3& white() {
    static const Vec3 w = mul(kRgbToXyz, {1.0, 1.0, 1.0});
    return w;
}

double srgb_to_linear(double v) {
    return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

namespace {

// YCxCz (Johnson & Fairchild's linearised L*a*b*): Y' = 116 y - 16, Cx = 500 (x - y),
// Cz = 200 (y - z) on white-normalised XYZ.
Vec3 linear_rgb_to_ycxcz(const Vec3& rgb) {
    const Vec3 xyz = mul(kRgbToXyz, rgb);
    const Vec3& w = white();
    const double x = xyz[0] / w[0], y = xyz[1] / w[1], z = xyz[2] / w[2];
    return {116.0 * y - 16.0, 500.0 * (x - y), 200.0 * (y - z)};
}

Vec3 ycxcz_to_linear_rgb(const Vec3& o) {
    const double y = (o[0] + 16.0) / 116.0;
    const Vec3& w = white();
    return mul(xyz_to_rgb(), {(y + o[1] / 500.0) * w[0], y * w[1], (y - o[2] / 200.0) * w[2]});
}

// CIE L*a*b* of linear RGB, then Hunt's adjustment: chroma scaled by 0.01 L*.
Vec3 linear_rgb_to_hunt_lab(const Vec3& rgb) {
    const Vec3 xyz = mul(kRgbToXyz, rgb);
    const Vec3& w = white();
    constexpr double d = 6.0 / 29.0;
    const auto f = [](double t) {
        return t > d * d * d ? std::cbrt(t) : t / (3.0 * d * d) + 4.0 / 29.0;
    };
    const double fx = f(xyz[0] / w[0]), fy = f(xyz[1] / w[1]), fz = f(xyz[2] / w[2]);
    const double l = 116.0 * fy - 16.0;
    return {l, 0.01 * l * 500.0 * (fx - fy), 0.01 * l * 200.0 * (fy - fz)};
}

double hyab(const Vec3& p, const Vec3& q) {
    return std::fabs(p[0] - q[0]) + std::hypot(p[1] - q[1], p[2] - q[2]);
}

}  // namespace

double cmax() {
    static const double c = std::pow(
        hyab(linear_rgb_to_hunt_lab({0.0, 1.0, 0.0}), linear_rgb_to_hunt_lab({0.0, 0.0, 1.0})),
        kQc);
    return c;
}

namespace {

// Eq. 5: differences up to pc * cmax map linearly to [0, pt], the rest to (pt, 1].
double redistribute(double e) {
    const double c = cmax(), knee = kPc * c;
    return e < knee ? e * kPt / knee : kPt + (e - knee) / (c - knee) * (1.0 - kPt);
}

}  // namespace

AxisFilters make_axis_filters(double ppd) {
    AxisFilters f;
    f.colour_radius = flip_colour_radius(ppd);
    f.feature_radius = flip_feature_radius(ppd);
    const int rc = f.colour_radius, rf = f.feature_radius;
    const double dx = 1.0 / ppd;
    const auto gauss = [&](int i, double b) {
        return std::exp(-pi * pi * (i * dx) * (i * dx) / b);
    };
    double sy = 0, scx = 0;
    for (int i = -rc; i <= rc; ++i) {
        f.y.push_back(gauss(i, kAchromatic.b1));
        f.cx.push_back(gauss(i, kRedGreen.b1));
        f.cz1.push_back(std::sqrt(kBlueYellow.a1 * std::sqrt(pi / kBlueYellow.b1)) *
                        gauss(i, kBlueYellow.b1));
        f.cz2.push_back(std::sqrt(kBlueYellow.a2 * std::sqrt(pi / kBlueYellow.b2)) *
                        gauss(i, kBlueYellow.b2));
        sy += f.y.back();
        scx += f.cx.back();
        f.cz1_sum += f.cz1.back();
        f.cz2_sum += f.cz2.back();
    }
    for (auto& v : f.y) v /= sy;
    for (auto& v : f.cx) v /= scx;
    const double sd = 0.5 * kFeatureWidthDeg * ppd;
    double sg = 0, dg_pos = 0, dg_neg = 0, ddg_pos = 0, ddg_neg = 0;
    for (int i = -rf; i <= rf; ++i) {
        const double g = std::exp(-double(i) * i / (2.0 * sd * sd));
        const double dg = -i * g, ddg = (double(i) * i / (sd * sd) - 1.0) * g;
        f.g.push_back(g);
        f.dg.push_back(dg);
        f.ddg.push_back(ddg);
        sg += g;
        (dg > 0 ? dg_pos : dg_neg) += std::fabs(dg);
        (ddg > 0 ? ddg_pos : ddg_neg) += std::fabs(ddg);
    }
    // A sum that underflowed to 0 (sub-pixel sd at absurdly low ppd) leaves its weights at 0.
    const auto norm = [](double v, double pos, double neg) {
        const double s = v > 0 ? pos : neg;
        return s > 0 ? v / s : 0.0;
    };
    for (size_t i = 0; i < f.g.size(); ++i) {
        f.g[i] /= sg;
        f.dg[i] = norm(f.dg[i], dg_pos, dg_neg);
        f.ddg[i] = norm(f.ddg[i], ddg_pos, ddg_neg);
    }
    return f;
}

namespace {

// One set of filters per distinct ppd value of a field (uniform fields: one).
class FilterBank {
public:
    explicit FilterBank(const std::vector<double>& ppd) {
        index_.resize(ppd.size());
        for (size_t i = 0; i < ppd.size(); ++i) {
            if (i == 0 || ppd[i] != ppd[i - 1]) {
                const auto it = std::find(values_.begin(), values_.end(), ppd[i]);
                if (it == values_.end()) {
                    values_.push_back(ppd[i]);
                    filters_.push_back(make_axis_filters(ppd[i]));
                }
            }
            index_[i] = std::find(values_.begin(), values_.end(), ppd[i]) - values_.begin();
        }
    }
    const AxisFilters& at(size_t i) const { return filters_[index_[i]]; }

private:
    std::vector<double> values_;
    std::vector<AxisFilters> filters_;
    std::vector<size_t> index_;
};

struct Opponent {
    std::vector<double> y, cx, cz;  // YCxCz per pixel
};

template <typename Fetch>
Opponent to_opponent(uint32_t w, uint32_t h, Fetch fetch) {
    Opponent o;
    const size_t n = size_t(w) * h;
    o.y.resize(n);
    o.cx.resize(n);
    o.cz.resize(n);
    for (size_t i = 0; i < n; ++i) {
        Vec3 rgb;
        for (int c = 0; c < 3; ++c) rgb[c] = srgb_to_linear(std::clamp(fetch(i, c), 0.0, 1.0));
        const Vec3 v = linear_rgb_to_ycxcz(rgb);
        o.y[i] = v[0];
        o.cx[i] = v[1];
        o.cz[i] = v[2];
    }
    return o;
}

// Both pipelines' separable filtering, then the per-pixel colour transform and feature magnitudes.
std::vector<FlipReference::Filtered> filter(const Opponent& o, uint32_t w, uint32_t h,
                                            const PpdField& ppd) {
    assert(ppd.x.size() == w && ppd.y.size() == h);
    const FilterBank columns(ppd.x), rows(ppd.y);
    constexpr int kH = 7;  // y, cx, cz1, cz2 (colour); g, dg, ddg of the achromatic y (features)
    std::vector<float> horiz(size_t(w) * h * kH);
    for (uint32_t y = 0; y < h; ++y) {
        const size_t row = size_t(y) * w;
        for (uint32_t x = 0; x < w; ++x) {
            const AxisFilters& f = columns.at(x);
            double acc[kH] = {};
            const auto at = [&](int dx) { return row + std::clamp(int(x) + dx, 0, int(w) - 1); };
            for (int i = -f.colour_radius; i <= f.colour_radius; ++i) {
                const size_t p = at(i), k = i + f.colour_radius;
                acc[0] += f.y[k] * o.y[p];
                acc[1] += f.cx[k] * o.cx[p];
                acc[2] += f.cz1[k] * o.cz[p];
                acc[3] += f.cz2[k] * o.cz[p];
            }
            for (int i = -f.feature_radius; i <= f.feature_radius; ++i) {
                const size_t p = at(i), k = i + f.feature_radius;
                const double a = (o.y[p] + 16.0) / 116.0;  // the erratum's division by 116
                acc[4] += f.g[k] * a;
                acc[5] += f.dg[k] * a;
                acc[6] += f.ddg[k] * a;
            }
            for (int c = 0; c < kH; ++c) horiz[(row + x) * kH + c] = float(acc[c]);
        }
    }
    std::vector<FlipReference::Filtered> out(size_t(w) * h);
    for (uint32_t y = 0; y < h; ++y) {
        const AxisFilters& f = rows.at(y);
        for (uint32_t x = 0; x < w; ++x) {
            const AxisFilters& fx = columns.at(x);
            const auto at = [&](int dy) {
                return (size_t(std::clamp(int(y) + dy, 0, int(h) - 1)) * w + x) * kH;
            };
            double yy = 0, cx = 0, cz = 0;
            for (int j = -f.colour_radius; j <= f.colour_radius; ++j) {
                const size_t p = at(j), k = j + f.colour_radius;
                yy += f.y[k] * horiz[p + 0];
                cx += f.cx[k] * horiz[p + 1];
                cz += f.cz1[k] * horiz[p + 2] + f.cz2[k] * horiz[p + 3];
            }
            cz /= fx.cz1_sum * f.cz1_sum + fx.cz2_sum * f.cz2_sum;
            double dx = 0, ddx = 0, dy = 0, ddy = 0;
            for (int j = -f.feature_radius; j <= f.feature_radius; ++j) {
                const size_t p = at(j), k = j + f.feature_radius;
                dx += f.g[k] * horiz[p + 5];
                ddx += f.g[k] * horiz[p + 6];
                dy += f.dg[k] * horiz[p + 4];
                ddy += f.ddg[k] * horiz[p + 4];
            }
            Vec3 rgb = ycxcz_to_linear_rgb({yy, cx, cz});
            for (double& c : rgb) c = std::clamp(c, 0.0, 1.0);
            const Vec3 lab = linear_rgb_to_hunt_lab(rgb);
            out[size_t(y) * w + x] = {lab[0], lab[1], lab[2], std::hypot(dx, dy),
                                      std::hypot(ddx, ddy)};
        }
    }
    return out;
}

Opponent opponent(const RgbFloatView& v) {
    assert(v.rgb.size() >= size_t(v.width) * v.height * 3);
    return to_opponent(v.width, v.height,
                       [&](size_t i, int c) { return double(v.rgb[3 * i + c]); });
}

Opponent opponent(const Rgb8View& v) {
    assert(v.rgb.size() >= size_t(v.width) * v.height * 3);
    return to_opponent(v.width, v.height,
                       [&](size_t i, int c) { return v.rgb[3 * i + c] / 255.0; });
}

float flip_value(const FlipReference::Filtered& r, const FlipReference::Filtered& t) {
    const double colour = redistribute(std::pow(hyab({r.l, r.a, r.b}, {t.l, t.a, t.b}), kQc));
    const double feature = std::pow(
        std::max(std::fabs(r.edge - t.edge), std::fabs(r.point - t.point)) / std::sqrt(2.0), kQf);
    return float(std::pow(colour, 1.0 - feature));
}

}  // namespace
}  // namespace detail

using namespace detail;

PpdField PpdField::uniform(uint32_t width, uint32_t height, double ppd) {
    return {std::vector<double>(width, ppd), std::vector<double>(height, ppd)};
}

double PpdField::max() const {
    double m = 0;
    for (double v : x) m = std::max(m, v);
    for (double v : y) m = std::max(m, v);
    return m;
}

int flip_colour_radius(double ppd) {
    return int(std::ceil(3.0 * std::sqrt(kWidestB / (2.0 * pi * pi)) * ppd));
}

int flip_feature_radius(double ppd) { return int(std::ceil(3.0 * 0.5 * kFeatureWidthDeg * ppd)); }

FlipReference::FlipReference(const RgbFloatView& reference, PpdField ppd)
    : width_(reference.width), height_(reference.height), ppd_(std::move(ppd)) {
    filtered_ = filter(opponent(reference), width_, height_, ppd_);
}

FlipReference::FlipReference(const Rgb8View& reference, PpdField ppd)
    : width_(reference.width), height_(reference.height), ppd_(std::move(ppd)) {
    filtered_ = filter(opponent(reference), width_, height_, ppd_);
}

namespace {

std::vector<float> compare_filtered(const std::vector<FlipReference::Filtered>& r,
                                    const std::vector<FlipReference::Filtered>& t) {
    std::vector<float> map(r.size());
    for (size_t i = 0; i < r.size(); ++i) map[i] = flip_value(r[i], t[i]);
    return map;
}

}  // namespace

std::vector<float> FlipReference::compare(const RgbFloatView& test) const {
    assert(test.width == width_ && test.height == height_);
    return compare_filtered(filtered_, filter(opponent(test), width_, height_, ppd_));
}

std::vector<float> FlipReference::compare(const Rgb8View& test) const {
    assert(test.width == width_ && test.height == height_);
    return compare_filtered(filtered_, filter(opponent(test), width_, height_, ppd_));
}

std::vector<float> flip_map(const Rgb8View& reference, const Rgb8View& test, const PpdField& ppd) {
    return FlipReference(reference, ppd).compare(test);
}

double weighted_percentile(std::span<const float> map, double percent) {
    std::vector<double> s;
    s.reserve(map.size());
    for (float v : map)
        if (std::isfinite(v)) s.push_back(v);
    if (s.empty()) return std::numeric_limits<double>::quiet_NaN();
    std::sort(s.begin(), s.end());
    double total = 0;
    for (double v : s) total += v;
    const double target = total * percent / 100.0;
    double running = 0;
    size_t i = 0;
    for (; i < s.size(); ++i) {
        running += s[i];
        if (running >= target) break;
    }
    i = std::min(i, s.size() - 1);
    return 0.5 * (s[i] + s[std::min(i + 1, s.size() - 1)]);
}

FlipPooled pool_flip(std::span<const float> map) {
    FlipPooled p;
    constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
    double sum = 0, lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (float v : map) {
        if (!std::isfinite(v)) continue;
        sum += v;
        lo = std::min(lo, double(v));
        hi = std::max(hi, double(v));
        ++p.pixels;
    }
    if (p.pixels == 0) return {kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, 0};
    p.mean = sum / double(p.pixels);
    p.min = lo;
    p.max = hi;
    p.weighted_median = weighted_percentile(map, 50.0);
    p.weighted_quartile1 = weighted_percentile(map, 25.0);
    p.weighted_quartile3 = weighted_percentile(map, 75.0);
    return p;
}

}  // namespace fovea::metrics
