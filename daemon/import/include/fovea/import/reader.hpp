// Recordings other trackers and their vendors' software wrote, read as one stream of samples,
// markers and labelled events, in constant memory (a file is never loaded whole).
//
//   auto r = fovea::import::open("test_eyelink.asc");
//   if (!r) return fail(r.error().message);          // "FILE:LINE: what", or "cannot open"
//   for (auto item = (*r)->next(); item != Item::kEnd; item = (*r)->next())
//       if (item == Item::kSample) use((*r)->sample().raw);  // a gaze::RawSample
//   for (const auto& line : (*r)->stats().issues) warn(line);  // rows skipped, and why
//
// Thread rules: a Reader is used by one thread at a time; separate readers share nothing.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fovea/gaze/sample.hpp"
#include "fovea/result.hpp"

namespace fovea::import {

enum class Format : uint8_t {
    kLund2013,     // Andersson et al. labelled CSV ("# sampFreq=..." header)
    kFoveaCsv,     // what `fovea record --out FILE.csv` writes ("# fovea ..." header)
    kArff,         // GazeCom / Startsev ARFF (time µs, x/y px, %@METADATA, label columns)
    kEyelinkAsc,   // SR Research edf2asc output
    kPupilFolder,  // a Pupil Capture recording folder (*.pldata + *_timestamps.npy)
    kPupilCsv,     // Pupil Player's gaze_positions.csv, or Pupil's LSL relay recorded to CSV
    kTobiiCsv,     // Tobii Pro SDK gaze data fields (';' or tab separated)
    kTobiiTsv,     // Tobii Studio / Pro Lab TSV exports (gaze, fixation or event data)
};
// "lund2013", "fovea-csv", "arff", "eyelink-asc", "pupil", "pupil-csv", "tobii-csv", "tobii-tsv".
const char* format_name(Format f);
std::optional<Format> format_from_name(std::string_view name);
// Every format, in the order above.
std::vector<Format> all_formats();

enum class Eye : uint8_t { kLeft = 0, kRight = 1, kBoth = 2 };

// Display geometry as far as the file states it; 0 where it does not.
struct Screen {
    int width_px = 0, height_px = 0;
    double width_m = 0.0, height_m = 0.0, distance_m = 0.0;
    bool has_pixels() const { return width_px > 0 && height_px > 0; }
    bool has_size() const { return width_m > 0 && height_m > 0 && distance_m > 0; }
    // The file's values where present, `fallback`'s elsewhere.
    gaze::DisplayGeometry resolve(const gaze::DisplayGeometry& fallback) const;
};

// What a sample's x/y mean.
enum class Coordinates : uint8_t {
    kDisplay,      // normalized display, origin top-left (the chain's own convention)
    kSceneCamera,  // Pupil: normalized world camera image, flipped to origin top-left
    kEyeCamera,    // Pupil pupil datums: normalized eye camera image (no gaze in the recording)
};
const char* coordinates_name(Coordinates c);

inline constexpr std::size_t kMaxLabelColumns = 4;

// Sample::flags: what the tracker said about a sample (EyeLink's flag field).
enum SampleFlag : uint16_t {
    kInterpolated = 1 << 0,
    kLeftCrMissing = 1 << 1,  // corneal reflection lost: pupil-only tracking
    kLeftCrRecovering = 1 << 2,
    kRightCrMissing = 1 << 3,
    kRightCrRecovering = 1 << 4,
};

struct SourceInfo {
    std::string path;
    Format format = Format::kFoveaCsv;
    std::string device;   // tracker / software as the file names it, "" if it does not
    std::string variant;  // format detail, e.g. "GAZE binocular", "HREF right", "player export"
    gaze::DeviceClock clock{64, 1e6};  // units of Sample::raw.device_ticks
    double tick_origin_s = 0.0;        // device_ticks = (time_s - tick_origin_s) * clock.tick_hz
    double header_rate_hz = 0.0;       // rate the file's header states; 0 if none
    double measured_rate_hz = 0.0;     // from the median step of the first samples; 0 if unknown
    bool binocular = false;
    bool has_pupil = false;  // Sample::raw eyes carry pupil_mm
    Coordinates coordinates = Coordinates::kDisplay;
    Screen screen;  // from the file (lund2013 header, %@METADATA, GAZE_COORDS, ...)
    // Per-sample label sets (Sample::labels order): "label" (lund2013), "handlabeller1", ...
    std::vector<std::string> label_columns;
    std::string label_codes;  // what Sample::label_codes mean, e.g. "0 UNKNOWN 1 FIX ..."
    std::string pupil_unit;   // unit of Sample::pupil_raw ("mm", "area (a.u.)", ""...)
    // Best rate to assume: measured, else the header's, else 0.
    double rate_hz() const { return measured_rate_hz > 0 ? measured_rate_hz : header_rate_hz; }
};

struct Sample {
    // device_ticks in SourceInfo::clock units; t_receive_ns 0; eyes in SourceInfo::coordinates;
    // truth = labels[0] where the file is labelled.
    gaze::RawSample raw;
    double time_s = 0.0;         // the file's time stamp, seconds of the device clock
    bool time_repaired = false;  // stamp missing/not increasing: previous + one period
    std::array<gaze::Event, kMaxLabelColumns> labels{};       // one per SourceInfo::label_columns
    std::array<int16_t, kMaxLabelColumns> label_codes{};      // as written (-1: missing)
    double confidence = gaze::kNaN;                           // Pupil / ARFF / Tobii validity
    std::array<double, 2> pupil_raw{gaze::kNaN, gaze::kNaN};  // left, right; SourceInfo::pupil_unit
    uint16_t flags = 0;                                       // SampleFlag bits
    uint64_t line = 0;  // line (text formats) or record number (binary) it came from
};

// A message the experiment or the tracker software wrote (EyeLink MSG/INPUT, Pupil
// notifications and annotations, Tobii Studio events).
struct Marker {
    double time_s = 0.0;
    uint64_t device_ticks = 0;
    std::string text;
    uint64_t line = 0;
};

// An event the tracker's own software labelled (EyeLink's online parser, Tobii's fixation
// filter, Pupil Player's fixation and blink detectors), delivered once it has ended.
struct LabelledEvent {
    gaze::Event type = gaze::Event::kUnknown;  // kFixation, kSaccade or kBlink
    Eye eye = Eye::kBoth;
    std::string source;        // "eyelink", "tobii", "pupil"
    double start_s = 0.0;      // first sample of the event, device clock
    double end_s = 0.0;        // last sample of the event
    uint64_t start_ticks = 0;  // the same in SourceInfo::clock ticks
    uint64_t end_ticks = 0;
    double amplitude_deg = gaze::kNaN;      // saccades, as the tracker computed it
    double peak_velocity_dps = gaze::kNaN;  // saccades
    // Normalized display coordinates where known: saccade start and end; fixation mean in x/y.
    double start_x = gaze::kNaN, start_y = gaze::kNaN, end_x = gaze::kNaN, end_y = gaze::kNaN;
    double x = gaze::kNaN, y = gaze::kNaN;
    double pupil_raw = gaze::kNaN;  // fixations: mean pupil, SourceInfo::pupil_unit
    uint64_t line = 0;
};

struct ReadStats {
    uint64_t lines = 0;  // lines (or binary records) read
    uint64_t bytes = 0;
    uint64_t samples = 0, markers = 0, events = 0;
    uint64_t invalid_samples = 0;     // delivered without valid gaze (missing data, low confidence)
    uint64_t skipped = 0;             // malformed rows or records dropped
    uint64_t repaired_times = 0;      // samples whose stamp was missing or not increasing
    bool truncated = false;           // the last line or record was cut off (and dropped)
    uint64_t issue_count = 0;         // every problem, including those not kept in `issues`
    std::vector<std::string> issues;  // the first Options::max_issues: "FILE:LINE: what"
};

enum class Item : uint8_t { kEnd, kSample, kMarker, kEvent };

class Reader {
public:
    virtual ~Reader() = default;
    Reader(const Reader&) = delete;
    Reader& operator=(const Reader&) = delete;

    const SourceInfo& info() const { return info_; }
    // The next item in file order. Malformed input is skipped and counted in stats(), never
    // fatal; kEnd at the end of the input or after an I/O error (then error() says which).
    virtual Item next() = 0;
    // The item next() returned; valid until the following next().
    const Sample& sample() const { return sample_; }
    const Marker& marker() const { return marker_; }
    const LabelledEvent& event() const { return event_; }
    const ReadStats& stats() const { return stats_; }
    const std::string& error() const { return error_; }

protected:
    Reader() = default;
    SourceInfo info_;
    Sample sample_;
    Marker marker_;
    LabelledEvent event_;
    ReadStats stats_;
    std::string error_;
};

struct Options {
    std::optional<Format> format;  // force a format; otherwise detected from the content
    double min_confidence = 0.6;   // Pupil: gaze below it is invalid (Pupil's own default)
    // Geometry for what the file does not state: pixels for ARFF/ASC without them, the
    // physical size for EyeLink HREF samples. Without it such files are an error.
    std::optional<gaze::DisplayGeometry> display;
    std::size_t max_issues = 100;  // issue lines kept in ReadStats::issues
    // The rate, when already known (reopening a file): skips the first pass that measures it.
    double rate_hz = 0.0;
};

// Open a file (or a Pupil recording folder) and read its header. Errors name the file and,
// for a bad header, the line.
Result<std::unique_ptr<Reader>> open(const std::string& path, const Options& options = {});
// The same over bytes in memory (tests, fuzzing); `data` must outlive the reader. Folder
// formats are not available this way.
Result<std::unique_ptr<Reader>> open_memory(std::string_view data, const std::string& name,
                                            const Options& options = {});
// Which format a file's content is; an error naming what was expected otherwise.
Result<Format> detect(const std::string& path);
Result<Format> detect_memory(std::string_view head, const std::string& name);

}  // namespace fovea::import
