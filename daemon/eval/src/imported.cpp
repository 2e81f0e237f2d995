// Datasets read through fovea::import (the one owner of the lund2013, ARFF and EyeLink ASC
// parsers): lund2013 (two coders' files per recording), GazeCom-style ARFF (label columns are
// coders) and EyeLink ASC (the tracker's online parser events are one more "coder", per eye).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <utility>

#include "fovea/eval/dataset.hpp"
#include "fovea/import/reader.hpp"
#include "loaders.hpp"

namespace fovea::eval {

namespace {

namespace fs = std::filesystem;
using gaze::Event;

struct Imported {
    import::SourceInfo info;
    std::vector<gaze::RawSample> samples;
    std::vector<double> time_s;
    std::vector<std::vector<Event>> labels;  // per label column
    std::vector<import::LabelledEvent> events;
    uint64_t skipped = 0;
    std::vector<std::string> issues;
};

Result<Imported> read_all(const std::string& path) {
    auto r = import::open(path);
    if (!r) return r.error();
    import::Reader& reader = **r;
    Imported out;
    out.info = reader.info();
    out.labels.resize(out.info.label_columns.size());
    for (auto it = reader.next(); it != import::Item::kEnd; it = reader.next()) {
        if (it == import::Item::kSample) {
            const import::Sample& s = reader.sample();
            out.samples.push_back(s.raw);
            out.time_s.push_back(s.time_s);
            for (size_t k = 0; k < out.labels.size(); ++k) out.labels[k].push_back(s.labels[k]);
        } else if (it == import::Item::kEvent) {
            out.events.push_back(reader.event());
        }
    }
    if (!reader.error().empty()) return make_error(reader.error());
    out.skipped = reader.stats().skipped;
    out.issues = reader.stats().issues;
    if (out.samples.size() < 10) return make_error(path + ": fewer than 10 samples");
    return out;
}

// Samples from t = 0 at the first sample, µs device ticks, display from the file.
Recording recording_of(const Imported& im, const std::string& name) {
    Recording r;
    r.name = name;
    r.stimulus = "all";
    r.subject = name;
    r.display = im.info.screen.resolve(gaze::DisplayGeometry{});
    r.binocular = im.info.binocular;
    r.samples = im.samples;
    const double t0 = im.time_s.front();
    std::vector<double> t(im.time_s.size());
    for (size_t i = 0; i < t.size(); ++i) t[i] = im.time_s[i] - t0;
    r.rate_hz = detail::rate_from_steps(t, im.info.rate_hz() > 0 ? im.info.rate_hz() : 500.0);
    for (size_t i = 0; i < t.size(); ++i) {
        detail::set_time(r.samples[i], t[i]);
        r.samples[i].truth = Event::kUnknown;
    }
    return r;
}

void note_issues(const Imported& im, const std::string& name, std::vector<std::string>& notes) {
    if (im.skipped) {
        notes.push_back(name + ": " + std::to_string(im.skipped) + " malformed rows skipped" +
                        (im.issues.empty() ? "" : " (first: " + im.issues.front() + ")"));
    }
}

std::vector<fs::path> files_with(const std::string& dir, const char* ext) {
    std::vector<fs::path> out;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec))
        if (e.is_regular_file(ec) && e.path().extension() == ext) out.push_back(e.path());
    std::sort(out.begin(), out.end());
    return out;
}

// The tracker's events as per-sample labels of one eye: a sample inside [start, end] (its own
// stamp, end = the event's last sample) takes the event. EyeLink wraps every blink in a
// "blink saccade", the lid's movement over the pupil taken for the eye's (SR Research; its Data
// Viewer merges them into the blink): a saccade holding a blink of the same eye is blink.
std::vector<Event> labels_from_events(const Imported& im, import::Eye eye) {
    std::vector<Event> out(im.time_s.size(), Event::kUnknown);
    const double half = 0.25 / std::max(1.0, im.info.rate_hz());
    const auto mine = [&](const import::LabelledEvent& e) {
        return e.eye == eye || e.eye == import::Eye::kBoth;
    };
    std::vector<std::pair<double, double>> blinks;  // [start, end], by start
    for (const auto& e : im.events)
        if (mine(e) && e.type == Event::kBlink) blinks.emplace_back(e.start_s, e.end_s);
    std::sort(blinks.begin(), blinks.end());
    const auto wraps_blink = [&](const import::LabelledEvent& s) {
        auto b = std::lower_bound(blinks.begin(), blinks.end(), std::make_pair(s.start_s, -1e300));
        return b != blinks.end() && b->second <= s.end_s;
    };
    for (int pass = 0; pass < 2; ++pass) {
        for (const auto& e : im.events) {
            if (!mine(e)) continue;
            if ((e.type == Event::kBlink) != (pass == 1)) continue;
            const Event label =
                e.type == Event::kSaccade && wraps_blink(e) ? Event::kBlink : e.type;
            auto lo = std::lower_bound(im.time_s.begin(), im.time_s.end(), e.start_s - half);
            for (auto k = lo; k != im.time_s.end() && *k <= e.end_s + half; ++k)
                out[static_cast<size_t>(k - im.time_s.begin())] = label;
        }
    }
    return out;
}

// The files of a folder that could not be read: each is a note, and when none could, the
// folder's error says why the first one failed.
struct Skipped {
    std::string first;
    size_t count = 0;
    void add(const std::string& why, std::vector<std::string>& notes) {
        if (count++ == 0) first = why;
        notes.push_back(why + " (skipped)");
    }
    Error none_read(const std::string& what) const {
        if (count == 0) return Error{what};
        return Error{what + ": " + first +
                     (count > 1 ? " (and " + std::to_string(count - 1) + " more)" : "")};
    }
};

}  // namespace

Result<Dataset> load_lund2013(const std::string& dir) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) return make_error(dir + ": not a directory");
    Dataset d;
    d.name = "lund2013";
    d.path = dir;
    d.scheme = {Event::kFixation, Event::kSaccade, Event::kPso, Event::kPursuit, Event::kBlink};
    struct CoderFile {
        std::string coder;
        Imported data;
    };
    std::map<std::pair<std::string, std::string>, std::vector<CoderFile>> by_recording;
    Skipped skipped;
    for (const auto& p : files_with(dir, ".csv")) {
        const std::string file = p.filename().string();
        if (file.rfind("fix_by_", 0) == 0) {
            d.notes.push_back(file +
                              ": skipped (a later correction; the paper scored the original "
                              "labels)");
            continue;
        }
        auto im = read_all(p.string());
        if (!im) {
            skipped.add(im.error().message, d.notes);
            continue;
        }
        if (im->info.format != import::Format::kLund2013 || im->labels.empty()) {
            skipped.add(file + ": not a labelled lund2013 CSV", d.notes);
            continue;
        }
        note_issues(*im, file, d.notes);
        // "<stimulus>__<recording>_<coder>.csv"
        const std::string stem = p.stem().string();
        const std::string stimulus = stem.find("img") != std::string::npos     ? "img"
                                     : stem.find("dots") != std::string::npos  ? "dots"
                                     : stem.find("video") != std::string::npos ? "video"
                                                                               : "all";
        const auto us = stem.rfind('_');
        std::string rec = us == std::string::npos ? stem : stem.substr(0, us);
        if (const auto dd = rec.find("__"); dd != std::string::npos) rec = rec.substr(dd + 2);
        by_recording[{stimulus, rec}].push_back(
            {us == std::string::npos ? "?" : stem.substr(us + 1), std::move(*im)});
    }
    if (by_recording.empty()) return skipped.none_read(dir + ": no labelled CSV files");
    for (auto& [key, files] : by_recording) {
        // The coders' files of a recording differ by 1-3 samples: aligned from the start,
        // truncated to the shortest; the samples are the first coder's.
        size_t n = files[0].data.samples.size();
        for (const auto& f : files) n = std::min(n, f.data.samples.size());
        Recording r = recording_of(files[0].data, key.second);
        r.stimulus = key.first;
        r.subject = r.name.substr(0, r.name.find('_'));
        r.samples.resize(n);
        for (const auto& f : files) {
            const auto& l = f.data.labels[0];
            r.coders[f.coder].assign(l.begin(), l.begin() + static_cast<long>(n));
        }
        d.recordings.push_back(std::move(r));
    }
    return d;
}

Result<Dataset> load_arff(const std::string& dir) {
    Dataset d;
    d.name = "gazecom";
    d.path = dir;
    d.scheme = {Event::kFixation, Event::kSaccade, Event::kPursuit};
    Skipped skipped;
    for (const auto& p : files_with(dir, ".arff")) {
        auto im = read_all(p.string());
        if (!im) {
            skipped.add(im.error().message, d.notes);
            continue;
        }
        if (im->info.label_columns.empty()) continue;  // gaze without labels: nothing to score
        note_issues(*im, p.filename().string(), d.notes);
        std::string name = p.stem().string();
        if (const auto dot = name.find('.'); dot != std::string::npos) name = name.substr(0, dot);
        Recording r = recording_of(*im, name);
        r.subject = name.substr(0, name.find('_'));
        for (size_t k = 0; k < im->labels.size(); ++k)
            r.coders[im->info.label_columns[k]] = im->labels[k];
        d.recordings.push_back(std::move(r));
    }
    if (d.recordings.empty()) return skipped.none_read(dir + ": no labelled ARFF file");
    return d;
}

Result<Recording> load_asc(const std::string& path, std::vector<std::string>* notes) {
    auto im = read_all(path);
    if (!im) return im.error();
    if (notes) note_issues(*im, fs::path(path).filename().string(), *notes);
    Recording r = recording_of(*im, fs::path(path).stem().string());
    r.stimulus = fs::path(path).parent_path().filename().string();  // the source
    bool left = false, right = false;
    for (const auto& e : im->events) {
        left = left || e.eye == import::Eye::kLeft;
        right = right || e.eye == import::Eye::kRight;
    }
    if (left) r.coders["eyelink-left"] = labels_from_events(*im, import::Eye::kLeft);
    if (right) r.coders["eyelink-right"] = labels_from_events(*im, import::Eye::kRight);
    if (r.coders.empty()) return make_error(path + ": no EFIX/ESACC/EBLINK events to compare with");
    return r;
}

Dataset eyelink_parser_dataset(std::string name, std::string path) {
    Dataset d;
    d.name = std::move(name);
    d.path = std::move(path);
    d.human = false;
    d.scheme = {Event::kFixation, Event::kSaccade, Event::kBlink};
    d.pso_without_label = Event::kFixation;
    return d;
}

Result<Dataset> load_asc_dir(const std::string& dir) {
    Dataset d = eyelink_parser_dataset("eyelink", dir);
    Skipped skipped;
    for (const auto& p : files_with(dir, ".asc")) {
        auto r = load_asc(p.string(), &d.notes);
        if (!r) {
            skipped.add(r.error().message, d.notes);
            continue;
        }
        d.recordings.push_back(std::move(*r));
    }
    if (d.recordings.empty())
        return skipped.none_read(dir + ": no EyeLink ASC file with parser events");
    return d;
}

namespace detail {

bool is_lund2013_csv(const std::string& path) {
    auto f = import::detect(path);
    return f && *f == import::Format::kLund2013;
}

bool dir_has_format(const std::string& dir, const char* ext, const char* format_name) {
    const auto format = import::format_from_name(format_name);
    for (const auto& p : files_with(dir, ext)) {
        auto f = import::detect(p.string());
        if (f && format && *f == *format) return true;
    }
    return false;
}

}  // namespace detail

}  // namespace fovea::eval
