// Agreement of a detector with the coders, the way the datasets' authors score:
// - Cohen's kappa per sample, one event against all others, pooled over the recordings of a
//   stimulus type, against each coder and all coders stacked (Andersson et al. 2017);
// - sample F1 per event from the same counts;
// - event F1 per event: a detected event (a maximal run of one label) is a hit when it overlaps
//   a not yet matched coder event of the same label with intersection over union >= 0.5
//   (Startsev et al. 2019; Hooge et al. 2018 score events by overlap). With IoU >= 0.5 at most
//   one coder event can qualify, so the matching is unique.
// Detections are first folded onto the coders' scheme (fold_to_scheme).
//
// Thread rules: pure functions; no shared state.
#pragma once

#include <map>
#include <span>
#include <string>
#include <vector>

#include "fovea/eval/dataset.hpp"

namespace fovea::eval {

// 2x2 counts of one event (a: detector, b: coder).
struct Agreement {
    double both = 0, only_a = 0, only_b = 0, neither = 0;
    void add(bool a, bool b);
    void add(const Agreement& o);
    double kappa() const;  // NaN when undefined (no variation)
    double f1() const;     // NaN when neither side has the event
};

struct EventCounts {
    double hits = 0, detected = 0, labelled = 0;
    void add(const EventCounts& o);
    double f1() const;  // NaN when neither side has an event
};
// Event matching of one label over two aligned label sequences (added to `out`).
void count_events(std::span<const gaze::Event> detected, std::span<const gaze::Event> labelled,
                  gaze::Event e, EventCounts& out, double min_iou = 0.5);

// Detections in the coders' vocabulary. A scheme without PSO puts it where its labels do
// (Dataset::pso_without_label: the saccade it ends, or EyeLink's fixation); without pursuit, the
// slow movement between saccades is what such coders call fixation (Hooge's coders saw static
// displays); without blinks, a blink is "no event".
std::vector<gaze::Event> fold_to_scheme(std::span<const gaze::Event> detected,
                                        const Dataset& dataset);
// A coder's labels in the same vocabulary (labels outside the scheme become "no event").
std::vector<gaze::Event> coder_labels(std::span<const gaze::Event> labels, const Dataset& dataset);

struct Cell {
    Agreement samples;
    EventCounts events;
    double kappa() const { return samples.kappa(); }
    double f1_sample() const { return samples.f1(); }
    double f1_event() const { return events.f1(); }
};
inline constexpr const char* kAllCoders = "all";
// cells[stimulus][event name][coder or kAllCoders]
using ScoreTable = std::map<std::string, std::map<std::string, std::map<std::string, Cell>>>;

struct DatasetScore {
    ScoreTable cells;
    size_t samples = 0;
};
// detections[i] labels dataset.recordings[i] (raw detector events; folded here).
DatasetScore score(const Dataset& dataset, const std::vector<std::vector<gaze::Event>>& detections);

// Coder against coder, the human reference of a dataset: every pair of coders that labelled
// the same recordings, each pair's counts pooled over a stimulus type as above.
struct Spread {
    double mean = gaze::kNaN, min = gaze::kNaN, max = gaze::kNaN;
    int pairs = 0;
    void add(double v);
};
struct CoderAgreement {
    Spread kappa, f1_sample, f1_event;
};
// agreement[stimulus][event name]; empty for single-coder datasets.
using CoderTable = std::map<std::string, std::map<std::string, CoderAgreement>>;
CoderTable coder_agreement(const Dataset& dataset);

const char* event_name(gaze::Event e);

}  // namespace fovea::eval
