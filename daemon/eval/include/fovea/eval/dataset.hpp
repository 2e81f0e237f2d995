// Labelled eye-movement recordings from other labs and trackers, in one shape: the raw samples
// the gaze chain reads (normalized display coordinates per eye, microsecond device clock), the
// display they are normalized against, and each coder's label per sample. Loaders for every
// shared dataset (../shared/data/README.md) and a directory walk that finds them all.
//
// Thread rules: loaders are pure functions of their files; a loaded Dataset is read-only and may
// be shared between threads.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "fovea/gaze/sample.hpp"
#include "fovea/result.hpp"

namespace fovea::eval {

struct Recording {
    std::string name;      // unique within its dataset
    std::string stimulus;  // scoring group: img/dots/video (lund2013), adult/infant (hooge2018)...
    std::string subject;   // who was recorded, for leave-one-subject-out fits
    double rate_hz = 0.0;  // from the time stamps (some headers are wrong)
    bool binocular = false;
    gaze::DisplayGeometry display;         // what the samples' x/y are normalized against
    std::vector<gaze::RawSample> samples;  // device_ticks in µs from the first sample
    // Labels per coder, aligned with samples (same length; kUnknown where a coder has none).
    std::map<std::string, std::vector<gaze::Event>> coders;
};

struct Dataset {
    std::string name;  // lund2013, gazecom, hooge2018, uneye, eyelink
    std::string path;
    // Labelled by people (false: by a peer algorithm, e.g. EyeLink's online parser; such a
    // dataset is scored but never fitted on).
    bool human = true;
    // The events the coders' scheme distinguishes; detections are mapped onto it for scoring
    // (scoring.hpp: fold_to_scheme) and only these are scored.
    std::vector<gaze::Event> scheme;
    // Where a detected PSO is scored when the scheme has none (fold_to_scheme): people who
    // label no PSO give the wobble to the saccade it ends; EyeLink's parser starts the fixation
    // where velocity and acceleration fall below its thresholds and keeps overshoots and
    // glissades out of the saccade (SR Research, EyeLink 1000 User Manual §4.3.5-4.3.6), so
    // there the wobble is fixation.
    gaze::Event pso_without_label = gaze::Event::kSaccade;
    std::vector<Recording> recordings;
    std::vector<std::string> notes;  // files skipped or repaired, and why

    size_t samples() const;
    bool labels(gaze::Event e) const;
};

// lund2013 (Andersson et al. 2017): every *.csv in dir, two coders' files per recording (read
// through fovea::import, the one lund2013 parser).
Result<Dataset> load_lund2013(const std::string& dir);
// Hooge et al. 2018: dir/data/ETdata/*.txt (time ms, x y px, Tobii TX300 300 Hz) and the 12
// coders' fixation intervals in dir/data/coderSettings/*.txt.
Result<Dataset> load_hooge2018(const std::string& dir);
// U'n'Eye (Bellet et al. 2019) CSV matrices in dir: *_X_*.csv, *_Y_*.csv (degrees) and
// *_Labels_*.csv (0 fixation, 1 saccade), one trial a row, at the rate in the file names (Hz).
Result<Dataset> load_uneye(const std::string& dir);

// GazeCom-style ARFF files in dir (Startsev et al. 2019): each labelled file a recording, each
// label column (handlabeller1, handlabeller2, handlabeller_final) a coder; FIX/SACC/SP scored
// (NOISE and UNKNOWN are no event). Read through fovea::import.
Result<Dataset> load_arff(const std::string& dir);
// EyeLink ASC files in dir, scored against the tracker's own online parser (EFIX/ESACC/EBLINK
// per eye: coders "eyelink-left" / "eyelink-right"); a peer, not people (Dataset::human false).
Result<Dataset> load_asc_dir(const std::string& dir);
// An empty dataset named `name` with the EyeLink parser's scheme and conventions, for ASC files
// gathered elsewhere (fovea eval-events --against eyelink).
Dataset eyelink_parser_dataset(std::string name, std::string path);
Result<Recording> load_asc(const std::string& path, std::vector<std::string>* notes = nullptr);

// Every dataset found under root, which may be one dataset's folder or ../shared/data itself
// (lund2013/, labelled/hooge2018/, labelled/uneye_*/, labelled/gazecom/, recordings/eyelink/*/).
// Folders of the same kind form one dataset; unreadable ones become notes.
struct DatasetSet {
    std::vector<Dataset> datasets;
    std::vector<std::string> notes;
};
Result<DatasetSet> load_datasets(const std::string& root);

// Every `factor`-th sample of the recording and of each coder's labels, from the first: what a
// tracker running at rate_hz / factor would have delivered of the same eye movements (no
// anti-alias filter: a camera samples, it does not average). The rate becomes rate_hz / factor.
void decimate(Recording& r, size_t factor);
// `factor` - 1 samples linearly interpolated into every interval (time stamps, both eyes'
// positions and pupils), each taking the nearer original sample's labels, and its eyes where
// either end is invalid: the same eye movements as a tracker at factor x rate_hz, minus the
// noise such a tracker would add between the samples (--add-noise-deg adds it back). Probes the
// rate handling up to 2000 Hz, where no labelled recording exists. The rate becomes
// rate_hz x factor; factor 0 or 1 leaves the recording as it is.
void upsample(Recording& r, size_t factor);
// Gaussian white noise of `sd_deg` per axis added to every valid sample, the same offset to
// both eyes (the combined gaze gets all of it): the same eye movements through a noisier
// tracker. Deterministic for a seed; sd_deg <= 0 leaves the recording as it is.
void add_white_noise(Recording& r, double sd_deg, uint64_t seed);

// Gaze of a sample in degrees from the display centre: the mean of the valid eyes, the same
// combination the gaze chain's detector sees (gaze/pipeline.hpp). NaN when no eye is valid.
struct Degrees {
    double x = gaze::kNaN, y = gaze::kNaN;
    bool valid = false;
};
Degrees degrees(const Recording& r, size_t i);
double seconds(const Recording& r, size_t i);

}  // namespace fovea::eval
