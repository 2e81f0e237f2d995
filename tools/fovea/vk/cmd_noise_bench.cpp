// `fovea noise-bench`: cost of Tariq 2022's Gabor-noise enhancement against impulses per kernel
// (12, 16, 32, 64; Tariq §6.3, Fig. 15) on the reference implementation
// (sdk/src/vk/post/enhance_model.cpp): parameter estimation and synthesis, median of --repeats
// runs on a blurred zone plate. Writes a CSV and a PNG plot (time against impulses).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>
#include <stb/stb_easy_font.h>

#include "command.hpp"
#include "post/enhance_model.hpp"

namespace fovea::cli {
namespace {

namespace post = fovea::vk::post;

struct NoiseBenchOptions {
    int size = 256;
    int repeats = 3;
    std::string csv = "noise_bench.csv";
    std::string png = "noise_bench.png";
};

struct Row {
    int impulses;
    double param_ms;
    double synth_ms;
};

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

// A plot with a white background: lines between points, axes, labels via stb_easy_font.
class Canvas {
public:
    Canvas(int w, int h) : w_(w), h_(h), px_(std::size_t(w) * h * 3, 255) {}
    void dot(int x, int y, const unsigned char* c) {
        if (x < 0 || y < 0 || x >= w_ || y >= h_) return;
        std::copy(c, c + 3, px_.begin() + (std::ptrdiff_t(y) * w_ + x) * 3);
    }
    void line(int x0, int y0, int x1, int y1, const unsigned char* c, int thick = 1) {
        const int n = std::max(std::abs(x1 - x0), std::abs(y1 - y0)) + 1;
        for (int i = 0; i <= n; ++i) {
            const int x = x0 + (x1 - x0) * i / n;
            const int y = y0 + (y1 - y0) * i / n;
            for (int t = -thick / 2; t <= thick / 2; ++t) {
                dot(x + t, y, c);
                dot(x, y + t, c);
            }
        }
    }
    void text(int x, int y, const std::string& s, const unsigned char* c) {
        static char buf[60000];
        const int quads = stb_easy_font_print(0, 0, const_cast<char*>(s.c_str()), nullptr, buf,
                                              sizeof(buf));
        const float* v = reinterpret_cast<const float*>(buf);
        for (int q = 0; q < quads; ++q) {  // 4 vertices of 16 bytes (x, y, z, colour)
            const float* a = v + q * 16;
            for (int yy = int(a[1]); yy < int(a[9]); ++yy)
                for (int xx = int(a[0]); xx < int(a[8]); ++xx) dot(x + xx, y + yy, c);
        }
    }
    bool write(const std::string& path) const {
        return stbi_write_png(path.c_str(), w_, h_, 3, px_.data(), w_ * 3) != 0;
    }

private:
    int w_, h_;
    std::vector<unsigned char> px_;
};

bool write_plot(const std::vector<Row>& rows, const std::string& path, int size) {
    const int w = 560, h = 380, left = 60, right = 20, top = 40, bottom = 50;
    Canvas c(w, h);
    const unsigned char black[3] = {0, 0, 0}, blue[3] = {30, 90, 200}, red[3] = {200, 50, 40},
                        green[3] = {40, 150, 60}, grey[3] = {210, 210, 210};
    double ymax = 0;
    for (const Row& r : rows) ymax = std::max(ymax, r.param_ms + r.synth_ms);
    ymax *= 1.1;
    auto X = [&](int imp) { return left + int((imp - 0) * double(w - left - right) / 68.0); };
    auto Y = [&](double ms) { return h - bottom - int(ms / ymax * (h - top - bottom)); };
    for (int k = 1; k <= 4; ++k) c.line(left, Y(ymax * k / 4.4), w - right, Y(ymax * k / 4.4), grey);
    c.line(left, h - bottom, w - right, h - bottom, black);
    c.line(left, top, left, h - bottom, black);
    for (const Row& r : rows) {
        c.line(X(r.impulses), h - bottom, X(r.impulses), h - bottom + 4, black);
        c.text(X(r.impulses) - 6, h - bottom + 8, std::to_string(r.impulses), black);
    }
    for (int k = 0; k <= 4; ++k) {
        char b[32];
        std::snprintf(b, sizeof b, "%.0f", ymax * k / 4.4);
        c.text(8, Y(ymax * k / 4.4) - 3, b, black);
    }
    auto series = [&](auto value, const unsigned char* col) {
        for (std::size_t i = 0; i + 1 < rows.size(); ++i)
            c.line(X(rows[i].impulses), Y(value(rows[i])), X(rows[i + 1].impulses),
                   Y(value(rows[i + 1])), col, 3);
    };
    series([](const Row& r) { return r.param_ms + r.synth_ms; }, black);
    series([](const Row& r) { return r.synth_ms; }, red);
    series([](const Row& r) { return r.param_ms; }, blue);
    c.text(left, 10, "Gabor noise (CPU reference), " + std::to_string(size) + "x" +
                         std::to_string(size) + ": ms vs impulses per kernel", black);
    c.text(left + 10, 24, "total", black);
    c.text(left + 60, 24, "synthesis", red);
    c.text(left + 140, 24, "parameter estimation", blue);
    c.text(w / 2 - 50, h - 18, "impulses per kernel", black);
    (void)green;
    return c.write(path);
}

int run(const NoiseBenchOptions& o) {
    const int n = o.size;
    // Blurred zone plate at 20° eccentricity, σ = 3 px, 40 px/deg: a non-empty noise band.
    post::Image luma(n, n, 1);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const float dx = float(x) - 0.5f * float(n), dy = float(y) - 0.5f * float(n);
            luma.at(x, y) = 0.5f + 0.3f * std::cos(3.14159265f * (dx * dx + dy * dy) / float(n));
        }
    luma = post::gaussian_pyramid(luma, 2)[0];
    const post::Image sigma(n, n, 1, 3.0f), ecc(n, n, 1, 20.0f);
    std::vector<Row> rows;
    using Clock = std::chrono::steady_clock;
    auto ms = [](Clock::time_point a, Clock::time_point b) {
        return std::chrono::duration<double, std::milli>(b - a).count();
    };
    std::printf("%-10s %12s %12s %12s\n", "impulses", "param_ms", "synth_ms", "total_ms");
    for (int impulses : {12, 16, 32, 64}) {
        post::NoiseParams p;
        p.impulses_per_kernel = impulses;
        std::vector<double> tp, ts;
        double checksum = 0;
        for (int r = 0; r < std::max(1, o.repeats); ++r) {
            const auto t0 = Clock::now();
            const post::Image params = post::noise_parameters({&luma, &sigma, &ecc}, p);
            const auto t1 = Clock::now();
            const post::Image noise = post::synthesize_gabor_noise(params, p);
            const auto t2 = Clock::now();
            tp.push_back(ms(t0, t1));
            ts.push_back(ms(t1, t2));
            checksum += noise.data[std::size_t(n) * n / 2];
        }
        rows.push_back({impulses, median(tp), median(ts)});
        std::printf("%-10d %12.2f %12.2f %12.2f   (checksum %.4g)\n", impulses, rows.back().param_ms,
                    rows.back().synth_ms, rows.back().param_ms + rows.back().synth_ms, checksum);
    }
    std::ofstream csv(o.csv);
    if (!csv) {
        std::fprintf(stderr, "noise-bench: cannot write %s\n", o.csv.c_str());
        return 1;
    }
    csv << "impulses_per_kernel,impulses_per_cell,param_ms,synth_ms,total_ms,size\n";
    for (const Row& r : rows)
        csv << r.impulses << ',' << post::impulses_per_cell(r.impulses) << ',' << r.param_ms << ','
            << r.synth_ms << ',' << r.param_ms + r.synth_ms << ',' << n << '\n';
    if (!write_plot(rows, o.png, n)) {
        std::fprintf(stderr, "noise-bench: cannot write %s\n", o.png.c_str());
        return 1;
    }
    std::printf("wrote %s and %s\n", o.csv.c_str(), o.png.c_str());
    return 0;
}

void setup(CLI::App& app) {
    auto o = std::make_shared<NoiseBenchOptions>();
    app.add_option("--size", o->size, "Image edge in pixels")->check(CLI::Range(16, 4096));
    app.add_option("--repeats", o->repeats, "Runs per setting (median reported)")
        ->check(CLI::Range(1, 100));
    app.add_option("--csv", o->csv, "CSV output path");
    app.add_option("--png", o->png, "PNG plot output path");
    app.callback([o] {
        if (const int rc = run(*o); rc != 0) throw CLI::RuntimeError(rc);
    });
}

const Command kNoiseBench{"noise-bench",
                          "Gabor-noise enhancement cost against impulses per kernel (CSV + PNG)",
                          &setup};

}  // namespace
}  // namespace fovea::cli
