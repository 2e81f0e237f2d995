// Recordings the replay driver reads: the lund2013 labelled CSV (../shared/data/README.md) and
// the CSV `fovea record --out FILE.csv` writes. Pure file parsing, no timing. Any thread.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "fovea/gaze/sample.hpp"
#include "fovea/result.hpp"

namespace fovea::drivers::replay {

struct Recording {
    std::string format;               // "lund2013" or "fovea-csv"
    std::vector<gaze::RawSample> samples;  // device_ticks = capture time in clock ticks
    std::vector<int64_t> t_ns;        // capture time of each sample, ns from the first
    gaze::DeviceClock clock;          // 64-bit; 1 MHz (lund2013) or 1 GHz (fovea CSV)
    double nominal_rate_hz = 0.0;
    bool binocular = false;
    bool has_pupil = false;
    gaze::DisplayGeometry display;    // from the lund2013 header; default otherwise
    uint64_t rows = 0;                // data rows read
    uint64_t skipped_rows = 0;        // unparseable rows, or time going backwards
};

// Detects the format from the first line. Errors name the file and line.
Result<Recording> load_recording(const std::string& path);
Result<Recording> parse_recording(const std::string& text, const std::string& name = "<memory>");

}  // namespace fovea::drivers::replay
