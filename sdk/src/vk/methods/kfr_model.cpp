#include "kfr_model.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <string>

namespace fovea::vk::methods {
namespace {
constexpr double kTwoPi = 6.28318530717958647692;
}

KfrKernel KfrKernel::power(double alpha) {
    assert(alpha > 0.0 && "kernel exponent must be positive");
    KfrKernel k;
    k.alpha_ = alpha;
    return k;
}

Result<KfrKernel> KfrKernel::polynomial(std::vector<double> betas) {
    if (betas.size() < 2) return make_error("polynomial kernel needs at least β0 and β1");
    if (std::abs(betas[0]) > 1e-9) return make_error("polynomial kernel needs K(0) = 0 (β0 = 0)");
    double sum = 0.0;
    for (double b : betas) sum += b;
    if (std::abs(sum - 1.0) > 1e-6) return make_error("polynomial kernel needs Σβ = 1 (K(1) = 1)");
    // Strictly increasing on [0, 1] so the inverse exists: check K' > 0 on a fine grid.
    for (int i = 0; i <= 1024; ++i) {
        const double x = i / 1024.0;
        double d = 0.0;
        for (std::size_t j = 1; j < betas.size(); ++j)
            d += double(j) * betas[j] * std::pow(x, double(j - 1));
        if (d < 0.0 || (i > 0 && d == 0.0 && i < 1024))
            return make_error("polynomial kernel is not increasing on [0, 1] (K'(" +
                              std::to_string(x) + ") <= 0)");
    }
    KfrKernel k;
    k.betas_ = std::move(betas);
    return k;
}

double KfrKernel::eval(double x) const {
    x = std::clamp(x, 0.0, 1.0);
    if (betas_.empty()) return std::pow(x, alpha_);
    double y = 0.0;
    for (std::size_t i = betas_.size(); i-- > 0;) y = y * x + betas_[i];  // Horner
    return y;
}

double KfrKernel::inverse(double y) const {
    y = std::clamp(y, 0.0, 1.0);
    if (betas_.empty()) return std::pow(y, 1.0 / alpha_);
    // Monotone on [0, 1]: bisection is robust where K' vanishes at an end (e.g. K = x^3).
    double lo = 0.0;
    double hi = 1.0;
    for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (lo + hi);
        (eval(mid) < y ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

KfrKernel kfr_study_kernel(double alpha, bool literal) {
    return KfrKernel::power(literal ? alpha : 1.0 / alpha);
}

int kfr_buffer_extent(int screen_extent, double sigma) {
    assert(sigma >= 1.0 && "sigma below 1 would enlarge the buffer");
    return std::max(1, static_cast<int>(std::ceil(screen_extent / sigma)));
}

double kfr_log_max_radius(int screen_w, int screen_h, Vec2d g) {
    const double l1 = std::hypot(g.x, g.y);
    const double l2 = std::hypot(screen_w - g.x, screen_h - g.y);
    const double l3 = std::hypot(g.x, screen_h - g.y);
    const double l4 = std::hypot(screen_w - g.x, g.y);
    return std::log(std::max({l1, l2, l3, l4, 2.0}));
}

KfrMap::KfrMap(int screen_w, int screen_h, int buffer_w, int buffer_h, Vec2d gaze, KfrKernel kernel)
    : w_(buffer_w), h_(buffer_h), kernel_(std::move(kernel)) {
    assert(screen_w > 0 && screen_h > 0 && buffer_w > 0 && buffer_h > 0);
    // A gaze off screen (tracker noise, blink) is clamped: L stays the corner distance.
    gaze_.x = std::isfinite(gaze.x) ? std::clamp(gaze.x, 0.0, double(screen_w)) : screen_w * 0.5;
    gaze_.y = std::isfinite(gaze.y) ? std::clamp(gaze.y, 0.0, double(screen_h)) : screen_h * 0.5;
    L_ = kfr_log_max_radius(screen_w, screen_h, gaze_);
}

Vec2d KfrMap::forward(Vec2d p) const {
    const double dx = p.x - gaze_.x;
    const double dy = p.y - gaze_.y;
    const double r = std::hypot(dx, dy);
    // log r < 0 inside one pixel of the gaze: clamp so the centre maps to u = 0, not -inf.
    const double lr = std::log(std::max(r, 1.0)) / L_;
    Vec2d lp;
    lp.x = kernel_.inverse(lr) * w_;
    // atan2 is finite at (0, 0); the [y' < 0]·2π term of Eq. 10 maps (-π, 0) to (π, 2π).
    double a = std::atan2(dy, dx);
    if (a < 0.0) a += kTwoPi;
    lp.y = a * h_ / kTwoPi;
    if (lp.y >= h_) lp.y -= h_;  // a = 2π - ε rounding up
    return lp;
}

Vec2d KfrMap::inverse(Vec2d lp) const {
    const double r = std::exp(L_ * kernel_.eval(lp.x / w_));
    const double a = lp.y * kTwoPi / h_;
    return {gaze_.x + r * std::cos(a), gaze_.y + r * std::sin(a)};
}

double KfrMap::radial_scale(double u) const {
    // dr/du = r L K'(u/w) / w, by central difference on the kernel (works for both kernels).
    const double x = std::clamp(u / w_, 1e-4, 1.0 - 1e-4);
    const double dk = (kernel_.eval(x + 1e-4) - kernel_.eval(x - 1e-4)) / 2e-4;
    return std::exp(L_ * kernel_.eval(x)) * L_ * dk / w_;
}

}  // namespace fovea::vk::methods
