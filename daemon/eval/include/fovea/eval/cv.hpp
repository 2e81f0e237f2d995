// Leave-one-dataset-out fitting of the detector constants that are neither physiological nor
// measured per recording (gaze/event_detector.hpp lists them: DetectorParams, "fitted"). For
// every candidate setting the detector runs once over every dataset; a fold picks the
// candidate with the best mean score over all human-labelled datasets but the held-out one and
// scores the held-out one with it. "In sample" is the shipped setting, scored on each dataset.
//
// Thread rules: run_cv uses up to `threads` worker threads internally; the inputs are read-only.
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "fovea/eval/dataset.hpp"
#include "fovea/eval/scoring.hpp"
#include "fovea/gaze/event_detector.hpp"

namespace fovea::eval {

// One fitted constant and the values a fit may choose from.
struct Tunable {
    std::string name;
    double gaze::DetectorParams::*field;
    std::vector<double> grid;
};
// The detector's fitted constants with their grids (the shipped value is always on the grid).
std::vector<Tunable> detector_tunables();

// What a dataset's fit maximizes: the mean all-coders kappa over its stimulus types and the
// events of its scheme (each dataset counts once, whatever its size).
double objective(const DatasetScore& s);

struct Candidate {
    gaze::DetectorParams params;
    std::vector<double> values;  // one per tunable
};

struct FoldResult {
    std::string dataset;
    std::vector<double> fitted;  // the held-out fold's choice, one per tunable
    DatasetScore in_sample;      // shipped constants
    DatasetScore held_out;       // constants fitted without this dataset
    double in_sample_objective = 0.0, held_out_objective = 0.0;
};

struct CvResult {
    std::vector<Tunable> tunables;
    std::vector<double> shipped;    // the defaults' values
    std::vector<double> fit_all;    // the choice on all human-labelled datasets
    std::vector<FoldResult> folds;  // one per dataset (peers too: scored, never fitted on)
    size_t candidates = 0;
    // Tunables left out by `pinned` (run_cv) and the value every fold used: base's.
    std::vector<std::pair<std::string, double>> pinned;
};

// `base` carries everything but the tunables (mode, look-ahead...). Detection per recording:
// `detect_fn` (defaults to eval::detect). Tunables named in `pinned` are not fitted: every
// fold keeps base's value (to score a setting that makes a constant physiological or
// measured per recording); an unknown name is ignored.
using DetectFn =
    std::function<std::vector<gaze::Event>(const Recording&, const gaze::DetectorParams&)>;
CvResult run_cv(const std::vector<Dataset>& datasets, const gaze::DetectorParams& base,
                const DetectFn& detect_fn, int threads = 2,
                const std::vector<std::string>& pinned = {});

// Every recording of a dataset through detect_fn on `threads` threads (one event per sample
// per recording), and the same scored.
std::vector<std::vector<gaze::Event>> detect_all(const Dataset& d,
                                                 const gaze::DetectorParams& params,
                                                 const DetectFn& fn, int threads = 2);
DatasetScore evaluate(const Dataset& d, const gaze::DetectorParams& params, const DetectFn& fn,
                      int threads = 2);

}  // namespace fovea::eval
