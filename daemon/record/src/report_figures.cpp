// `fovea report`, stage 2: the figures (report_parts.hpp).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "fovea/record/plot.hpp"
#include "report_parts.hpp"

namespace fovea::record::report {
namespace {

constexpr int kW = 1000, kH = 420;

Rgb event_colour(gaze::Event e) {
    switch (e) {
        case gaze::Event::kFixation: return {222, 235, 247};
        case gaze::Event::kSaccade: return {252, 187, 161};
        case gaze::Event::kPso: return {253, 224, 144};
        case gaze::Event::kPursuit: return {199, 233, 192};
        case gaze::Event::kBlink: return {210, 210, 210};
        default: return {255, 255, 255};
    }
}

std::string f1(double v) {
    char b[48];
    std::snprintf(b, sizeof b, "%.1f", v);
    return b;
}

class Figures {
public:
    explicit Figures(const std::string& out_dir) : out_dir_(out_dir) {}

    Result<void> save(Canvas& c, const std::string& name, const std::string& caption) {
        if (auto r = c.save_png((std::filesystem::path(out_dir_) / name).string()); !r) return r;
        list_.push_back({name, caption});
        return {};
    }
    std::vector<Figure> take() { return std::move(list_); }

private:
    std::string out_dir_;
    std::vector<Figure> list_;
};

// Log-spaced display bins, 20 per decade, over [min, max] of the histogram.
Result<void> latency_figure(Figures& out, const HopDef& hop, const LatencyHistogram& H) {
    const double lo_us = std::max(0.1, static_cast<double>(H.min_ns()) / 1e3 * 0.9);
    const double hi_us = std::max(lo_us * 10, static_cast<double>(H.max_ns()) / 1e3 * 1.1);
    const int nb = std::max(10, static_cast<int>(std::ceil(20 * std::log10(hi_us / lo_us))));
    std::vector<double> blo(static_cast<std::size_t>(nb)), bhi(blo.size()), cnt(blo.size(), 0.0);
    for (int b = 0; b < nb; ++b) {
        blo[static_cast<std::size_t>(b)] = lo_us * std::pow(hi_us / lo_us, double(b) / nb);
        bhi[static_cast<std::size_t>(b)] = lo_us * std::pow(hi_us / lo_us, double(b + 1) / nb);
    }
    for (int i = 0; i < LatencyHistogram::kBucketCount; ++i) {
        const uint64_t c = H.bucket_count(i);
        if (!c) continue;
        const double mid_us = (static_cast<double>(LatencyHistogram::bucket_lower(i)) +
                               static_cast<double>(LatencyHistogram::bucket_width(i)) / 2) /
                              1e3;
        const int b = std::clamp(
            static_cast<int>(nb * std::log10(mid_us / lo_us) / std::log10(hi_us / lo_us)), 0,
            nb - 1);
        cnt[static_cast<std::size_t>(b)] += static_cast<double>(c);
    }
    Plot p(kW, kH, std::string("Latency: ") + hop.title, "latency (us, log scale)", "samples");
    p.set_x(lo_us, hi_us, true);
    p.set_y(0, *std::max_element(cnt.begin(), cnt.end()) * 1.15);
    p.bars(blo, bhi, cnt, {70, 110, 180});
    p.vline(H.percentile(0.5) / 1e3, {0, 140, 0}, "p50 " + f1(H.percentile(0.5) / 1e3) + " us");
    p.vline(H.percentile(0.99) / 1e3, {200, 0, 0}, "p99 " + f1(H.percentile(0.99) / 1e3) + " us");
    return out.save(p.finish(), std::string("latency_") + hop.key + ".png",
                    std::string("Latency histogram, ") + hop.title);
}

Result<void> gaze_trace_figure(Figures& out, const Recording& rec, int64_t t0) {
    std::vector<double> t, x, y;
    double ymin = -5, ymax = 5;
    for (const auto& g : rec.gaze) {
        t.push_back(static_cast<double>(g.t_capture_ns - t0) * 1e-9);
        x.push_back(g.combined_deg_x);
        y.push_back(g.combined_deg_y);
        for (double v : {g.combined_deg_x, g.combined_deg_y}) {
            if (std::isfinite(v)) {
                ymin = std::min(ymin, v);
                ymax = std::max(ymax, v);
            }
        }
    }
    Plot p(kW, kH, "Gaze (combined eye) with detected events", "time (s)", "deg from centre");
    p.set_x(std::min(0.0, t.front()), std::max(t.back(), 1e-3));
    p.set_y(ymin - 1, ymax + 1);
    std::size_t a = 0;
    for (std::size_t i = 1; i <= rec.gaze.size(); ++i) {
        if (i == rec.gaze.size() || rec.gaze[i].event != rec.gaze[a].event) {
            p.xspan(t[a], t[i - 1], event_colour(rec.gaze[a].event));
            a = i;
        }
    }
    p.line(t, x, {33, 102, 172}, 1);
    p.line(t, y, {178, 24, 43}, 1);
    p.legend("x", {33, 102, 172});
    p.legend("y", {178, 24, 43});
    for (auto e : {gaze::Event::kFixation, gaze::Event::kSaccade, gaze::Event::kPso,
                   gaze::Event::kPursuit, gaze::Event::kBlink}) {
        p.legend(event_label(e), event_colour(e));
    }
    return out.save(p.finish(), "gaze_trace.png",
                    "Gaze trace over time; background = detected event");
}

Result<void> main_sequence_figure(Figures& out, const std::vector<Saccade>& sacc) {
    std::vector<double> ax, pv;
    double amax = 20;
    for (const auto& s : sacc) {
        ax.push_back(s.amplitude);
        pv.push_back(s.peak);
        amax = std::max(amax, s.amplitude * 1.1);
    }
    std::vector<double> cx, cy;
    for (int k = 0; k <= 200; ++k) {
        const double A = amax * k / 200.0;
        cx.push_back(A);
        cy.push_back(kExpectedMainSequence.peak_velocity_dps(A));
    }
    double vmax = 600;
    for (double v : pv) vmax = std::max(vmax, v * 1.1);
    Plot p(kW, kH, "Saccade main sequence", "amplitude (deg)", "peak velocity (deg/s)");
    p.set_x(0, amax);
    p.set_y(0, vmax);
    p.line(cx, cy, {0, 0, 0}, 2);
    p.points(ax, pv, {215, 48, 39}, 3);
    char curve[64];
    std::snprintf(curve, sizeof curve, "expected %g(1-exp(-A/%g))", kExpectedMainSequence.peak_dps,
                  kExpectedMainSequence.peak_c_deg);
    p.legend(curve, {0, 0, 0});
    p.legend("detected saccades (" + std::to_string(sacc.size()) + ")", {215, 48, 39});
    return out.save(
        p.finish(), "main_sequence.png",
        "Peak velocity against amplitude per detected saccade, with the expected main sequence");
}

Result<void> timeline_figures(Figures& out, const Timeline& tl, double duration_s) {
    const std::size_t nb = tl.lo.size();
    std::vector<double> mid(nb), fl(nb), fr(nb);
    for (std::size_t b = 0; b < nb; ++b) {
        mid[b] = tl.lo[b] + tl.bin_s / 2;
        fl[b] = tl.total[b] ? tl.valid_left[b] / tl.total[b] * 100 : 0;
        fr[b] = tl.total[b] ? tl.valid_right[b] / tl.total[b] * 100 : 0;
    }
    double mmax = 1;
    for (std::size_t b = 0; b < nb; ++b)
        mmax = std::max({mmax, tl.missing[b] * 1.2, tl.ring_gap[b] * 1.2});
    {
        Plot p(kW, kH / 1.3, "Dropped samples per 100 ms", "time (s)", "samples");
        p.set_x(0, std::max(duration_s, 0.1));
        p.set_y(0, mmax);
        p.bars(tl.lo, tl.hi, tl.missing, {215, 48, 39});
        p.bars(tl.lo, tl.hi, tl.ring_gap, {120, 60, 160});
        p.legend("lost by device/transport (counter gaps)", {215, 48, 39});
        p.legend("not recorded (ring index gaps)", {120, 60, 160});
        if (auto r = out.save(p.finish(), "drops.png", "Drop timeline"); !r) return r;
    }
    Plot p(kW, kH / 1.3, "Validity per 100 ms", "time (s)", "% valid");
    p.set_x(0, std::max(duration_s, 0.1));
    p.set_y(0, 105);
    p.line(mid, fl, {33, 102, 172}, 2);
    p.line(mid, fr, {27, 158, 119}, 1);
    p.legend("left eye", {33, 102, 172});
    p.legend("right eye", {27, 158, 119});
    return out.save(p.finish(), "validity.png", "Validity timeline");
}

}  // namespace

Result<std::vector<Figure>> draw_figures(const Analysis& a, const std::string& out_dir) {
    Figures out(out_dir);
    for (std::size_t h = 0; h < kHops.size(); ++h) {
        if (a.hops[h].count() == 0) continue;
        if (auto r = latency_figure(out, kHops[h], a.hops[h]); !r) return r.error();
    }
    if (!a.rec.gaze.empty()) {
        if (auto r = gaze_trace_figure(out, a.rec, a.t0); !r) return r.error();
    }
    if (auto r = main_sequence_figure(out, a.saccades); !r) return r.error();
    if (!a.rec.raw.empty()) {
        if (auto r = timeline_figures(out, a.timeline, a.summary.duration_s); !r) return r.error();
    }
    return out.take();
}

}  // namespace fovea::record::report
