// `fovea eval-events DIR [--mode online|offline] [--json] [--cv dataset] [--detector K=V]...
// [--decimate N] [--upsample N] [--add-noise-deg SD]`:
// agreement of the gaze chain's events with hand-labelled recordings, every dataset found under DIR
// (one dataset's folder or ../shared/data) scored on its own: Cohen's kappa per sample and event
// (Andersson et al. 2017), sample F1 and event F1 (IoU >= 0.5; Hooge et al. 2018, Startsev et al.
// 2019), per stimulus type and coder, next to the coders' agreement with each other. `--cv dataset`
// refits the detector's fitted constants without each dataset and scores it with them (held out)
// beside the shipped constants (in sample). `--decimate N` scores every recording at 1/N of its
// rate (every N-th sample and label), as a slower tracker would have seen the same eye movements;
// `--upsample N` at N x its rate (linear interpolation: the rate handling up to 2000 Hz);
// `--add-noise-deg SD` through a noisier one.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>

#include "command.hpp"
#include "fovea/eval/cv.hpp"
#include "fovea/eval/dataset.hpp"
#include "fovea/eval/detect.hpp"
#include "fovea/eval/detector_params.hpp"
#include "fovea/eval/scoring.hpp"

namespace fovea::cli {
namespace {

struct Options {
    std::string dir;
    std::string mode = "offline";
    std::string cv;
    std::string against;
    bool json = false;
    bool per_file = false;
    std::string dump_dir;
    double lookahead_ms = gaze::DetectorParams{}.lookahead_s * 1e3;
    std::vector<std::string> detector;  // KEY=VALUE overrides of DetectorParams
    std::vector<std::string> cv_pin;    // fitted constants the folds keep at the shipped value
    int threads = 0;
    size_t decimate = 1;         // keep every N-th sample: the same eye movements at rate / N
    size_t upsample = 1;         // interpolate N - 1 samples into every interval: at rate x N
    double add_noise_deg = 0.0;  // white noise per axis: the same eye movements, noisier tracker
};

struct Published {
    double best[3];
    const char* best_name;
};

// lund2013: the best algorithm per event in Andersson et al. (2017), ../shared/data/README.md.
const std::map<std::string, Published>& lund_published() {
    static const std::map<std::string, Published> p = {
        {"fixation", {{.67, .03, .14}, "I-VT/BIT"}},
        {"saccade", {{.81, .75, .81}, "LNS"}},
        {"pso", {{.64, .59, .63}, "LNS"}},
    };
    return p;
}

double published_best(const std::string& dataset, const std::string& stimulus,
                      const std::string& event) {
    if (dataset != "lund2013") return NAN;
    const int si = stimulus == "img" ? 0 : stimulus == "dots" ? 1 : stimulus == "video" ? 2 : -1;
    const auto it = lund_published().find(event);
    return si < 0 || it == lund_published().end() ? NAN : it->second.best[si];
}

nlohmann::json number(double v) {
    return std::isfinite(v) ? nlohmann::json(std::round(v * 1e4) / 1e4) : nlohmann::json(nullptr);
}

using Metric = double (eval::Cell::*)() const;
nlohmann::json table(const eval::ScoreTable& t, Metric m, const char* stacked_name) {
    nlohmann::json j = nlohmann::json::object();
    for (const auto& [stimulus, events] : t)
        for (const auto& [event, coders] : events)
            for (const auto& [coder, cell] : coders)
                j[stimulus][event][coder == eval::kAllCoders ? stacked_name : coder] =
                    number((cell.*m)());
    return j;
}

nlohmann::json scores_json(const eval::DatasetScore& s) {
    return {{"kappa", table(s.cells, &eval::Cell::kappa, eval::kAllCoders)},
            {"f1_sample", table(s.cells, &eval::Cell::f1_sample, eval::kAllCoders)},
            {"f1_event", table(s.cells, &eval::Cell::f1_event, eval::kAllCoders)}};
}

nlohmann::json coders_json(const eval::CoderTable& t) {
    nlohmann::json j = nlohmann::json::object();
    for (const auto& [stimulus, events] : t) {
        for (const auto& [event, a] : events) {
            j[stimulus][event] = {
                {"kappa", number(a.kappa.mean)},       {"kappa_min", number(a.kappa.min)},
                {"kappa_max", number(a.kappa.max)},    {"f1_sample", number(a.f1_sample.mean)},
                {"f1_event", number(a.f1_event.mean)}, {"pairs", a.kappa.pairs}};
        }
    }
    return j;
}

// One CSV per recording (index, detected event, each coder's label; event codes as in the
// data README) for looking at where the detector and the coders disagree. x/y are pixels of
// the recording's display (degree sources: a 4096-px plane spanning +-60 deg).
bool dump_detections(const eval::Dataset& d, const std::vector<std::vector<gaze::Event>>& det,
                     const std::string& dir) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    for (size_t r = 0; r < d.recordings.size(); ++r) {
        const auto& rec = d.recordings[r];
        const std::string path = dir + "/" + rec.stimulus + "__" + rec.name + ".csv";
        std::FILE* f = std::fopen(path.c_str(), "w");
        if (!f) {
            std::fprintf(stderr, "eval-events: cannot write %s\n", path.c_str());
            return false;
        }
        std::fprintf(f, "i,t_s,x_px,y_px,det");
        for (const auto& [coder, labels] : rec.coders) std::fprintf(f, ",%s", coder.c_str());
        std::fprintf(f, "\n");
        for (size_t i = 0; i < rec.samples.size() && i < det[r].size(); ++i) {
            const auto& s = rec.samples[i];
            std::fprintf(f, "%zu,%.6f,%.2f,%.2f,%d", i, eval::seconds(rec, i),
                         s.left.valid ? s.left.x * rec.display.width_px : 0.0,
                         s.left.valid ? s.left.y * rec.display.height_px : 0.0,
                         static_cast<int>(det[r][i]));
            for (const auto& [coder, labels] : rec.coders) {
                std::fprintf(f, ",%d", static_cast<int>(labels[i]));
            }
            std::fprintf(f, "\n");
        }
        std::fclose(f);
    }
    return true;
}

// Kappa against all coders stacked, per recording: which files drive a stimulus' score.
void print_per_file(const eval::Dataset& d, const std::vector<std::vector<gaze::Event>>& det) {
    std::printf("%-10s %-6s %-28s", "dataset", "stim", "recording");
    for (gaze::Event e : d.scheme) std::printf(" %8s", eval::event_name(e));
    std::printf("\n");
    for (size_t r = 0; r < d.recordings.size(); ++r) {
        eval::Dataset one = d;
        one.recordings = {d.recordings[r]};
        const eval::DatasetScore s = eval::score(one, {det[r]});
        const auto& rec = d.recordings[r];
        std::printf("%-10s %-6s %-28s", d.name.c_str(), rec.stimulus.c_str(), rec.name.c_str());
        for (gaze::Event e : d.scheme) {
            const double k =
                s.cells.at(rec.stimulus).at(eval::event_name(e)).at(eval::kAllCoders).kappa();
            if (std::isfinite(k)) {
                std::printf(" %8.3f", k);
            } else {
                std::printf(" %8s", "-");
            }
        }
        std::printf("\n");
    }
}

const char* cell(double v) {
    static char buf[16][16];
    static int slot = 0;
    char* b = buf[slot++ % 16];
    if (std::isfinite(v)) {
        std::snprintf(b, 16, "%6.3f", v);
    } else {
        std::snprintf(b, 16, "%6s", "-");
    }
    return b;
}

// The table: one row per dataset x stimulus x event x coder (and all coders stacked).
void print_table(const eval::Dataset& d, const eval::DatasetScore& in,
                 const eval::DatasetScore* held_out) {
    const eval::CoderTable humans = eval::coder_agreement(d);
    std::printf("\n%s: %zu recordings, %zu samples%s\n", d.name.c_str(), d.recordings.size(),
                in.samples, d.human ? "" : " (labels from a peer algorithm: scored, never fitted)");
    int sw = 6, cw = 8;  // column widths: stimulus, coder
    for (const auto& [stimulus, events] : in.cells) {
        sw = std::max(sw, static_cast<int>(stimulus.size()));
        for (const auto& [event, coders] : events)
            for (const auto& [coder, c] : coders) cw = std::max(cw, static_cast<int>(coder.size()));
    }
    std::printf("%-*s %-9s %-*s %6s %6s %6s", sw, "stim", "event", cw, "coder", "kappa", "F1smp",
                "F1evt");
    if (held_out) std::printf(" | %6s %6s %6s", "kappa", "F1smp", "F1evt");
    std::printf(" | %6s %6s %s\n", d.human ? "humans" : "peers", "best",
                held_out ? "(left: in sample, right: held out)"
                         : "(humans/peers: mean coder-vs-coder kappa)");
    for (const auto& [stimulus, events] : in.cells) {
        for (const auto& [event, coders] : events) {
            double human = NAN;
            if (auto s = humans.find(stimulus); s != humans.end())
                if (auto e = s->second.find(event); e != s->second.end())
                    human = e->second.kappa.mean;
            for (const auto& [coder, c] : coders) {
                std::printf("%-*s %-9s %-*s %s %s %s", sw, stimulus.c_str(), event.c_str(), cw,
                            coder.c_str(), cell(c.kappa()), cell(c.f1_sample()),
                            cell(c.f1_event()));
                if (held_out) {
                    const eval::Cell& h = held_out->cells.at(stimulus).at(event).at(coder);
                    std::printf(" | %s %s %s", cell(h.kappa()), cell(h.f1_sample()),
                                cell(h.f1_event()));
                }
                const bool all = coder == eval::kAllCoders;
                std::printf(" | %s %s\n", cell(all ? human : NAN),
                            cell(all ? published_best(d.name, stimulus, event) : NAN));
            }
        }
    }
    for (const auto& n : d.notes) std::fprintf(stderr, "note: %s: %s\n", d.name.c_str(), n.c_str());
}

// `--against eyelink FILE.asc|DIR`: the detector against EyeLink's own online parser on the
// same samples, one table row group per ASC file (stimulus column = source/file).
Result<eval::Dataset> peer_dataset(const std::string& path) {
    std::vector<std::string> files;
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) {
        for (const auto& e : std::filesystem::recursive_directory_iterator(path, ec))
            if (e.is_regular_file(ec) && e.path().extension() == ".asc")
                files.push_back(e.path().string());
        std::sort(files.begin(), files.end());
    } else {
        files.push_back(path);
    }
    eval::Dataset d = eval::eyelink_parser_dataset("eyelink", path);
    for (const auto& f : files) {
        auto r = eval::load_asc(f, &d.notes);
        if (!r) {
            d.notes.push_back(r.error().message + " (skipped)");
            continue;
        }
        r->stimulus = r->stimulus + "/" + r->name;
        d.recordings.push_back(std::move(*r));
    }
    if (d.recordings.empty()) return make_error(path + ": no EyeLink ASC file with parser events");
    return d;
}

int run(const Options& o) {
    gaze::DetectorMode mode;
    if (o.mode == "online") {
        mode = gaze::DetectorMode::kOnline;
    } else if (o.mode == "offline") {
        mode = gaze::DetectorMode::kOffline;
    } else {
        std::fprintf(stderr, "eval-events: --mode must be online or offline, not '%s'\n",
                     o.mode.c_str());
        return 2;
    }
    if (!o.cv.empty() && o.cv != "dataset") {
        std::fprintf(stderr,
                     "eval-events: --cv takes 'dataset' (leave one dataset out), not '%s'\n",
                     o.cv.c_str());
        return 2;
    }
    if (!(o.lookahead_ms > 0) || o.lookahead_ms > 10000) {
        std::fprintf(stderr, "eval-events: --lookahead-ms must be in (0, 10000]\n");
        return 2;
    }
    if (!o.against.empty() && o.against != "eyelink") {
        std::fprintf(stderr,
                     "eval-events: --against takes 'eyelink' (its online parser), not '%s'\n",
                     o.against.c_str());
        return 2;
    }
    if (!o.against.empty() && !o.cv.empty()) {
        std::fprintf(stderr, "eval-events: --against and --cv do not combine\n");
        return 2;
    }
    Result<eval::DatasetSet> set = eval::DatasetSet{};
    if (!o.against.empty()) {
        auto peer = peer_dataset(o.dir);
        if (!peer) {
            std::fprintf(stderr, "eval-events: %s\n", peer.error().message.c_str());
            return 1;
        }
        set->datasets.push_back(std::move(*peer));
    } else {
        set = eval::load_datasets(o.dir);
    }
    if (!set) {
        std::fprintf(stderr, "eval-events: %s\n", set.error().message.c_str());
        return 1;
    }
    for (const auto& n : set->notes) std::fprintf(stderr, "note: %s\n", n.c_str());
    for (auto& d : set->datasets) {
        uint64_t seed = 1;  // one stream per recording, the same on every run
        for (auto& r : d.recordings) {
            eval::decimate(r, o.decimate);
            eval::upsample(r, o.upsample);
            eval::add_white_noise(r, o.add_noise_deg, seed++);
        }
    }
    gaze::DetectorParams params;
    params.lookahead_s = o.lookahead_ms * 1e-3;
    for (const std::string& a : o.detector) {
        if (auto r = eval::set_detector_param(params, a); !r) {
            std::fprintf(stderr, "eval-events: %s\n", r.error().message.c_str());
            return 2;
        }
    }
    const int threads = o.threads > 0
                            ? o.threads
                            : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    const eval::DetectFn detect = [mode](const eval::Recording& r, const gaze::DetectorParams& p) {
        return eval::detect(r, mode, p);
    };

    std::vector<eval::DatasetScore> in_sample(set->datasets.size());
    std::vector<const eval::FoldResult*> folds(set->datasets.size(), nullptr);
    eval::CvResult cv;
    if (!o.cv.empty()) {
        cv = eval::run_cv(set->datasets, params, detect, threads, o.cv_pin);
        for (size_t d = 0; d < set->datasets.size(); ++d) {
            folds[d] = &cv.folds[d];
            in_sample[d] = cv.folds[d].in_sample;
        }
    }
    const bool several = set->datasets.size() > 1;
    for (size_t d = 0; d < set->datasets.size(); ++d) {
        const eval::Dataset& ds = set->datasets[d];
        if (!o.cv.empty() && o.dump_dir.empty() && !o.per_file) continue;
        const auto det = eval::detect_all(ds, params, detect, threads);
        if (o.cv.empty()) in_sample[d] = eval::score(ds, det);
        if (!o.dump_dir.empty() &&
            !dump_detections(ds, det, several ? o.dump_dir + "/" + ds.name : o.dump_dir)) {
            return 1;
        }
        if (o.per_file) print_per_file(ds, det);
    }

    if (o.json) {
        nlohmann::json j;
        // Today's keys: the first dataset's kappa (lund2013 when present), coders stacked as
        // "both".
        size_t primary = 0;
        for (size_t d = 0; d < set->datasets.size(); ++d)
            if (set->datasets[d].name == "lund2013") primary = d;
        j["kappa"] = table(in_sample[primary].cells, &eval::Cell::kappa, "both");
        j["samples"] = in_sample[primary].samples;
        j["mode"] = o.mode;
        for (size_t d = 0; d < set->datasets.size(); ++d) {
            const eval::Dataset& ds = set->datasets[d];
            nlohmann::json& dj = j["datasets"][ds.name];
            dj = scores_json(in_sample[d]);
            dj["samples"] = in_sample[d].samples;
            dj["recordings"] = ds.recordings.size();
            dj["human_labels"] = ds.human;
            dj["coder_agreement"] = coders_json(eval::coder_agreement(ds));
            if (folds[d]) {
                dj["held_out"] = scores_json(folds[d]->held_out);
                for (size_t t = 0; t < cv.tunables.size(); ++t)
                    dj["held_out"]["fitted"][cv.tunables[t].name] = folds[d]->fitted[t];
                dj["objective"] = number(folds[d]->in_sample_objective);
                dj["held_out"]["objective"] = number(folds[d]->held_out_objective);
            }
        }
        if (!o.cv.empty()) {
            for (size_t t = 0; t < cv.tunables.size(); ++t) {
                j["cv"]["shipped"][cv.tunables[t].name] = cv.shipped[t];
                j["cv"]["fit_all"][cv.tunables[t].name] = cv.fit_all[t];
                j["cv"]["grid"][cv.tunables[t].name] = cv.tunables[t].grid;
            }
            j["cv"]["candidates"] = cv.candidates;
            for (const auto& [name, value] : cv.pinned) j["cv"]["pinned"][name] = value;
        }
        std::printf("%s\n", j.dump().c_str());
        return 0;
    }
    std::printf(
        "eval-events: %zu datasets under %s, mode %s%s\n", set->datasets.size(), o.dir.c_str(),
        o.mode.c_str(),
        o.mode == "online"
            ? (", look-ahead " + std::to_string(static_cast<int>(o.lookahead_ms)) + " ms").c_str()
            : "");
    for (size_t d = 0; d < set->datasets.size(); ++d) {
        print_table(set->datasets[d], in_sample[d], folds[d] ? &folds[d]->held_out : nullptr);
    }
    if (!o.cv.empty()) {
        std::printf("\nleave-one-dataset-out over %zu candidates; fitted constants:%s\n",
                    cv.candidates,
                    cv.tunables.empty() && cv.pinned.empty()
                        ? " none (held out = in sample: every threshold is physiological, "
                          "statistical or measured on the recording)"
                        : "");
        for (size_t t = 0; t < cv.tunables.size(); ++t) {
            std::printf("  %-22s shipped %g, fit on all %g;", cv.tunables[t].name.c_str(),
                        cv.shipped[t], cv.fit_all[t]);
            for (const auto& f : cv.folds)
                std::printf(" w/o %s %g", f.dataset.c_str(), f.fitted[t]);
            std::printf("\n");
        }
        for (const auto& [name, value] : cv.pinned)
            std::printf("  %-22s pinned %g in every fold (--cv-pin)\n", name.c_str(), value);
    }
    return 0;
}

void setup(CLI::App& app) {
    auto o = std::make_shared<Options>();
    app.add_option("dir", o->dir,
                   "A labelled dataset's folder, or a folder holding several (../shared/data)")
        ->required();
    app.add_option("--mode", o->mode, "Detector mode: offline (whole recording) or online");
    app.add_option("--cv", o->cv,
                   "'dataset': refit the fitted constants leaving each dataset out and score it "
                   "held out");
    app.add_option("--against", o->against,
                   "'eyelink': score against EyeLink's online parser events in DIR (an ASC file or "
                   "a folder of them) instead of people's labels");
    app.add_flag("--json", o->json, "Print one JSON object");
    app.add_flag("--per-file", o->per_file, "Also print kappa (all coders) per recording");
    app.add_option("--dump", o->dump_dir,
                   "Write one CSV per recording (detected event and coder labels) to this "
                   "directory");
    app.add_option("--lookahead-ms", o->lookahead_ms,
                   "Online mode: look-ahead bound in ms (the daemon's setting)");
    app.add_option("--detector", o->detector,
                   "KEY=VALUE: override one detector constant for this run (repeatable; "
                   "with --cv it replaces the shipped value that 'in sample' scores)");
    app.add_option("--cv-pin", o->cv_pin,
                   "KEY: with --cv, do not fit this constant; every fold keeps the shipped "
                   "value (or --detector's) (repeatable)");
    app.add_option("--decimate", o->decimate,
                   "Keep every N-th sample (and label) of each recording: the same eye movements "
                   "as a tracker at 1/N of the rate would see them")
        ->check(CLI::PositiveNumber);
    app.add_option("--upsample", o->upsample,
                   "Interpolate N - 1 samples (linearly) into every interval of each recording, "
                   "labels from the nearer sample: the same eye movements at N x the rate (with "
                   "--add-noise-deg, through a tracker that fast)")
        ->check(CLI::PositiveNumber);
    app.add_option("--add-noise-deg", o->add_noise_deg,
                   "Add Gaussian white noise of this SD (deg, per axis) to every sample: the same "
                   "eye movements through a noisier tracker")
        ->check(CLI::NonNegativeNumber);
    app.add_option("--threads", o->threads, "Worker threads (default: one per core)");
    app.callback([o] {
        const int rc = run(*o);
        if (rc != 0) throw CLI::RuntimeError(rc);
    });
}

const Command kEvalEvents{"eval-events", "Score event detection against labelled recordings",
                          &setup};

}  // namespace
}  // namespace fovea::cli
