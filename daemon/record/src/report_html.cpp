// `fovea report`, stage 3: the page (report_parts.hpp).
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "fovea/record/xdf.hpp"
#include "report_parts.hpp"

namespace fovea::record::report {
namespace {

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

std::string hop_rows(const Analysis& a) {
    std::string rows;
    for (std::size_t h = 0; h < kHops.size(); ++h) {
        const auto& H = a.hops[h];
        if (H.count() == 0) continue;
        rows += "<tr><td>" + std::string(kHops[h].title) + "</td><td>" + std::to_string(H.count()) +
                "</td><td>" + f2(H.percentile(0.5) / 1e3) + "</td><td>" +
                f2(H.percentile(0.9) / 1e3) + "</td><td>" + f2(H.percentile(0.99) / 1e3) +
                "</td><td>" + f2(H.percentile(0.999) / 1e3) + "</td><td>" + f2(H.max_ns() / 1e3) +
                "</td><td>" + std::to_string(H.negative()) + "</td></tr>\n";
    }
    return rows;
}

}  // namespace

std::string html_page(const Analysis& a, const std::string& source,
                      const std::vector<Figure>& figures, const std::string& out_dir) {
    const RecordingInfo& info = a.rec.info;
    const ReportSummary& sum = a.summary;
    std::ostringstream h;
    h << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>Fovea report: "
      << xdf::xml_escape(source) << "</title>\n<style>body{font-family:sans-serif;max-width:1040px;"
      << "margin:auto;color:#222}table{border-collapse:collapse;margin:8px 0}td,th{border:1px "
         "solid "
      << "#ccc;padding:3px 8px;text-align:right}td:first-child,th:first-child{text-align:left}"
      << "img{max-width:100%;border:1px solid #eee;margin:6px 0}</style></head><body>\n";
    h << "<h1>Fovea recording report</h1>\n<p>File <code>" << xdf::xml_escape(source)
      << "</code>, device <b>" << xdf::xml_escape(info.device_name) << "</b> ("
      << xdf::xml_escape(info.driver) << ", " << f2(info.nominal_rate_hz, "%.0f")
      << " Hz nominal), host " << xdf::xml_escape(info.hostname)
      << ".</p>\n<table><tr><th>quantity</th><th>value</th></tr>\n"
      << "<tr><td>duration</td><td>" << f2(sum.duration_s, "%.3f") << " s</td></tr>\n"
      << "<tr><td>raw samples</td><td>" << sum.raw_samples << "</td></tr>\n"
      << "<tr><td>effective rate</td><td>"
      << f2(sum.duration_s > 0 ? (sum.raw_samples - 1) / sum.duration_s : 0) << " Hz</td></tr>\n"
      << "<tr><td>processed samples</td><td>" << sum.gaze_samples << "</td></tr>\n"
      << "<tr><td>samples lost before the host (device counter gaps)</td><td>"
      << sum.missing_samples << "</td></tr>\n"
      << "<tr><td>saccades detected</td><td>" << sum.saccades << "</td></tr>\n"
      << "<tr><td>median peak velocity / main-sequence expectation</td><td>"
      << f2(sum.main_sequence_median_ratio, "%.2f") << "</td></tr>\n";
    for (int e = 0; e < 6; ++e) {
        const uint64_t n = a.event_samples[static_cast<std::size_t>(e)];
        h << "<tr><td>samples labelled " << event_label(static_cast<gaze::Event>(e)) << "</td><td>"
          << n << (sum.gaze_samples ? " (" + f2(100.0 * n / sum.gaze_samples) + " %)" : "")
          << "</td></tr>\n";
    }
    h << "</table>\n<h2>Latency per hop "
         "(us)</h2>\n<table><tr><th>hop</th><th>count</th><th>p50</th>"
      << "<th>p90</th><th>p99</th><th>p99.9</th><th>max</th><th>negative</th></tr>\n"
      << hop_rows(a) << "</table>\n<p>Capture times are the device clock mapped to the host clock; "
      << "'negative' counts samples whose mapped capture time lies after their receive time.</p>\n";
    for (const auto& [name, caption] : figures) {
        std::ifstream in((std::filesystem::path(out_dir) / name).string(), std::ios::binary);
        std::ostringstream bytes;
        bytes << in.rdbuf();
        h << "<h2>" << xdf::xml_escape(caption) << "</h2>\n<img alt=\"" << name
          << "\" src=\"data:image/png;base64," << base64(bytes.str()) << "\">\n";
    }
    h << "</body></html>\n";
    return h.str();
}

}  // namespace fovea::record::report
