#include "replay/recording.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string_view>

namespace fovea::drivers::replay {
namespace {

std::vector<std::string_view> split(std::string_view line, char sep) {
    std::vector<std::string_view> out;
    std::size_t start = 0;
    while (true) {
        const std::size_t p = line.find(sep, start);
        out.push_back(line.substr(start, p == std::string_view::npos ? p : p - start));
        if (p == std::string_view::npos) return out;
        start = p + 1;
    }
}

std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.back() == '\r' || s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    return s;
}

// Parses a whole field as a double ("nan" included); false on junk.
bool number(std::string_view s, double& out) {
    s = trim(s);
    if (s.empty()) return false;
    const std::string tmp(s);
    char* end = nullptr;
    out = std::strtod(tmp.c_str(), &end);
    return end == tmp.c_str() + tmp.size();
}

gaze::Event event_from_name(std::string_view s) {
    s = trim(s);
    if (s == "fixation") return gaze::Event::kFixation;
    if (s == "saccade") return gaze::Event::kSaccade;
    if (s == "pso") return gaze::Event::kPso;
    if (s == "pursuit") return gaze::Event::kPursuit;
    if (s == "blink") return gaze::Event::kBlink;
    return gaze::Event::kUnknown;
}

gaze::Event event_from_lund(double label) {
    switch (static_cast<int>(label)) {
        case 1: return gaze::Event::kFixation;
        case 2: return gaze::Event::kSaccade;
        case 3: return gaze::Event::kPso;
        case 4: return gaze::Event::kPursuit;
        case 5: return gaze::Event::kBlink;
        default: return gaze::Event::kUnknown;  // 6: undefined
    }
}

// "key=value key=a,b ..." from the lund2013 first line.
std::map<std::string, std::string> header_fields(std::string_view line) {
    std::map<std::string, std::string> f;
    line.remove_prefix(1);  // '#'
    for (auto tok : split(line, ' ')) {
        tok = trim(tok);
        const auto eq = tok.find('=');
        if (eq != std::string_view::npos) f[std::string(tok.substr(0, eq))] = std::string(tok.substr(eq + 1));
    }
    return f;
}

void finish(Recording& r) {
    if (r.t_ns.size() >= 2) {
        std::vector<int64_t> dt;
        dt.reserve(r.t_ns.size() - 1);
        for (std::size_t i = 1; i < r.t_ns.size(); ++i) dt.push_back(r.t_ns[i] - r.t_ns[i - 1]);
        std::nth_element(dt.begin(), dt.begin() + static_cast<long>(dt.size() / 2), dt.end());
        const int64_t med = dt[dt.size() / 2];
        // Timestamps win over the header (some lund2013 files say 500 Hz but are 200 Hz).
        if (med > 0) r.nominal_rate_hz = std::round(1e9 / static_cast<double>(med) * 100) / 100;
    }
    if (!r.t_ns.empty()) {
        const int64_t t0 = r.t_ns.front();
        for (auto& t : r.t_ns) t -= t0;
    }
}

Result<Recording> parse_lund(std::istringstream& in, std::string_view first, const std::string& name) {
    Recording r;
    r.format = "lund2013";
    r.clock = {64, 1e6};
    r.binocular = false;
    const auto h = header_fields(first);
    const auto get = [&](const char* k) -> const std::string* {
        const auto it = h.find(k);
        return it == h.end() ? nullptr : &it->second;
    };
    double rate = 0;
    if (!get("sampFreq") || !number(*get("sampFreq"), rate) || !(rate > 0 && rate <= 10000))
        return make_error(name + ":1: lund2013 header needs sampFreq=HZ");
    r.nominal_rate_hz = rate;
    double res_w = 0, res_h = 0;
    if (const auto* res = get("screenRes_px")) {
        const auto p = split(*res, ',');
        if (p.size() != 2 || !number(p[0], res_w) || !number(p[1], res_h) || res_w <= 0 || res_h <= 0)
            return make_error(name + ":1: bad screenRes_px");
    } else {
        return make_error(name + ":1: lund2013 header needs screenRes_px=W,H");
    }
    r.display.width_px = static_cast<int>(res_w);
    r.display.height_px = static_cast<int>(res_h);
    if (const auto* dim = get("screenDim_m")) {
        const auto p = split(*dim, ',');
        double w = 0, hh = 0;
        if (p.size() == 2 && number(p[0], w) && number(p[1], hh) && w > 0 && hh > 0) {
            r.display.width_m = w;
            r.display.height_m = hh;
        }
    }
    if (const auto* d = get("viewDist_m")) {
        double v = 0;
        if (number(*d, v) && v > 0) r.display.distance_m = v;
    }

    std::string line;
    if (!std::getline(in, line)) return make_error(name + ":2: missing column header");
    const auto cols = split(trim(line), ',');
    std::map<std::string, std::size_t> idx;
    for (std::size_t i = 0; i < cols.size(); ++i) idx[std::string(trim(cols[i]))] = i;
    for (const char* c : {"t_us", "x_px", "y_px"})
        if (!idx.count(c)) return make_error(name + ":2: missing column '" + c + "'");
    const bool has_label = idx.count("label") != 0;
    const double period_us = 1e6 / rate;
    double prev_t_us = NAN;
    int line_no = 2;
    while (std::getline(in, line)) {
        ++line_no;
        if (trim(line).empty()) continue;
        ++r.rows;
        const auto f = split(trim(line), ',');
        double t_us = NAN, x = 0, y = 0, label = 6;
        if (f.size() < cols.size() || !number(f[idx["x_px"]], x) || !number(f[idx["y_px"]], y) ||
            (has_label && !number(f[idx["label"]], label))) {
            ++r.skipped_rows;
            continue;
        }
        // NaN, and 0 after the first row (padding at the end of some files): nominal rate.
        if (!number(f[idx["t_us"]], t_us) || !std::isfinite(t_us) ||
            (t_us == 0 && std::isfinite(prev_t_us))) {
            t_us = std::isfinite(prev_t_us) ? prev_t_us + period_us : 0.0;
        }
        if (std::isfinite(prev_t_us) && t_us <= prev_t_us) {
            ++r.skipped_rows;
            continue;
        }
        prev_t_us = t_us;
        gaze::RawSample s;
        s.device_ticks = static_cast<uint64_t>(std::llround(std::max(0.0, t_us)));
        // Lost tracking is 0,0 (not NaN) in these files.
        if (std::isfinite(x) && std::isfinite(y) && !(x == 0 && y == 0)) {
            s.left = {x / res_w, y / res_h, 0.0, true};
        }
        s.truth = event_from_lund(label);
        r.samples.push_back(s);
        r.t_ns.push_back(static_cast<int64_t>(std::llround(t_us * 1000.0)));
    }
    finish(r);
    return r;
}

Result<Recording> parse_fovea(std::istringstream& in, const std::string& name) {
    Recording r;
    r.format = "fovea-csv";
    r.clock = {64, 1e9};
    std::string line;
    if (!std::getline(in, line)) return make_error(name + ":2: missing column header");
    const auto cols = split(trim(line), ',');
    std::map<std::string, std::size_t> idx;
    for (std::size_t i = 0; i < cols.size(); ++i) idx[std::string(trim(cols[i]))] = i;
    for (const char* c : {"t_capture_ns", "left_x", "left_y", "left_valid"})
        if (!idx.count(c)) return make_error(name + ":2: missing column '" + c + "'");
    const bool right = idx.count("right_x") && idx.count("right_y") && idx.count("right_valid");
    const bool pupil = idx.count("left_pupil_mm") != 0;
    const bool event = idx.count("event") != 0;
    r.binocular = right;
    r.has_pupil = pupil;
    int64_t prev = 0;
    bool have_prev = false;
    while (std::getline(in, line)) {
        if (trim(line).empty() || line[0] == '#') continue;
        ++r.rows;
        const auto f = split(trim(line), ',');
        const auto field = [&](const char* c) { return f[idx[c]]; };
        double t = 0;
        if (f.size() < cols.size() || !number(field("t_capture_ns"), t) || !std::isfinite(t) ||
            (have_prev && static_cast<int64_t>(t) <= prev)) {
            ++r.skipped_rows;
            continue;
        }
        gaze::RawSample s;
        bool ok = true;
        const auto eye = [&](const char* x, const char* y, const char* p, const char* v,
                             gaze::EyeSample& e) {
            double fx = 0, fy = 0, fv = 0, fp = 0;
            if (!number(field(v), fv)) {
                ok = false;
                return;
            }
            if (fv == 0) return;
            if (!number(field(x), fx) || !number(field(y), fy) || !std::isfinite(fx) ||
                !std::isfinite(fy)) {
                ok = false;
                return;
            }
            if (p && idx.count(p) && number(field(p), fp) && std::isfinite(fp)) e.pupil_mm = fp;
            e.x = fx;
            e.y = fy;
            e.valid = true;
        };
        eye("left_x", "left_y", pupil ? "left_pupil_mm" : nullptr, "left_valid", s.left);
        if (right) eye("right_x", "right_y", pupil ? "right_pupil_mm" : nullptr, "right_valid", s.right);
        if (!ok) {
            ++r.skipped_rows;
            continue;
        }
        if (event) s.truth = event_from_name(field("event"));
        prev = static_cast<int64_t>(t);
        have_prev = true;
        s.device_ticks = static_cast<uint64_t>(prev);
        r.samples.push_back(s);
        r.t_ns.push_back(prev);
    }
    finish(r);
    return r;
}

}  // namespace

Result<Recording> parse_recording(const std::string& text, const std::string& name) {
    std::istringstream in(text);
    std::string first;
    if (!std::getline(in, first)) return make_error(name + ": empty file");
    const std::string_view f = trim(first);
    Result<Recording> r = f.starts_with("# fovea")       ? parse_fovea(in, name)
                          : f.starts_with("# sampFreq=") ? parse_lund(in, f, name)
                                                         : Result<Recording>(make_error(
                                                               name + ":1: unknown format (expected "
                                                                      "'# fovea ...' or '# sampFreq=...')"));
    if (r.ok() && r->samples.empty()) return make_error(name + ": no samples");
    return r;
}

Result<Recording> load_recording(const std::string& path) {
    std::ifstream file(path, std::ios::binary);
    if (!file) return make_error("cannot open " + path);
    std::ostringstream ss;
    ss << file.rdbuf();
    return parse_recording(ss.str(), path);
}

}  // namespace fovea::drivers::replay
