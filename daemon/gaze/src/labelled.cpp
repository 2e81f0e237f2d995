#include "fovea/gaze/labelled.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fovea::gaze {

namespace {

double header_value(const std::string& header, const std::string& key, int index = 0) {
    const auto pos = header.find(key + "=");
    if (pos == std::string::npos) return kNaN;
    std::string v = header.substr(pos + key.size() + 1);
    v = v.substr(0, v.find(' '));
    std::stringstream ss(v);
    std::string part;
    for (int i = 0; std::getline(ss, part, ','); ++i) {
        if (i == index) return std::strtod(part.c_str(), nullptr);
    }
    return kNaN;
}

}  // namespace

const char* event_name(Event e) {
    switch (e) {
        case Event::kFixation:
            return "fixation";
        case Event::kSaccade:
            return "saccade";
        case Event::kPso:
            return "pso";
        case Event::kPursuit:
            return "pursuit";
        case Event::kBlink:
            return "blink";
        default:
            return "undefined";
    }
}

Result<LabelledFile> load_labelled_csv(const std::string& path) {
    std::ifstream in(path);
    if (!in) return make_error("cannot open " + path);
    LabelledFile f;
    f.path = path;
    std::string header, columns, line;
    if (!std::getline(in, header) || header.rfind("#", 0) != 0) {
        return make_error(path + ": missing '# sampFreq=...' header line");
    }
    if (!std::getline(in, columns) || columns.rfind("t_us,", 0) != 0) {
        return make_error(path + ": missing column line 't_us,pupil_h,pupil_v,x_px,y_px,label'");
    }
    f.header_rate_hz = header_value(header, "sampFreq");
    const double dist = header_value(header, "viewDist_m");
    const double w_m = header_value(header, "screenDim_m", 0);
    const double h_m = header_value(header, "screenDim_m", 1);
    const double w_px = header_value(header, "screenRes_px", 0);
    const double h_px = header_value(header, "screenRes_px", 1);
    if (!(f.header_rate_hz > 0) || !(dist > 0) || !(w_m > 0) || !(h_m > 0) || !(w_px > 0) ||
        !(h_px > 0)) {
        return make_error(path + ": header lacks sampFreq/viewDist_m/screenDim_m/screenRes_px");
    }
    f.display.distance_m = dist;
    f.display.width_m = w_m;
    f.display.height_m = h_m;
    f.display.width_px = static_cast<int>(w_px);
    f.display.height_px = static_cast<int>(h_px);

    std::vector<double> stamps;
    while (std::getline(in, line)) {
        if (line.empty()) continue;
        double v[6];
        const char* p = line.c_str();
        bool ok = true;
        for (int i = 0; i < 6; ++i) {
            char* end = nullptr;
            v[i] = std::strtod(p, &end);  // accepts "nan"
            if (end == p) {
                ok = false;
                break;
            }
            p = end;
            if (i < 5) {
                if (*p != ',') {
                    ok = false;
                    break;
                }
                ++p;
            }
        }
        if (!ok || !std::isfinite(v[5])) {
            ++f.bad_rows;
            continue;
        }
        stamps.push_back(v[0]);
        f.x_px.push_back(v[3]);
        f.y_px.push_back(v[4]);
        const bool lost = !std::isfinite(v[3]) || !std::isfinite(v[4]) || (v[3] == 0 && v[4] == 0);
        f.valid.push_back(!lost);
        const int label = static_cast<int>(std::lround(v[5]));
        f.labels.push_back(label >= 1 && label <= 5 ? static_cast<Event>(label) : Event::kUnknown);
    }
    // Rate from the median timestamp step where stamps exist (six files' headers are wrong).
    std::vector<double> steps;
    for (size_t i = 1; i < stamps.size(); ++i) {
        const double d = stamps[i] - stamps[i - 1];
        if (std::isfinite(d) && d > 0) steps.push_back(d);
    }
    f.rate_hz = f.header_rate_hz;
    if (steps.size() > 10) {
        std::nth_element(steps.begin(), steps.begin() + static_cast<long>(steps.size() / 2),
                         steps.end());
        f.rate_hz = 1e6 / steps[steps.size() / 2];
    }
    f.t_s.resize(stamps.size());
    double t0 = kNaN;
    for (size_t i = 0; i < stamps.size(); ++i) {
        const bool good = std::isfinite(stamps[i]) &&
                          (i == 0 || !std::isfinite(stamps[i - 1]) || stamps[i] > stamps[i - 1]);
        if (std::isfinite(stamps[i]) && !std::isfinite(t0)) t0 = stamps[i];
        if (good && std::isfinite(t0)) {
            f.t_s[i] = (stamps[i] - t0) * 1e-6;
            if (i > 0 && f.t_s[i] <= f.t_s[i - 1]) f.t_s[i] = f.t_s[i - 1] + 1.0 / f.rate_hz;
        } else {
            if (!std::isfinite(stamps[i])) ++f.nan_timestamps;
            f.t_s[i] = i == 0 ? 0.0 : f.t_s[i - 1] + 1.0 / f.rate_hz;
        }
    }
    const std::string name = std::filesystem::path(path).stem().string();
    f.stimulus = name.find("img") != std::string::npos     ? "img"
                 : name.find("dots") != std::string::npos  ? "dots"
                 : name.find("video") != std::string::npos ? "video"
                                                           : "all";
    const auto us = name.rfind('_');
    f.coder = us == std::string::npos ? "?" : name.substr(us + 1);
    std::string rec = us == std::string::npos ? name : name.substr(0, us);
    if (const auto dd = rec.find("__"); dd != std::string::npos) rec = rec.substr(dd + 2);
    f.recording = rec;
    return f;
}

Result<LabelledSet> load_labelled_dir(const std::string& dir) {
    std::error_code ec;
    if (!std::filesystem::is_directory(dir, ec)) return make_error(dir + ": not a directory");
    std::vector<std::string> paths;
    for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
        if (entry.path().extension() == ".csv") paths.push_back(entry.path().string());
    }
    std::sort(paths.begin(), paths.end());
    LabelledSet set;
    for (const auto& p : paths) {
        const std::string name = std::filesystem::path(p).filename().string();
        if (name.rfind("fix_by_", 0) == 0) {
            set.notes.push_back(name +
                                ": skipped (a later correction; the paper scored the "
                                "original labels)");
            continue;
        }
        auto f = load_labelled_csv(p);
        if (!f) {
            set.notes.push_back(f.error().message + " (skipped)");
            continue;
        }
        set.files.push_back(std::move(*f));
    }
    if (set.files.empty()) return make_error(dir + ": no labelled CSV files");
    std::map<std::pair<std::string, std::string>, size_t> index;
    for (const auto& f : set.files) {
        const auto key = std::make_pair(f.stimulus, f.recording);
        auto it = index.find(key);
        if (it == index.end()) {
            index[key] = set.recordings.size();
            LabelledRecording r;
            r.name = f.recording;
            r.stimulus = f.stimulus;
            r.data = &f;
            r.length = f.labels.size();
            set.recordings.push_back(r);
            it = index.find(key);
        }
        LabelledRecording& r = set.recordings[it->second];
        r.coders[f.coder] = &f;
        r.length = std::min(r.length, f.labels.size());
    }
    return set;
}

std::vector<DetectorInput> detector_input(const LabelledFile& f) {
    std::vector<DetectorInput> out(f.t_s.size());
    for (size_t i = 0; i < out.size(); ++i) {
        out[i].t_s = f.t_s[i];
        out[i].valid = f.valid[i];
        if (f.valid[i]) {
            const double nx = f.x_px[i] / f.display.width_px;
            const double ny = f.y_px[i] / f.display.height_px;
            f.display.to_degrees(nx, ny, out[i].x_deg, out[i].y_deg);
        }
    }
    return out;
}

std::vector<RawSample> raw_samples(const LabelledFile& f) {
    std::vector<RawSample> out(f.t_s.size());
    for (size_t i = 0; i < out.size(); ++i) {
        RawSample& r = out[i];
        // A 64-bit microsecond counter received without latency: the clock maps 1:1.
        r.device_ticks = static_cast<uint64_t>(std::llround(f.t_s[i] * 1e6));
        r.t_receive_ns = std::llround(f.t_s[i] * 1e9);
        r.left.valid = f.valid[i];
        if (f.valid[i]) {
            r.left.x = f.x_px[i] / f.display.width_px;
            r.left.y = f.y_px[i] / f.display.height_px;
        }
        r.truth = f.labels[i];
    }
    return out;
}

std::vector<Event> run_pipeline(const LabelledFile& f, DetectorMode mode,
                                const DetectorParams& params) {
    PipelineConfig c;
    c.clock = DeviceClock{64, 1e6};
    c.display = f.display;
    c.nominal_rate_hz = f.rate_hz;
    c.detector = params;
    c.detector_mode = mode;
    c.filter = FilterKind::kOneEuro;
    if (mode == DetectorMode::kOffline) {
        const auto in = detector_input(f);
        c.offline_thresholds = EventDetector::estimate_thresholds(in, params, f.rate_hz);
    }
    Pipeline pipeline(c);
    std::vector<Event> events;
    events.reserve(f.t_s.size());
    std::vector<GazeSample> out;
    for (const auto& r : raw_samples(f)) {
        pipeline.process(r, out);
        for (const auto& g : out) events.push_back(g.event);
    }
    pipeline.flush(out);
    for (const auto& g : out) events.push_back(g.event);
    return events;
}

void Agreement::add(bool a, bool b) {
    if (a && b) {
        both += 1;
    } else if (a) {
        only_a += 1;
    } else if (b) {
        only_b += 1;
    } else {
        neither += 1;
    }
}

void Agreement::add(const Agreement& o) {
    both += o.both;
    only_a += o.only_a;
    only_b += o.only_b;
    neither += o.neither;
}

double Agreement::kappa() const {
    const double n = both + only_a + only_b + neither;
    if (n <= 0) return kNaN;
    const double po = (both + neither) / n;
    const double pa = (both + only_a) / n, pb = (both + only_b) / n;
    const double pe = pa * pb + (1 - pa) * (1 - pb);
    if (pe >= 1.0) return kNaN;
    return (po - pe) / (1 - pe);
}

EvalResult score(const LabelledSet& set, const std::vector<std::vector<Event>>& detections) {
    // counts[stimulus][event][coder]
    std::map<std::string, std::map<Event, std::map<std::string, Agreement>>> counts;
    EvalResult result;
    for (size_t r = 0; r < set.recordings.size() && r < detections.size(); ++r) {
        const auto& rec = set.recordings[r];
        const auto& det = detections[r];
        const size_t n = std::min(rec.length, det.size());
        result.samples += n;
        for (const auto& [coder, file] : rec.coders) {
            for (Event e : kScoredEvents) {
                Agreement& a = counts[rec.stimulus][e][coder];
                for (size_t i = 0; i < n; ++i) a.add(det[i] == e, file->labels[i] == e);
            }
        }
    }
    for (const auto& [stimulus, per_event] : counts) {
        for (const auto& [event, per_coder] : per_event) {
            Agreement stacked;
            auto& cell = result.kappa[stimulus][event_name(event)];
            for (const auto& [coder, a] : per_coder) {
                cell[coder] = a.kappa();
                stacked.add(a);
            }
            cell["both"] = stacked.kappa();
        }
    }
    return result;
}

}  // namespace fovea::gaze
