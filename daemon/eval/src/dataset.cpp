#include "fovea/eval/dataset.hpp"

#include <algorithm>
#include <filesystem>
#include <random>
#include <tuple>

#include "loaders.hpp"

namespace fovea::eval {

namespace fs = std::filesystem;

size_t Dataset::samples() const {
    size_t n = 0;
    for (const auto& r : recordings) n += r.samples.size();
    return n;
}

bool Dataset::labels(gaze::Event e) const {
    return std::find(scheme.begin(), scheme.end(), e) != scheme.end();
}

Degrees degrees(const Recording& r, size_t i) {
    const gaze::RawSample& s = r.samples[i];
    Degrees out;
    double sx = 0, sy = 0;
    int n = 0;
    for (const gaze::EyeSample* e : {&s.left, &s.right}) {
        if (!e->valid || !std::isfinite(e->x) || !std::isfinite(e->y)) continue;
        double dx = 0, dy = 0;
        r.display.to_degrees(e->x, e->y, dx, dy);
        sx += dx;
        sy += dy;
        ++n;
    }
    if (n > 0) {
        out.x = sx / n;
        out.y = sy / n;
        out.valid = true;
    }
    return out;
}

double seconds(const Recording& r, size_t i) {
    return static_cast<double>(r.samples[i].device_ticks - r.samples[0].device_ticks) * 1e-6;
}

namespace detail {

gaze::DisplayGeometry degree_display() {
    // A flat plane at 1 m spanning +-60 deg: to_degrees(to_normalized(a)) == a (atan/tan).
    gaze::DisplayGeometry d;
    d.distance_m = 1.0;
    d.width_m = d.height_m = 2.0 * std::tan(60.0 * 0.017453292519943295);
    d.width_px = d.height_px = 4096;
    return d;
}

double rate_from_steps(const std::vector<double>& t_s, double fallback_hz) {
    std::vector<double> steps;
    for (size_t i = 1; i < t_s.size(); ++i) {
        const double d = t_s[i] - t_s[i - 1];
        if (std::isfinite(d) && d > 0) steps.push_back(d);
    }
    if (steps.size() < 10) return fallback_hz;
    auto mid = steps.begin() + static_cast<long>(steps.size() / 2);
    std::nth_element(steps.begin(), mid, steps.end());
    return 1.0 / *mid;
}

void set_time(gaze::RawSample& s, double t_s) {
    s.device_ticks = static_cast<uint64_t>(std::llround(std::max(0.0, t_s) * 1e6));
    s.t_receive_ns = std::llround(std::max(0.0, t_s) * 1e9);
}

}  // namespace detail

namespace {

// Loaders by what their folder looks like; the first that recognizes a folder owns it.
struct Loader {
    const char* dataset;
    bool (*recognizes)(const fs::path&);
    Result<Dataset> (*load)(const std::string&);
};

bool has_file(const fs::path& dir, auto&& pred) {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec)) {
        if (e.is_regular_file(ec) && pred(e.path())) return true;
    }
    return false;
}

bool is_lund(const fs::path& dir) {
    return has_file(dir, [](const fs::path& p) {
        return p.extension() == ".csv" && detail::is_lund2013_csv(p.string());
    });
}
bool is_hooge(const fs::path& dir) {
    std::error_code ec;
    return fs::is_directory(dir / "data" / "ETdata", ec) &&
           fs::is_directory(dir / "data" / "coderSettings", ec);
}
bool is_uneye(const fs::path& dir) {
    return has_file(dir, [](const fs::path& p) {
        return p.extension() == ".csv" &&
               p.filename().string().find("_Labels_") != std::string::npos;
    });
}

bool is_arff(const fs::path& dir) { return detail::dir_has_format(dir.string(), ".arff", "arff"); }
bool is_asc(const fs::path& dir) {
    return detail::dir_has_format(dir.string(), ".asc", "eyelink-asc");
}

const Loader kLoaders[] = {
    {"hooge2018", &is_hooge, &load_hooge2018}, {"uneye", &is_uneye, &load_uneye},
    {"lund2013", &is_lund, &load_lund2013},    {"gazecom", &is_arff, &load_arff},
    {"eyelink", &is_asc, &load_asc_dir},
};

void walk(const fs::path& dir, int depth, DatasetSet& out) {
    // A folder may look like several kinds (ASC files next to an unlabelled ARFF): the first
    // loader that reads it owns it.
    std::vector<std::string> failed;
    for (const Loader& l : kLoaders) {
        if (!l.recognizes(dir)) continue;
        auto d = l.load(dir.string());
        if (!d) {
            failed.push_back(d.error().message);
            continue;
        }
        auto same = std::find_if(out.datasets.begin(), out.datasets.end(),
                                 [&](const Dataset& x) { return x.name == d->name; });
        if (same == out.datasets.end()) {
            out.datasets.push_back(std::move(*d));
        } else {  // a second folder of the same kind: one dataset
            for (auto& r : d->recordings) same->recordings.push_back(std::move(r));
            same->notes.insert(same->notes.end(), d->notes.begin(), d->notes.end());
        }
        return;
    }
    // A folder that looked like a dataset but was none (raw gaze beside the labelled set's own
    // folder) is noted, and its subfolders are still searched.
    for (const auto& f : failed) out.notes.push_back(f + " (skipped)");
    if (depth <= 0) return;
    std::vector<fs::path> subdirs;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec)) {
        if (e.is_directory(ec)) subdirs.push_back(e.path());
    }
    std::sort(subdirs.begin(), subdirs.end());
    for (const auto& s : subdirs) walk(s, depth - 1, out);
}

}  // namespace

Result<DatasetSet> load_datasets(const std::string& root) {
    std::error_code ec;
    if (!fs::is_directory(root, ec)) return Error{root + ": not a directory"};
    DatasetSet out;
    // Deep enough for a set kept in split folders below its own (root/labelled/<set>/
    // ground_truth/test/*.arff is four below root); folders that hold a dataset end the walk.
    constexpr int kMaxDepth = 6;
    walk(fs::path(root), kMaxDepth, out);
    if (out.datasets.empty()) {
        std::string why = root +
                          ": no labelled dataset found (lund2013 CSV, Hooge 2018, U'n'Eye, "
                          "labelled ARFF, EyeLink ASC)";
        for (const auto& n : out.notes) why += "\n  " + n;
        return Error{why};
    }
    // A fixed order, whatever the directory walk found first: the table and the fits depend on it.
    std::sort(out.datasets.begin(), out.datasets.end(),
              [](const Dataset& a, const Dataset& b) { return a.name < b.name; });
    return out;
}

void decimate(Recording& r, size_t factor) {
    if (factor <= 1) return;
    auto keep_every = [factor](auto& v) {
        size_t kept = 0;
        for (size_t i = 0; i < v.size(); i += factor) v[kept++] = v[i];
        v.resize(kept);
    };
    keep_every(r.samples);
    for (auto& [coder, labels] : r.coders) keep_every(labels);
    r.rate_hz /= static_cast<double>(factor);
}

void upsample(Recording& r, size_t factor) {
    if (factor <= 1 || r.samples.size() < 2) return;
    const size_t n = r.samples.size();
    const size_t m = (n - 1) * factor + 1;
    std::vector<gaze::RawSample> samples;
    samples.reserve(m);
    std::map<std::string, std::vector<gaze::Event>> coders;
    for (const auto& [coder, labels] : r.coders) coders[coder].reserve(m);
    auto lerp = [](auto a, auto b, double f) { return a + (b - a) * f; };
    for (size_t i = 0; i < n; ++i) {
        const gaze::RawSample& a = r.samples[i];
        samples.push_back(a);
        for (auto& [coder, labels] : r.coders) coders[coder].push_back(labels[i]);
        if (i + 1 == n) break;
        const gaze::RawSample& b = r.samples[i + 1];
        for (size_t k = 1; k < factor; ++k) {
            const double f = static_cast<double>(k) / static_cast<double>(factor);
            const bool nearer_a = 2 * k < factor;
            gaze::RawSample s = nearer_a ? a : b;
            s.device_ticks =
                a.device_ticks + static_cast<uint64_t>(std::llround(
                                     f * static_cast<double>(b.device_ticks - a.device_ticks)));
            s.t_receive_ns = a.t_receive_ns +
                             std::llround(f * static_cast<double>(b.t_receive_ns - a.t_receive_ns));
            for (auto [e, ea, eb] : {std::tuple{&s.left, &a.left, &b.left},
                                     std::tuple{&s.right, &a.right, &b.right}}) {
                if (!ea->valid || !eb->valid) continue;  // the nearer sample's eye, as copied
                e->x = lerp(ea->x, eb->x, f);
                e->y = lerp(ea->y, eb->y, f);
                e->pupil_mm = lerp(ea->pupil_mm, eb->pupil_mm, f);
            }
            samples.push_back(s);
            for (auto& [coder, labels] : r.coders) {
                coders[coder].push_back(labels[nearer_a ? i : i + 1]);
            }
        }
    }
    r.samples = std::move(samples);
    r.coders = std::move(coders);
    r.rate_hz *= static_cast<double>(factor);
}

void add_white_noise(Recording& r, double sd_deg, uint64_t seed) {
    if (!(sd_deg > 0.0)) return;
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> normal(0.0, sd_deg);
    for (auto& s : r.samples) {
        const double nx = normal(rng), ny = normal(rng);
        for (gaze::EyeSample* e : {&s.left, &s.right}) {
            if (!e->valid) continue;
            double x_deg, y_deg;
            r.display.to_degrees(e->x, e->y, x_deg, y_deg);
            r.display.to_normalized(x_deg + nx, y_deg + ny, e->x, e->y);
        }
    }
}

}  // namespace fovea::eval
