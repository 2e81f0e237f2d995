// `fovea gaze-sweep LUND_DIR [--out PREFIX] [--seconds S]`: run time and lag against error for
// the gaze chain's knobs, written as PREFIX.csv and PREFIX.png.
//   filter rows: 1€ (mincutoff, beta) and Kalman (acceleration noise) on the simulated tracker:
//                residual jitter (deg RMS sample-to-sample in fixation) vs pursuit lag (ms),
//                ns/sample;
//   detector rows: online look-ahead (ms) vs mean kappa (fixation, saccade, PSO; both coders) on
//                LUND_DIR, ns/sample.
// The PNG has two panels: left jitter (y) vs lag (x), 1€ blue / Kalman red; right mean kappa (y)
// vs look-ahead (x). Axes start at 0 (kappa axis: at the lowest value - 0.02); the CSV holds
// the numbers.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

// Static: other objects linked into `fovea` (fovea_record, vk tools) carry their own copy.
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include <stb/stb_image_write.h>
#pragma GCC diagnostic pop

#include "command.hpp"
#include "fovea/eval/dataset.hpp"
#include "fovea/eval/detect.hpp"
#include "fovea/eval/scoring.hpp"
#include "fovea/gaze/pipeline.hpp"
#include "sim/sim_tracker.hpp"

namespace fovea::cli {
namespace {

struct Options {
    std::string dir;
    std::string out = "gaze_sweep";
    double seconds = 60.0;
};

struct Row {
    std::string kind, params;
    double x = 0, y = 0, ns = 0;  // filter: lag ms, jitter deg; detector: look-ahead ms, kappa
};

using Clock = std::chrono::steady_clock;

Row filter_row(const std::vector<drivers::sim::SimTracker::Frame>& frames, double rate,
               gaze::FilterKind kind, const gaze::OneEuroParams& oe, const gaze::KalmanParams& kf,
               const std::string& params, double raw_lag) {
    gaze::OneEuroFilter ox(oe), oy(oe);
    gaze::KalmanCv kx(kf), ky(kf);
    gaze::DisplayGeometry d;
    double jit = 0, lag = 0, px = NAN, py = NAN, ptx = NAN, pty = NAN;
    size_t nj = 0, nl = 0;
    const auto t0 = Clock::now();
    for (const auto& f : frames) {
        if (!f.raw.left.valid) {
            px = NAN;
            continue;
        }
        double gx, gy;
        d.to_degrees(f.raw.left.x, f.raw.left.y, gx, gy);
        const double t = static_cast<double>(f.t_true_ns) * 1e-9;
        if (kind == gaze::FilterKind::kOneEuro) {
            gx = ox.filter(gx, t);
            gy = oy.filter(gy, t);
        } else if (kind == gaze::FilterKind::kKalman) {
            gx = kx.filter(gx, t);
            gy = ky.filter(gy, t);
        }
        if (f.truth.event == gaze::Event::kFixation && std::isfinite(px)) {
            jit += (gx - px) * (gx - px) + (gy - py) * (gy - py);
            ++nj;
        } else if (f.truth.event == gaze::Event::kPursuit && std::isfinite(ptx)) {
            const double vx = (f.truth.x_deg - ptx) * rate, vy = (f.truth.y_deg - pty) * rate;
            const double v2 = vx * vx + vy * vy;
            if (v2 > 1.0) {
                lag += ((f.truth.x_deg - gx) * vx + (f.truth.y_deg - gy) * vy) / v2;
                ++nl;
            }
        }
        px = gx;
        py = gy;
        ptx = f.truth.x_deg;
        pty = f.truth.y_deg;
    }
    const double ns =
        std::chrono::duration<double, std::nano>(Clock::now() - t0).count() / frames.size();
    Row r;
    r.kind = kind == gaze::FilterKind::kOneEuro  ? "oneeuro"
             : kind == gaze::FilterKind::kKalman ? "kalman"
                                                 : "raw";
    r.params = params;
    r.x = 1e3 * lag / std::max<size_t>(1, nl) - raw_lag;
    r.y = std::sqrt(jit / std::max<size_t>(1, nj));
    r.ns = ns;
    return r;
}

void plot(const std::vector<Row>& rows, const std::string& path) {
    constexpr int kW = 900, kH = 420, kPanel = 430, kPad = 30;
    std::vector<unsigned char> img(kW * kH * 3, 255);
    auto px = [&](int x, int y, unsigned char r, unsigned char g, unsigned char b) {
        if (x < 0 || y < 0 || x >= kW || y >= kH) return;
        unsigned char* p = &img[(static_cast<size_t>(y) * kW + x) * 3];
        p[0] = r;
        p[1] = g;
        p[2] = b;
    };
    auto panel = [&](int ox, bool filters) {
        double xmax = 1e-9, ymax = 1e-9, ymin = filters ? 0.0 : 1e9;
        for (const auto& r : rows) {
            if ((r.kind == "detector") == filters) continue;
            xmax = std::max(xmax, r.x);
            ymax = std::max(ymax, r.y);
            if (!filters) ymin = std::min(ymin, r.y - 0.02);
        }
        if (ymax <= ymin) ymax = ymin + 1e-3;
        const int x0 = ox + kPad, y0 = kH - kPad, w = kPanel - 2 * kPad, h = kH - 2 * kPad;
        for (int i = 0; i <= w; ++i) px(x0 + i, y0, 0, 0, 0);
        for (int i = 0; i <= h; ++i) px(x0, y0 - i, 0, 0, 0);
        for (int t = 1; t <= 4; ++t) {  // quarter ticks
            for (int k = 0; k < 5; ++k) {
                px(x0 + w * t / 4, y0 + k, 0, 0, 0);
                px(x0 - k, y0 - h * t / 4, 0, 0, 0);
            }
        }
        for (const auto& r : rows) {
            if ((r.kind == "detector") == filters) continue;
            const int cx = x0 + static_cast<int>(std::max(0.0, r.x) / xmax * w);
            const int cy = y0 - static_cast<int>((r.y - ymin) / (ymax - ymin) * h);
            const bool blue = r.kind == "oneeuro" || r.kind == "detector";
            for (int dy = -3; dy <= 3; ++dy) {
                for (int dx = -3; dx <= 3; ++dx) {
                    px(cx + dx, cy + dy, blue ? 30 : 220, 60, blue ? 220 : 30);
                }
            }
        }
    };
    panel(0, true);
    panel(kPanel + 40, false);
    stbi_write_png(path.c_str(), kW, kH, 3, img.data(), kW * 3);
}

int run(const Options& o) {
    auto set = eval::load_lund2013(o.dir);
    if (!set) {
        std::fprintf(stderr, "gaze-sweep: %s\n", set.error().message.c_str());
        return 1;
    }
    std::vector<Row> rows;
    // Filters on the simulated tracker (1 kHz, default noise).
    drivers::sim::SimConfig sc;
    sc.seed = 21;
    drivers::sim::SimTracker sim(sc);
    std::vector<drivers::sim::SimTracker::Frame> frames(
        static_cast<size_t>(o.seconds * sc.rate_hz));
    for (auto& f : frames) f = sim.next();
    const Row raw = filter_row(frames, sc.rate_hz, gaze::FilterKind::kNone, {}, {}, "-", 0.0);
    rows.push_back(raw);
    rows.back().x = 0.0;
    for (double mc : {0.25, 0.5, 1.0, 2.0, 4.0}) {
        for (double beta : {0.0, 0.01, 0.1, 1.0}) {
            char p[64];
            std::snprintf(p, sizeof p, "mincutoff=%g beta=%g", mc, beta);
            rows.push_back(filter_row(frames, sc.rate_hz, gaze::FilterKind::kOneEuro,
                                      {mc, beta, 1.0, sc.rate_hz, 0.5}, {}, p, raw.x));
        }
    }
    for (double q : {20.0, 50.0, 200.0, 500.0, 2000.0}) {
        char p[64];
        std::snprintf(p, sizeof p, "accel_noise=%g sd=0.05", q);
        rows.push_back(filter_row(frames, sc.rate_hz, gaze::FilterKind::kKalman, {},
                                  {q, 0.05, 0.5, 1000.0}, p, raw.x));
    }
    // Detector look-ahead on the labelled recordings (online mode).
    for (double la : {0.04, 0.06, 0.1, 0.2, 0.4}) {
        gaze::DetectorParams dp;
        dp.lookahead_s = la;
        std::vector<std::vector<gaze::Event>> det;
        size_t n = 0;
        const auto t0 = Clock::now();
        for (const auto& r : set->recordings) {
            det.push_back(eval::detect(r, gaze::DetectorMode::kOnline, dp));
            n += det.back().size();
        }
        const double ns = std::chrono::duration<double, std::nano>(Clock::now() - t0).count() / n;
        const auto res = eval::score(*set, det);
        double sum = 0;
        int m = 0;
        for (const auto& [stim, ev] : res.cells) {
            for (const char* e : {"fixation", "saccade", "pso"}) {
                auto it = ev.find(e);
                if (it != ev.end() && std::isfinite(it->second.at(eval::kAllCoders).kappa())) {
                    sum += it->second.at(eval::kAllCoders).kappa();
                    ++m;
                }
            }
        }
        char p[64];
        std::snprintf(p, sizeof p, "lookahead_ms=%g", la * 1e3);
        rows.push_back({"detector", p, la * 1e3, m ? sum / m : NAN, ns});
    }
    const std::string csv = o.out + ".csv", png = o.out + ".png";
    std::FILE* f = std::fopen(csv.c_str(), "w");
    if (!f) {
        std::fprintf(stderr, "gaze-sweep: cannot write %s\n", csv.c_str());
        return 1;
    }
    std::fprintf(f, "kind,params,x,y,ns_per_sample,x_meaning,y_meaning\n");
    for (const auto& r : rows) {
        const bool det = r.kind == "detector";
        std::fprintf(f, "%s,%s,%.4f,%.5f,%.1f,%s,%s\n", r.kind.c_str(), r.params.c_str(), r.x, r.y,
                     r.ns, det ? "lookahead_ms" : "pursuit_lag_ms",
                     det ? "mean_kappa_fix_sac_pso" : "fixation_jitter_deg");
        std::printf("%-9s %-26s %s %8.2f  %s %.4f  %6.1f ns/sample\n", r.kind.c_str(),
                    r.params.c_str(), det ? "lookahead ms" : "lag ms", r.x,
                    det ? "kappa" : "jitter deg", r.y, r.ns);
    }
    std::fclose(f);
    plot(rows, png);
    std::printf("wrote %s and %s\n", csv.c_str(), png.c_str());
    return 0;
}

void setup(CLI::App& app) {
    auto o = std::make_shared<Options>();
    app.add_option("dir", o->dir, "Labelled recordings (lund2013 format) for the detector rows")
        ->required();
    app.add_option("--out", o->out, "Output prefix: PREFIX.csv and PREFIX.png");
    app.add_option("--seconds", o->seconds, "Simulated seconds for the filter rows");
    app.callback([o] {
        const int rc = run(*o);
        if (rc != 0) throw CLI::RuntimeError(rc);
    });
}

const Command kGazeSweep{"gaze-sweep", "Sweep filter/detector knobs: lag and time vs error",
                         &setup};

}  // namespace
}  // namespace fovea::cli
