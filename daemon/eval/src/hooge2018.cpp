// Hooge et al. (2018): Tobii TX300 recordings (300 Hz, 10 adults and 60 infants) and the
// fixation intervals twelve expert coders marked in them. The coders labelled fixations only:
// every other sample is "not fixation".
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "fovea/eval/dataset.hpp"
#include "loaders.hpp"

namespace fovea::eval {

namespace {

namespace fs = std::filesystem;

// From the dataset's README: a 1920 x 1080 screen of 50.9 x 28.6 cm at ~65 cm.
gaze::DisplayGeometry hooge_display() {
    gaze::DisplayGeometry d;
    d.width_px = 1920;
    d.height_px = 1080;
    d.width_m = 0.509;
    d.height_m = 0.286;
    d.distance_m = 0.65;
    return d;
}

// Tab-separated fields of one line.
std::vector<std::string> fields(const std::string& line) {
    std::vector<std::string> out;
    size_t start = 0;
    while (true) {
        const size_t tab = line.find('\t', start);
        out.push_back(line.substr(start, tab == std::string::npos ? tab : tab - start));
        if (tab == std::string::npos) break;
        start = tab + 1;
    }
    if (!out.empty() && !out.back().empty() && out.back().back() == '\r') out.back().pop_back();
    return out;
}

bool number(const std::string& s, double& v) {
    char* end = nullptr;
    v = std::strtod(s.c_str(), &end);
    return end != s.c_str();
}

struct Interval {
    double start_ms, end_ms;
};
// coder -> trial -> fixations
using CoderIntervals = std::map<std::string, std::map<std::string, std::vector<Interval>>>;

Result<void> read_coder(const fs::path& path, CoderIntervals& out, size_t& bad) {
    std::ifstream in(path);
    if (!in) return make_error("cannot open " + path.string());
    std::string line;
    if (!std::getline(in, line) || line.rfind("Trial\t", 0) != 0) {
        return make_error(path.string() + ":1: expected 'Trial\\tdatum\\tFixStart\\tFixEnd...'");
    }
    auto& coder = out[path.stem().string()];
    while (std::getline(in, line)) {
        if (line.empty()) continue;
        const auto f = fields(line);
        Interval iv{};
        if (f.size() < 4 || !number(f[2], iv.start_ms) || !number(f[3], iv.end_ms) ||
            !(iv.end_ms >= iv.start_ms)) {
            ++bad;
            continue;
        }
        coder[f[0]].push_back(iv);
    }
    return {};
}

}  // namespace

Result<Dataset> load_hooge2018(const std::string& dir) {
    const fs::path et = fs::path(dir) / "data" / "ETdata";
    const fs::path cs = fs::path(dir) / "data" / "coderSettings";
    std::error_code ec;
    if (!fs::is_directory(et, ec) || !fs::is_directory(cs, ec)) {
        return make_error(dir +
                          ": expected data/ETdata and data/coderSettings (Hooge et al. 2018)");
    }
    Dataset d;
    d.name = "hooge2018";
    d.path = dir;
    d.scheme = {gaze::Event::kFixation};
    CoderIntervals coders;
    std::vector<fs::path> coder_files, trial_files;
    for (const auto& e : fs::directory_iterator(cs, ec))
        if (e.path().extension() == ".txt") coder_files.push_back(e.path());
    for (const auto& e : fs::directory_iterator(et, ec))
        if (e.path().extension() == ".txt") trial_files.push_back(e.path());
    std::sort(coder_files.begin(), coder_files.end());
    std::sort(trial_files.begin(), trial_files.end());
    for (const auto& p : coder_files) {
        size_t bad = 0;
        if (auto r = read_coder(p, coders, bad); !r) {
            d.notes.push_back(r.error().message + " (coder skipped)");
        } else if (bad) {
            d.notes.push_back(p.filename().string() + ": " + std::to_string(bad) +
                              " unparsable intervals skipped");
        }
    }
    const gaze::DisplayGeometry display = hooge_display();
    for (const auto& p : trial_files) {
        std::ifstream in(p);
        std::string line;
        if (!in || !std::getline(in, line) || line.rfind("time", 0) != 0) {
            d.notes.push_back(p.string() + ":1: expected the header 'time x y v' (skipped)");
            continue;
        }
        std::vector<double> t_ms, x, y;
        size_t bad = 0;
        while (std::getline(in, line)) {
            if (line.empty()) continue;
            const auto f = fields(line);
            double t = 0, px = 0, py = 0;
            if (f.size() < 3 || !number(f[0], t)) {
                ++bad;
                continue;
            }
            if (!number(f[1], px)) px = gaze::kNaN;
            if (!number(f[2], py)) py = gaze::kNaN;
            t_ms.push_back(t);
            x.push_back(px);
            y.push_back(py);
        }
        if (bad) {
            d.notes.push_back(p.filename().string() + ": " + std::to_string(bad) +
                              " unparsable rows skipped");
        }
        if (t_ms.size() < 10) {
            d.notes.push_back(p.filename().string() + ": fewer than 10 samples (skipped)");
            continue;
        }
        Recording r;
        r.name = p.stem().string();
        r.stimulus = r.name.substr(0, r.name.find('_'));  // adult / infant
        r.subject = r.name;
        r.display = display;
        std::vector<double> t_s(t_ms.size());
        for (size_t i = 0; i < t_s.size(); ++i) t_s[i] = (t_ms[i] - t_ms[0]) * 1e-3;
        r.rate_hz = detail::rate_from_steps(t_s, 300.0);
        r.samples.resize(t_s.size());
        for (size_t i = 0; i < t_s.size(); ++i) {
            gaze::RawSample& s = r.samples[i];
            detail::set_time(s, t_s[i]);
            s.left.valid = std::isfinite(x[i]) && std::isfinite(y[i]);
            if (s.left.valid) {
                s.left.x = x[i] / display.width_px;
                s.left.y = y[i] / display.height_px;
            }
        }
        // A sample belongs to a fixation whose [start, end] holds its stamp (coders' times are
        // the samples' own, rounded to 0.01 ms).
        const double tol_ms = 0.25e3 / r.rate_hz;
        for (const auto& [coder, trials] : coders) {
            auto it = trials.find(r.name);
            if (it == trials.end()) continue;  // this coder did not code the trial
            std::vector<gaze::Event> labels(t_ms.size(), gaze::Event::kUnknown);
            for (const Interval& iv : it->second) {
                auto lo = std::lower_bound(t_ms.begin(), t_ms.end(), iv.start_ms - tol_ms);
                for (auto k = lo; k != t_ms.end() && *k <= iv.end_ms + tol_ms; ++k) {
                    labels[static_cast<size_t>(k - t_ms.begin())] = gaze::Event::kFixation;
                }
            }
            r.coders[coder] = std::move(labels);
        }
        if (r.coders.empty()) {
            d.notes.push_back(r.name + ": no coder labelled it (skipped)");
            continue;
        }
        d.recordings.push_back(std::move(r));
    }
    if (d.recordings.empty()) return make_error(dir + ": no coded Hooge 2018 trial");
    return d;
}

}  // namespace fovea::eval
