#include "fovea/record/plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#include <stb/stb_easy_font.h>
#include <stb/stb_image_write.h>

namespace fovea::record {

Canvas::Canvas(int width, int height, Rgb bg)
    : w_(width), h_(height), px_(static_cast<std::size_t>(width * height * 3)) {
    for (std::size_t i = 0; i < px_.size(); i += 3) {
        px_[i] = bg.r;
        px_[i + 1] = bg.g;
        px_[i + 2] = bg.b;
    }
}

void Canvas::pixel(int x, int y, Rgb c) {
    if (x < 0 || y < 0 || x >= w_ || y >= h_) return;
    uint8_t* p = &px_[static_cast<std::size_t>((y * w_ + x) * 3)];
    p[0] = c.r;
    p[1] = c.g;
    p[2] = c.b;
}

void Canvas::rect(int x0, int y0, int x1, int y1, Rgb c) {
    if (x0 > x1) std::swap(x0, x1);
    if (y0 > y1) std::swap(y0, y1);
    x0 = std::max(x0, 0);
    y0 = std::max(y0, 0);
    x1 = std::min(x1, w_ - 1);
    y1 = std::min(y1, h_ - 1);
    for (int y = y0; y <= y1; ++y) {
        for (int x = x0; x <= x1; ++x) pixel(x, y, c);
    }
}

void Canvas::line(double x0, double y0, double x1, double y1, Rgb c, int thickness) {
    if (!std::isfinite(x0) || !std::isfinite(y0) || !std::isfinite(x1) || !std::isfinite(y1))
        return;
    const double len = std::max(std::abs(x1 - x0), std::abs(y1 - y0));
    const int steps = std::min(100000, static_cast<int>(std::ceil(len)) + 1);
    const int r0 = -(thickness - 1) / 2, r1 = thickness / 2;
    for (int i = 0; i <= steps; ++i) {
        const double t = steps ? static_cast<double>(i) / steps : 0.0;
        const int x = static_cast<int>(std::lround(x0 + (x1 - x0) * t));
        const int y = static_cast<int>(std::lround(y0 + (y1 - y0) * t));
        for (int dy = r0; dy <= r1; ++dy) {
            for (int dx = r0; dx <= r1; ++dx) pixel(x + dx, y + dy, c);
        }
    }
}

void Canvas::dot(double x, double y, int radius, Rgb c) {
    if (!std::isfinite(x) || !std::isfinite(y)) return;
    const int cx = static_cast<int>(std::lround(x)), cy = static_cast<int>(std::lround(y));
    for (int dy = -radius; dy <= radius; ++dy) {
        for (int dx = -radius; dx <= radius; ++dx) {
            if (dx * dx + dy * dy <= radius * radius) pixel(cx + dx, cy + dy, c);
        }
    }
}

int Canvas::text_width(const std::string& s, int scale) {
    return stb_easy_font_width(const_cast<char*>(s.c_str())) * scale;
}

int Canvas::text(int x, int y, const std::string& s, Rgb c, int scale) {
    static char buf[200000];
    const int quads =
        stb_easy_font_print(0, 0, const_cast<char*>(s.c_str()), nullptr, buf, sizeof buf);
    // each quad: 4 vertices of (x, y, z floats + rgba bytes) = 16 bytes; axis-aligned
    for (int q = 0; q < quads; ++q) {
        const float* v0 = reinterpret_cast<const float*>(buf + q * 64);
        const float* v2 = reinterpret_cast<const float*>(buf + q * 64 + 32);
        const int qx0 = x + static_cast<int>(v0[0] * static_cast<float>(scale));
        const int qy0 = y + static_cast<int>(v0[1] * static_cast<float>(scale));
        const int qx1 = x + static_cast<int>(v2[0] * static_cast<float>(scale)) - 1;
        const int qy1 = y + static_cast<int>(v2[1] * static_cast<float>(scale)) - 1;
        rect(qx0, qy0, qx1, qy1, c);
    }
    return text_width(s, scale);
}

Result<void> Canvas::save_png(const std::string& path) const {
    if (!stbi_write_png(path.c_str(), w_, h_, 3, px_.data(), w_ * 3)) {
        return make_error("cannot write PNG " + path);
    }
    return {};
}

std::vector<double> nice_ticks(double lo, double hi, int target) {
    std::vector<double> t;
    if (!(hi > lo) || !std::isfinite(lo) || !std::isfinite(hi)) return t;
    const double raw = (hi - lo) / std::max(1, target);
    const double mag = std::pow(10.0, std::floor(std::log10(raw)));
    double step = mag;
    for (double m : {1.0, 2.0, 5.0, 10.0}) {
        step = m * mag;
        if (step >= raw) break;
    }
    for (double v = std::ceil(lo / step) * step; v <= hi + step * 1e-9; v += step) {
        t.push_back(std::abs(v) < step * 1e-9 ? 0.0 : v);
    }
    return t;
}

namespace {
const Rgb kAxis{40, 40, 40};
const Rgb kGrid{228, 228, 228};

std::string fmt_tick(double v) {
    char b[32];
    if (v != 0 && (std::abs(v) >= 1e5 || std::abs(v) < 1e-3)) {
        std::snprintf(b, sizeof b, "%.0e", v);
    } else {
        std::snprintf(b, sizeof b, "%g", v);
    }
    return b;
}
}  // namespace

Plot::Plot(int width, int height, std::string title, std::string xlabel, std::string ylabel)
    : canvas_(width, height),
      title_(std::move(title)),
      xlabel_(std::move(xlabel)),
      ylabel_(std::move(ylabel)) {}

void Plot::set_x(double lo, double hi, bool log) {
    x0_ = lo;
    x1_ = hi > lo ? hi : lo + 1;
    xlog_ = log;
}
void Plot::set_y(double lo, double hi, bool log) {
    y0_ = lo;
    y1_ = hi > lo ? hi : lo + 1;
    ylog_ = log;
}

// A position far off the canvas (0 on a log axis is -inf) or undefined (NaN) becomes a finite
// one off the canvas, so that every later cast to int is defined.
static double off_canvas_if_not_finite(double p) {
    return std::isnan(p) ? -1e6 : std::clamp(p, -1e6, 1e6);
}
double Plot::px(double x) const {
    const double a = xlog_ ? std::log10(x0_) : x0_, b = xlog_ ? std::log10(x1_) : x1_;
    const double v = xlog_ ? std::log10(x) : x;
    return off_canvas_if_not_finite(left_ + (v - a) / (b - a) * (canvas_.width() - left_ - right_));
}
double Plot::py(double y) const {
    const double a = ylog_ ? std::log10(y0_) : y0_, b = ylog_ ? std::log10(y1_) : y1_;
    const double v = ylog_ ? std::log10(y) : y;
    return off_canvas_if_not_finite(canvas_.height() - bottom_ -
                                    (v - a) / (b - a) * (canvas_.height() - top_ - bottom_));
}

void Plot::line(const std::vector<double>& xs, const std::vector<double>& ys, Rgb c,
                int thickness) {
    for (std::size_t i = 1; i < xs.size() && i < ys.size(); ++i) {
        canvas_.line(px(xs[i - 1]), py(ys[i - 1]), px(xs[i]), py(ys[i]), c, thickness);
    }
}
void Plot::points(const std::vector<double>& xs, const std::vector<double>& ys, Rgb c, int radius) {
    for (std::size_t i = 0; i < xs.size() && i < ys.size(); ++i)
        canvas_.dot(px(xs[i]), py(ys[i]), radius, c);
}
void Plot::bars(const std::vector<double>& lo, const std::vector<double>& hi,
                const std::vector<double>& ys, Rgb c) {
    const double base = ylog_ ? y0_ : std::max(0.0, y0_);
    for (std::size_t i = 0; i < ys.size(); ++i) {
        if (!(ys[i] > base)) continue;
        canvas_.rect(static_cast<int>(px(lo[i])), static_cast<int>(py(ys[i])),
                     std::max(static_cast<int>(px(lo[i])), static_cast<int>(px(hi[i])) - 1),
                     static_cast<int>(py(base)), c);
    }
}
void Plot::xspan(double a, double b, Rgb c) {
    canvas_.rect(static_cast<int>(px(a)), top_, static_cast<int>(px(b)), canvas_.height() - bottom_,
                 c);
}
void Plot::vline(double x, Rgb c, const std::string& label) {
    const double X = px(x);
    canvas_.line(X, top_, X, canvas_.height() - bottom_, c, 1);
    if (label.empty()) return;
    // stagger labels downwards; flip to the left of the line near the right edge
    const int w = Canvas::text_width(label);
    const int tx = X + 3 + w > canvas_.width() - right_ ? static_cast<int>(X) - 3 - w
                                                        : static_cast<int>(X) + 3;
    canvas_.text(tx, top_ + 2 + 12 * (vlines_++ % 4), label, c);
}
void Plot::legend(const std::string& label, Rgb c) { legend_.emplace_back(label, c); }

Canvas& Plot::finish() {
    const int W = canvas_.width(), H = canvas_.height();
    // margins cleared so data never covers the labels
    canvas_.rect(0, 0, W - 1, top_ - 1, {255, 255, 255});
    canvas_.rect(0, H - bottom_ + 1, W - 1, H - 1, {255, 255, 255});
    canvas_.rect(0, 0, left_ - 1, H - 1, {255, 255, 255});
    canvas_.rect(W - right_ + 1, 0, W - 1, H - 1, {255, 255, 255});
    auto ticks = [](double lo, double hi, bool log) {
        if (!log) return nice_ticks(lo, hi);
        std::vector<double> t;
        for (double d = std::pow(10.0, std::floor(std::log10(lo))); d <= hi * 1.0001; d *= 10) {
            for (double m : {1.0, 2.0, 5.0}) {
                if (m * d >= lo * 0.9999 && m * d <= hi * 1.0001) t.push_back(m * d);
            }
        }
        return t;
    };
    for (double t : ticks(x0_, x1_, xlog_)) {
        const int X = static_cast<int>(px(t));
        for (int y = top_; y < H - bottom_; y += 3) canvas_.pixel(X, y, kGrid);
        canvas_.line(X, H - bottom_, X, H - bottom_ + 4, kAxis);
        const std::string s = fmt_tick(t);
        canvas_.text(X - Canvas::text_width(s) / 2, H - bottom_ + 7, s, kAxis);
    }
    for (double t : ticks(y0_, y1_, ylog_)) {
        const int Y = static_cast<int>(py(t));
        for (int x = left_; x < W - right_; x += 3) canvas_.pixel(x, Y, kGrid);
        canvas_.line(left_ - 4, Y, left_, Y, kAxis);
        const std::string s = fmt_tick(t);
        canvas_.text(left_ - 7 - Canvas::text_width(s), Y - 3, s, kAxis);
    }
    canvas_.line(left_, top_, left_, H - bottom_, kAxis);
    canvas_.line(left_, H - bottom_, W - right_, H - bottom_, kAxis);
    canvas_.text(left_, 6, title_, {0, 0, 0}, 2);
    canvas_.text(left_ + (W - left_ - right_ - Canvas::text_width(xlabel_)) / 2, H - 18, xlabel_,
                 kAxis);
    canvas_.text(4, top_ - 12, ylabel_, kAxis);
    int lx = W - right_ - 6;
    for (auto it = legend_.rbegin(); it != legend_.rend(); ++it) {
        lx -= Canvas::text_width(it->first) + 20;
        canvas_.rect(lx, 25, lx + 9, 33, it->second);  // a row of its own under the title
        canvas_.text(lx + 13, 26, it->first, kAxis);
    }
    return canvas_;
}

}  // namespace fovea::record
