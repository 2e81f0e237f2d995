// `fovea eval-events DIR [--mode online|offline] [--json]`: per-sample Cohen's kappa of the
// gaze pipeline's events against hand-labelled recordings (Andersson et al. 2017 scoring).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "command.hpp"
#include "fovea/gaze/labelled.hpp"

namespace fovea::cli {
namespace {

struct Options {
    std::string dir;
    std::string mode = "offline";
    bool json = false;
    bool per_file = false;
    std::string dump_dir;
    double lookahead_ms = gaze::DetectorParams{}.lookahead_s * 1e3;
};

struct Published {
    double humans[3];
    double best[3];
    const char* best_name;
    double target[3];
};

// ../shared/data/README.md (Andersson et al. 2017) and the targets of issue 3.
const std::map<std::string, Published>& published() {
    static const std::map<std::string, Published> p = {
        {"fixation", {{.84, .65, .65}, {.67, .03, .14}, "I-VT/BIT", {.75, .55, .55}}},
        {"saccade", {{.91, .81, .87}, {.81, .75, .81}, "LNS", {.85, .78, .84}}},
        {"pso", {{.76, .62, .65}, {.64, .59, .63}, "LNS", {.65, .60, .63}}},
        {"pursuit", {{.34, .70, .66}, {NAN, NAN, NAN}, "-", {NAN, NAN, NAN}}},
        {"blink", {{.92, .77, .81}, {NAN, NAN, NAN}, "-", {NAN, NAN, NAN}}},
    };
    return p;
}

int stimulus_index(const std::string& s) {
    return s == "img" ? 0 : s == "dots" ? 1 : s == "video" ? 2 : -1;
}

nlohmann::json number(double v) {
    return std::isfinite(v) ? nlohmann::json(std::round(v * 1e4) / 1e4) : nlohmann::json(nullptr);
}

// One CSV per recording (index, detected event, each coder's label; event codes as in the
// data README) for looking at where the detector and the coders disagree.
bool dump_detections(const gaze::LabelledSet& set,
                     const std::vector<std::vector<gaze::Event>>& detections,
                     const std::string& dir) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    for (size_t r = 0; r < set.recordings.size(); ++r) {
        const auto& rec = set.recordings[r];
        const std::string path = dir + "/" + rec.stimulus + "__" + rec.name + ".csv";
        std::FILE* f = std::fopen(path.c_str(), "w");
        if (!f) {
            std::fprintf(stderr, "eval-events: cannot write %s\n", path.c_str());
            return false;
        }
        std::fprintf(f, "i,t_s,x_px,y_px,det");
        for (const auto& [coder, file] : rec.coders) std::fprintf(f, ",%s", coder.c_str());
        std::fprintf(f, "\n");
        for (size_t i = 0; i < rec.length; ++i) {
            std::fprintf(f, "%zu,%.6f,%.2f,%.2f,%d", i, rec.data->t_s[i], rec.data->x_px[i],
                         rec.data->y_px[i], static_cast<int>(detections[r][i]));
            for (const auto& [coder, file] : rec.coders) {
                std::fprintf(f, ",%d", static_cast<int>(file->labels[i]));
            }
            std::fprintf(f, "\n");
        }
        std::fclose(f);
    }
    return true;
}

// Kappa against both coders stacked, per recording: which files drive a stimulus' score.
void print_per_file(const gaze::LabelledSet& set,
                    const std::vector<std::vector<gaze::Event>>& detections) {
    std::printf("%-6s %-28s", "stim", "recording");
    for (gaze::Event e : gaze::kScoredEvents) std::printf(" %8s", gaze::event_name(e));
    std::printf("\n");
    for (size_t r = 0; r < set.recordings.size(); ++r) {
        const auto& rec = set.recordings[r];
        std::printf("%-6s %-28s", rec.stimulus.c_str(), rec.name.c_str());
        for (gaze::Event e : gaze::kScoredEvents) {
            gaze::Agreement a;
            for (const auto& [coder, file] : rec.coders) {
                for (size_t i = 0; i < rec.length; ++i) {
                    a.add(detections[r][i] == e, file->labels[i] == e);
                }
            }
            const double k = a.kappa();
            if (std::isfinite(k)) {
                std::printf(" %8.3f", k);
            } else {
                std::printf(" %8s", "-");
            }
        }
        std::printf("\n");
    }
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
    auto set = gaze::load_labelled_dir(o.dir);
    if (!set) {
        std::fprintf(stderr, "eval-events: %s\n", set.error().message.c_str());
        return 1;
    }
    if (!(o.lookahead_ms > 0) || o.lookahead_ms > 10000) {
        std::fprintf(stderr, "eval-events: --lookahead-ms must be in (0, 10000]\n");
        return 2;
    }
    gaze::DetectorParams params;
    params.lookahead_s = o.lookahead_ms * 1e-3;
    std::vector<std::vector<gaze::Event>> detections;
    for (const auto& rec : set->recordings) {
        detections.push_back(gaze::run_pipeline(*rec.data, mode, params));
    }
    const gaze::EvalResult result = gaze::score(*set, detections);
    if (!o.dump_dir.empty() && !dump_detections(*set, detections, o.dump_dir)) return 1;
    if (o.per_file) print_per_file(*set, detections);
    if (o.json) {
        nlohmann::json j;
        j["kappa"] = nlohmann::json::object();
        for (const auto& [stimulus, events] : result.kappa) {
            for (const auto& [event, coders] : events) {
                for (const auto& [coder, k] : coders)
                    j["kappa"][stimulus][event][coder] = number(k);
            }
        }
        j["samples"] = result.samples;
        std::printf("%s\n", j.dump().c_str());
        return 0;
    }
    for (const auto& n : set->notes) std::fprintf(stderr, "note: %s\n", n.c_str());
    std::printf(
        "eval-events: %zu recordings, %zu samples scored, mode %s%s\n", set->recordings.size(),
        result.samples, o.mode.c_str(),
        o.mode == "online"
            ? (", look-ahead " + std::to_string(static_cast<int>(o.lookahead_ms)) + " ms").c_str()
            : "");
    std::printf("%-6s %-9s %7s %7s %7s | %7s %7s %-9s %7s\n", "stim", "event", "MN", "RA", "both",
                "humans", "best", "(algo)", "target");
    auto cell = [](double v) {
        static char buf[8][16];
        static int slot = 0;
        char* b = buf[slot++ % 8];
        if (std::isfinite(v)) {
            std::snprintf(b, 16, "%7.3f", v);
        } else {
            std::snprintf(b, 16, "%7s", "-");
        }
        return b;
    };
    for (const auto& [stimulus, events] : result.kappa) {
        const int si = stimulus_index(stimulus);
        for (const auto& [event, coders] : events) {
            auto get = [&](const char* c) {
                auto it = coders.find(c);
                return it == coders.end() ? NAN : it->second;
            };
            const auto& p = published().at(event);
            std::printf("%-6s %-9s %s %s %s | %s %s %-9s %s\n", stimulus.c_str(), event.c_str(),
                        cell(get("MN")), cell(get("RA")), cell(get("both")),
                        cell(si >= 0 ? p.humans[si] : NAN), cell(si >= 0 ? p.best[si] : NAN),
                        p.best_name, cell(si >= 0 ? p.target[si] : NAN));
        }
    }
    return 0;
}

void setup(CLI::App& app) {
    auto o = std::make_shared<Options>();
    app.add_option("dir", o->dir, "Directory of labelled CSV files (lund2013 format)")->required();
    app.add_option("--mode", o->mode, "Detector mode: offline (whole recording) or online");
    app.add_flag("--json", o->json, "Print one JSON object");
    app.add_flag("--per-file", o->per_file, "Also print kappa (both coders) per recording");
    app.add_option("--dump", o->dump_dir,
                   "Write one CSV per recording (detected event and coder labels) to this "
                   "directory");
    app.add_option("--lookahead-ms", o->lookahead_ms,
                   "Online mode: look-ahead bound in ms (the daemon's setting)");
    app.callback([o] {
        const int rc = run(*o);
        if (rc != 0) throw CLI::RuntimeError(rc);
    });
}

const Command kEvalEvents{"eval-events", "Score event detection against labelled recordings",
                          &setup};

}  // namespace
}  // namespace fovea::cli
