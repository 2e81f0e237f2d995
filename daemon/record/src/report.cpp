#include "fovea/record/report.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "fovea/latency_histogram.hpp"
#include "fovea/record/offline.hpp"
#include "fovea/record/plot.hpp"

namespace fovea::record {

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
const char* event_name(gaze::Event e) {
    switch (e) {
        case gaze::Event::kFixation: return "fixation";
        case gaze::Event::kSaccade: return "saccade";
        case gaze::Event::kPso: return "PSO";
        case gaze::Event::kPursuit: return "pursuit";
        case gaze::Event::kBlink: return "blink";
        default: return "unknown";
    }
}

std::string base64(const std::string& in) {
    static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    std::size_t i = 0;
    for (; i + 2 < in.size(); i += 3) {
        const uint32_t v = (uint8_t(in[i]) << 16) | (uint8_t(in[i + 1]) << 8) | uint8_t(in[i + 2]);
        out += k[v >> 18];
        out += k[(v >> 12) & 63];
        out += k[(v >> 6) & 63];
        out += k[v & 63];
    }
    if (i < in.size()) {
        uint32_t v = uint8_t(in[i]) << 16;
        if (i + 1 < in.size()) v |= uint8_t(in[i + 1]) << 8;
        out += k[v >> 18];
        out += k[(v >> 12) & 63];
        out += i + 1 < in.size() ? k[(v >> 6) & 63] : '=';
        out += '=';
    }
    return out;
}

std::string f2(double v, const char* fmt = "%.1f") {
    char b[48];
    std::snprintf(b, sizeof b, fmt, v);
    return b;
}

struct Saccade {
    double t_s, amplitude, peak;
};

}  // namespace

Result<ReportSummary> make_report(const xdf::File& file, const std::string& source,
                                  const std::string& out_dir) {
    auto decoded = decode_recording(file);
    if (!decoded) return decoded.error();
    Recording& rec = *decoded;
    // the pre-roll (chain history from before the recording started) is for replay only
    std::size_t keep = 0;
    for (std::size_t i = 0; i < rec.raw.size(); ++i) {
        if (rec.raw_preroll[i]) continue;
        rec.raw[keep] = rec.raw[i];
        rec.raw_predict_landing[keep] = rec.raw_predict_landing[i];
        rec.raw_preroll[keep++] = false;
    }
    rec.raw.resize(keep);
    rec.raw_predict_landing.resize(keep);
    rec.raw_preroll.resize(keep);
    std::error_code ec;
    std::filesystem::create_directories(out_dir, ec);
    if (ec) return make_error("cannot create " + out_dir + ": " + ec.message());
    ReportSummary sum;
    sum.raw_samples = rec.raw.size();
    sum.gaze_samples = rec.gaze.size();
    std::vector<std::pair<std::string, std::string>> figures;  // file, caption
    auto save = [&](Canvas& c, const std::string& name, const std::string& caption) -> Result<void> {
        const std::string p = (std::filesystem::path(out_dir) / name).string();
        if (auto r = c.save_png(p); !r) return r;
        sum.pngs.push_back(p);
        figures.emplace_back(name, caption);
        return {};
    };
    const double rate = rec.info.nominal_rate_hz > 0 ? rec.info.nominal_rate_hz : 1000.0;
    const int64_t t0 = !rec.raw.empty() ? rec.raw.front().t_receive_ns
                       : !rec.gaze.empty() ? rec.gaze.front().t_capture_ns : rec.info.time_origin_ns;
    if (!rec.raw.empty()) sum.duration_s = static_cast<double>(rec.raw.back().t_receive_ns - t0) * 1e-9;

    // ---- latency histograms per hop (from the gaze stream's own stamps) ----
    struct HopDef {
        const char* key;
        const char* title;
    };
    const HopDef hops[] = {{"capture_to_receive", "device capture -> host receive"},
                           {"receive_to_processed", "host receive -> processed"},
                           {"processed_to_publish", "processed -> published in ring"},
                           {"capture_to_publish", "total: device capture -> published"}};
    std::array<LatencyHistogram, 4> hist;
    for (std::size_t i = 0; i < rec.gaze.size(); ++i) {
        const auto& g = rec.gaze[i];
        hist[0].record(g.t_receive_ns - g.t_capture_ns);
        hist[1].record(g.t_processed_ns - g.t_receive_ns);
        hist[2].record(rec.t_publish_ns[i] - g.t_processed_ns);
        hist[3].record(rec.t_publish_ns[i] - g.t_capture_ns);
    }
    std::string hop_rows;
    for (std::size_t h = 0; h < 4; ++h) {
        const auto& H = hist[h];
        if (H.count() == 0) continue;
        hop_rows += "<tr><td>" + std::string(hops[h].title) + "</td><td>" + std::to_string(H.count()) +
                    "</td><td>" + f2(H.percentile(0.5) / 1e3) + "</td><td>" + f2(H.percentile(0.9) / 1e3) +
                    "</td><td>" + f2(H.percentile(0.99) / 1e3) + "</td><td>" +
                    f2(H.percentile(0.999) / 1e3) + "</td><td>" + f2(H.max_ns() / 1e3) + "</td><td>" +
                    std::to_string(H.negative()) + "</td></tr>\n";
        // log-spaced display bins, 20 per decade, over [min, max]
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
                                   static_cast<double>(LatencyHistogram::bucket_width(i)) / 2) / 1e3;
            const int b = std::clamp(static_cast<int>(nb * std::log10(mid_us / lo_us) / std::log10(hi_us / lo_us)), 0, nb - 1);
            cnt[static_cast<std::size_t>(b)] += static_cast<double>(c);
        }
        Plot p(kW, kH, std::string("Latency: ") + hops[h].title, "latency (us, log scale)", "samples");
        p.set_x(lo_us, hi_us, true);
        p.set_y(0, *std::max_element(cnt.begin(), cnt.end()) * 1.15);
        p.bars(blo, bhi, cnt, {70, 110, 180});
        p.vline(H.percentile(0.5) / 1e3, {0, 140, 0}, "p50 " + f2(H.percentile(0.5) / 1e3) + " us");
        p.vline(H.percentile(0.99) / 1e3, {200, 0, 0}, "p99 " + f2(H.percentile(0.99) / 1e3) + " us");
        if (auto r = save(p.finish(), std::string("latency_") + hops[h].key + ".png",
                          std::string("Latency histogram, ") + hops[h].title); !r) return r.error();
    }

    // ---- gaze trace with events ----
    if (!rec.gaze.empty()) {
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
            p.legend(event_name(e), event_colour(e));
        }
        if (auto r = save(p.finish(), "gaze_trace.png",
                          "Gaze trace over time; background = detected event"); !r) return r.error();
    }

    // ---- main sequence ----
    std::vector<Saccade> sacc;
    for (std::size_t i = 0; i < rec.gaze.size();) {
        if (rec.gaze[i].event != gaze::Event::kSaccade) {
            ++i;
            continue;
        }
        std::size_t j = i;
        double amp = 0, peak = 0;
        while (j < rec.gaze.size() && rec.gaze[j].event == gaze::Event::kSaccade) {
            if (std::isfinite(rec.gaze[j].saccade.amplitude_deg)) amp = std::max(amp, rec.gaze[j].saccade.amplitude_deg);
            if (std::isfinite(rec.gaze[j].saccade.peak_velocity_dps)) peak = std::max(peak, rec.gaze[j].saccade.peak_velocity_dps);
            ++j;
        }
        if (amp > 0 && peak > 0) sacc.push_back({static_cast<double>(rec.gaze[i].t_capture_ns - t0) * 1e-9, amp, peak});
        i = j;
    }
    sum.saccades = sacc.size();
    {
        std::vector<double> ax, pv, ratios;
        double amax = 20;
        for (const auto& s : sacc) {
            ax.push_back(s.amplitude);
            pv.push_back(s.peak);
            amax = std::max(amax, s.amplitude * 1.1);
            ratios.push_back(s.peak / (560.0 * (1 - std::exp(-s.amplitude / 4.25))));
        }
        if (!ratios.empty()) {
            std::nth_element(ratios.begin(), ratios.begin() + static_cast<long>(ratios.size() / 2), ratios.end());
            sum.main_sequence_median_ratio = ratios[ratios.size() / 2];
        }
        std::vector<double> cx, cy;
        for (int k = 0; k <= 200; ++k) {
            const double A = amax * k / 200.0;
            cx.push_back(A);
            cy.push_back(560.0 * (1 - std::exp(-A / 4.25)));
        }
        double vmax = 600;
        for (double v : pv) vmax = std::max(vmax, v * 1.1);
        Plot p(kW, kH, "Saccade main sequence", "amplitude (deg)", "peak velocity (deg/s)");
        p.set_x(0, amax);
        p.set_y(0, vmax);
        p.line(cx, cy, {0, 0, 0}, 2);
        p.points(ax, pv, {215, 48, 39}, 3);
        p.legend("expected 560(1-exp(-A/4.25))", {0, 0, 0});
        p.legend("detected saccades (" + std::to_string(sacc.size()) + ")", {215, 48, 39});
        if (auto r = save(p.finish(), "main_sequence.png",
                          "Peak velocity against amplitude per detected saccade, with the expected main sequence"); !r) return r.error();
    }

    // ---- drops and validity timelines (100 ms bins) ----
    if (!rec.raw.empty()) {
        const double bin_s = 0.1;
        const std::size_t nb = static_cast<std::size_t>(sum.duration_s / bin_s) + 1;
        std::vector<double> lo(nb), hi(nb), missing(nb, 0), tot(nb, 0), vl(nb, 0), vr(nb, 0), ring_gap(nb, 0);
        for (std::size_t b = 0; b < nb; ++b) {
            lo[b] = static_cast<double>(b) * bin_s;
            hi[b] = lo[b] + bin_s;
        }
        const double tick_period = 1.0 / rec.info.clock.tick_hz;
        const uint64_t mask = rec.info.clock.counter_bits >= 64 ? ~uint64_t{0} : (uint64_t{1} << rec.info.clock.counter_bits) - 1;
        for (std::size_t i = 0; i < rec.raw.size(); ++i) {
            const auto& r = rec.raw[i];
            const std::size_t b = std::min(nb - 1, static_cast<std::size_t>(static_cast<double>(r.t_receive_ns - t0) * 1e-9 / bin_s));
            tot[b] += 1;
            vl[b] += r.left.valid;
            vr[b] += r.right.valid;
            if (i > 0 && rec.raw[i - 1].device_id == r.device_id) {
                // gaps in the device's own clock: samples the device took that never arrived
                const double dt = static_cast<double>((r.device_ticks - rec.raw[i - 1].device_ticks) & mask) * tick_period;
                const double lost = std::round(dt * rate) - 1;
                if (lost > 0 && lost < 1e6) {
                    missing[b] += lost;
                    sum.missing_samples += static_cast<uint64_t>(lost);
                }
            }
        }
        for (std::size_t i = 1; i < rec.ring_index.size(); ++i) {
            const double gap = static_cast<double>(rec.ring_index[i]) - static_cast<double>(rec.ring_index[i - 1]) - 1;
            if (gap > 0) {
                const std::size_t b = std::min(nb - 1, static_cast<std::size_t>(std::max(0.0, static_cast<double>(rec.gaze[i].t_capture_ns - t0) * 1e-9 / bin_s)));
                ring_gap[b] += gap;
            }
        }
        std::vector<double> mid(nb), fl(nb), fr(nb);
        for (std::size_t b = 0; b < nb; ++b) {
            mid[b] = lo[b] + bin_s / 2;
            fl[b] = tot[b] ? vl[b] / tot[b] * 100 : 0;
            fr[b] = tot[b] ? vr[b] / tot[b] * 100 : 0;
        }
        double mmax = 1;
        for (std::size_t b = 0; b < nb; ++b) mmax = std::max({mmax, missing[b] * 1.2, ring_gap[b] * 1.2});
        {
            Plot p(kW, kH / 1.3, "Dropped samples per 100 ms", "time (s)", "samples");
            p.set_x(0, std::max(sum.duration_s, 0.1));
            p.set_y(0, mmax);
            p.bars(lo, hi, missing, {215, 48, 39});
            p.bars(lo, hi, ring_gap, {120, 60, 160});
            p.legend("lost by device/transport (counter gaps)", {215, 48, 39});
            p.legend("not recorded (ring index gaps)", {120, 60, 160});
            if (auto r = save(p.finish(), "drops.png", "Drop timeline"); !r) return r.error();
        }
        {
            Plot p(kW, kH / 1.3, "Validity per 100 ms", "time (s)", "% valid");
            p.set_x(0, std::max(sum.duration_s, 0.1));
            p.set_y(0, 105);
            p.line(mid, fl, {33, 102, 172}, 2);
            p.line(mid, fr, {27, 158, 119}, 1);
            p.legend("left eye", {33, 102, 172});
            p.legend("right eye", {27, 158, 119});
            if (auto r = save(p.finish(), "validity.png", "Validity timeline"); !r) return r.error();
        }
    }

    // ---- HTML ----
    std::array<uint64_t, 6> ev{};
    for (const auto& g : rec.gaze) ev[std::min<std::size_t>(5, static_cast<std::size_t>(g.event))]++;
    std::ostringstream h;
    h << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>Fovea report: "
      << xdf::xml_escape(source) << "</title>\n<style>body{font-family:sans-serif;max-width:1040px;"
      << "margin:auto;color:#222}table{border-collapse:collapse;margin:8px 0}td,th{border:1px solid "
      << "#ccc;padding:3px 8px;text-align:right}td:first-child,th:first-child{text-align:left}"
      << "img{max-width:100%;border:1px solid #eee;margin:6px 0}</style></head><body>\n";
    h << "<h1>Fovea recording report</h1>\n<p>File <code>" << xdf::xml_escape(source) << "</code>, device <b>"
      << xdf::xml_escape(rec.info.device_name) << "</b> (" << xdf::xml_escape(rec.info.driver) << ", "
      << f2(rec.info.nominal_rate_hz, "%.0f") << " Hz nominal), host " << xdf::xml_escape(rec.info.hostname)
      << ".</p>\n<table><tr><th>quantity</th><th>value</th></tr>\n"
      << "<tr><td>duration</td><td>" << f2(sum.duration_s, "%.3f") << " s</td></tr>\n"
      << "<tr><td>raw samples</td><td>" << sum.raw_samples << "</td></tr>\n"
      << "<tr><td>effective rate</td><td>" << f2(sum.duration_s > 0 ? (sum.raw_samples - 1) / sum.duration_s : 0) << " Hz</td></tr>\n"
      << "<tr><td>processed samples</td><td>" << sum.gaze_samples << "</td></tr>\n"
      << "<tr><td>samples lost before the host (device counter gaps)</td><td>" << sum.missing_samples << "</td></tr>\n"
      << "<tr><td>saccades detected</td><td>" << sum.saccades << "</td></tr>\n"
      << "<tr><td>median peak velocity / main-sequence expectation</td><td>"
      << f2(sum.main_sequence_median_ratio, "%.2f") << "</td></tr>\n";
    for (int e = 0; e < 6; ++e) {
        h << "<tr><td>samples labelled " << event_name(static_cast<gaze::Event>(e)) << "</td><td>" << ev[static_cast<std::size_t>(e)]
          << (sum.gaze_samples ? " (" + f2(100.0 * ev[static_cast<std::size_t>(e)] / sum.gaze_samples) + " %)" : "") << "</td></tr>\n";
    }
    h << "</table>\n<h2>Latency per hop (us)</h2>\n<table><tr><th>hop</th><th>count</th><th>p50</th>"
      << "<th>p90</th><th>p99</th><th>p99.9</th><th>max</th><th>negative</th></tr>\n"
      << hop_rows << "</table>\n<p>Capture times are the device clock mapped to the host clock; "
      << "'negative' counts samples whose mapped capture time lies after their receive time.</p>\n";
    for (const auto& [name, caption] : figures) {
        std::ifstream in((std::filesystem::path(out_dir) / name).string(), std::ios::binary);
        std::ostringstream bytes;
        bytes << in.rdbuf();
        h << "<h2>" << xdf::xml_escape(caption) << "</h2>\n<img alt=\"" << name
          << "\" src=\"data:image/png;base64," << base64(bytes.str()) << "\">\n";
    }
    h << "</body></html>\n";
    sum.html_path = (std::filesystem::path(out_dir) / "report.html").string();
    std::ofstream out(sum.html_path);
    out << h.str();
    if (!out) return make_error("cannot write " + sum.html_path);
    return sum;
}

}  // namespace fovea::record
