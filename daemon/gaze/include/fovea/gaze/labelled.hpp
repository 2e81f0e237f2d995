// Hand-labelled recordings in the lund2013 CSV format (../shared/data/README.md) and the
// Andersson et al. (2017) scoring: per-sample Cohen's kappa, one event against all others,
// pooled over the files of a stimulus type, against each coder and both coders stacked.
// Used by `fovea eval-events`, `fovea eval-landing` and the evaluation tests.
#pragma once

#include <array>
#include <map>
#include <string>
#include <vector>

#include "fovea/gaze/pipeline.hpp"
#include "fovea/gaze/sample.hpp"
#include "fovea/result.hpp"

namespace fovea::gaze {

struct LabelledFile {
    std::string path;
    std::string recording;  // file name without stimulus prefix, coder suffix and extension
    std::string stimulus;   // img / dots / video from the name, else "all"
    std::string coder;      // MN / RA / ... from the name's last _X suffix
    double header_rate_hz = 0.0;
    double rate_hz = 0.0;  // from timestamps where present (some headers are wrong)
    DisplayGeometry display;
    std::vector<double> t_s;  // NaN stamps replaced by the nominal period
    std::vector<double> x_px, y_px;
    std::vector<bool> valid;  // (0,0) means tracking lost
    std::vector<Event> labels;
    size_t nan_timestamps = 0;
    size_t bad_rows = 0;  // unparsable rows, skipped
};

struct LabelledRecording {
    std::string name, stimulus;
    const LabelledFile* data = nullptr;                 // the samples (first coder's file)
    std::map<std::string, const LabelledFile*> coders;  // labels per coder
    size_t length = 0;  // samples scored: aligned from the start, shortest file
};

struct LabelledSet {
    std::vector<LabelledFile> files;
    std::vector<LabelledRecording> recordings;
    std::vector<std::string> notes;  // skipped files and why
};

Result<LabelledFile> load_labelled_csv(const std::string& path);
// Every *.csv in dir. Corrected re-labellings (fix_by_*) are skipped: the paper scored the
// originals.
Result<LabelledSet> load_labelled_dir(const std::string& dir);

// Convert one recording to detector input (degrees) or pipeline raw samples.
std::vector<DetectorInput> detector_input(const LabelledFile& f);
std::vector<RawSample> raw_samples(const LabelledFile& f);

// Run the full Pipeline over a recording (clock sync, filter, detector, predictor), in the
// given detector mode; returns one event per sample.
std::vector<Event> run_pipeline(const LabelledFile& f, DetectorMode mode,
                                const DetectorParams& params = {});

inline constexpr std::array<Event, 5> kScoredEvents = {Event::kFixation, Event::kSaccade,
                                                       Event::kPso, Event::kPursuit, Event::kBlink};
const char* event_name(Event e);

// 2x2 agreement counts of one event vs the rest.
struct Agreement {
    double both = 0, only_a = 0, only_b = 0, neither = 0;
    void add(bool a, bool b);
    void add(const Agreement& o);
    double kappa() const;  // NaN when undefined (no variation)
};

// kappa[stimulus][event][coder or "both"]
using KappaTable = std::map<std::string, std::map<std::string, std::map<std::string, double>>>;

struct EvalResult {
    KappaTable kappa;
    size_t samples = 0;
};
// detections[i] labels set.recordings[i]'s data file.
EvalResult score(const LabelledSet& set, const std::vector<std::vector<Event>>& detections);

}  // namespace fovea::gaze
