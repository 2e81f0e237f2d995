// U'n'Eye (Bellet et al. 2019) training matrices: X and Y in degrees, Labels 0 fixation /
// 1 saccade, one trial a row, the sampling rate in the file names ("..._500hz_...").
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "fovea/eval/dataset.hpp"
#include "loaders.hpp"

namespace fovea::eval {

namespace {

namespace fs = std::filesystem;

Result<std::vector<std::vector<double>>> read_matrix(const fs::path& path) {
    std::ifstream in(path);
    if (!in) return make_error("cannot open " + path.string());
    std::vector<std::vector<double>> rows;
    std::string line;
    for (size_t n = 1; std::getline(in, line); ++n) {
        if (line.empty() || line == "\r") continue;
        std::vector<double> row;
        const char* p = line.c_str();
        while (*p && *p != '\r') {
            char* end = nullptr;
            const double v = std::strtod(p, &end);
            if (end == p) {
                return make_error(path.string() + ":" + std::to_string(n) +
                                  ": not a number at column " + std::to_string(row.size() + 1));
            }
            row.push_back(v);
            p = end;
            if (*p == ',') ++p;
        }
        rows.push_back(std::move(row));
    }
    return rows;
}

// The digits just before the first "hz" (any case) of a file name, e.g. "..._1000Hz_..." -> 1000;
// 0 when there are none.
double rate_in_name(const std::string& name) {
    for (size_t at = 0; at + 1 < name.size(); ++at) {
        if (std::tolower(static_cast<unsigned char>(name[at])) != 'h' ||
            std::tolower(static_cast<unsigned char>(name[at + 1])) != 'z') {
            continue;
        }
        size_t first = at;
        while (first > 0 && std::isdigit(static_cast<unsigned char>(name[first - 1]))) --first;
        if (first < at) return std::strtod(name.substr(first, at - first).c_str(), nullptr);
    }
    return 0;
}

}  // namespace

Result<Dataset> load_uneye(const std::string& dir) {
    std::error_code ec;
    Dataset d;
    d.name = "uneye";
    d.path = dir;
    d.scheme = {gaze::Event::kFixation, gaze::Event::kSaccade};
    // Sets of three matrices sharing a name but for X / Y / Labels.
    std::vector<fs::path> label_files;
    for (const auto& e : fs::directory_iterator(dir, ec)) {
        const std::string n = e.path().filename().string();
        if (e.path().extension() == ".csv" && n.find("_Labels_") != std::string::npos) {
            label_files.push_back(e.path());
        }
    }
    std::sort(label_files.begin(), label_files.end());
    for (const auto& lp : label_files) {
        const std::string name = lp.filename().string();
        const size_t at = name.find("_Labels_");
        const fs::path xp = lp.parent_path() / (name.substr(0, at) + "_X_" + name.substr(at + 8));
        const fs::path yp = lp.parent_path() / (name.substr(0, at) + "_Y_" + name.substr(at + 8));
        const double rate = rate_in_name(name);
        if (!(rate > 0)) {
            d.notes.push_back(name + ": no sampling rate ('..._500hz_...') in the name (skipped)");
            continue;
        }
        auto lab = read_matrix(lp);
        auto xs = read_matrix(xp);
        auto ys = read_matrix(yp);
        for (const auto* r : {&lab, &xs, &ys}) {
            if (!*r) d.notes.push_back(r->error().message + " (set skipped)");
        }
        if (!lab || !xs || !ys) continue;
        if (lab->size() != xs->size() || lab->size() != ys->size()) {
            d.notes.push_back(name + ": X, Y and Labels have different row counts (set skipped)");
            continue;
        }
        const std::string set = fs::path(name.substr(at + 8)).stem().string();
        const gaze::DisplayGeometry display = detail::degree_display();
        for (size_t row = 0; row < lab->size(); ++row) {
            const auto& l = (*lab)[row];
            const auto& x = (*xs)[row];
            const auto& y = (*ys)[row];
            const size_t n = std::min({l.size(), x.size(), y.size()});
            if (n < 10) continue;
            Recording r;
            char id[32];
            std::snprintf(id, sizeof id, "%s_trial%03zu", set.c_str(), row + 1);
            r.name = id;
            r.stimulus = "all";
            r.subject = set;
            r.rate_hz = rate;
            r.display = display;
            r.samples.resize(n);
            std::vector<gaze::Event> labels(n);
            for (size_t i = 0; i < n; ++i) {
                gaze::RawSample& s = r.samples[i];
                detail::set_time(s, static_cast<double>(i) / rate);
                s.left.valid = std::isfinite(x[i]) && std::isfinite(y[i]) && std::fabs(x[i]) < 60 &&
                               std::fabs(y[i]) < 60;
                if (s.left.valid) display.to_normalized(x[i], y[i], s.left.x, s.left.y);
                labels[i] = l[i] == 1   ? gaze::Event::kSaccade
                            : l[i] == 0 ? gaze::Event::kFixation
                                        : gaze::Event::kUnknown;
                s.truth = labels[i];
            }
            r.coders["expert"] = std::move(labels);
            d.recordings.push_back(std::move(r));
        }
    }
    if (d.recordings.empty()) return make_error(dir + ": no U'n'Eye X/Y/Labels matrices");
    return d;
}

}  // namespace fovea::eval
