// The three stages of `fovea report` (report.cpp runs them in order): the analysis of a decoded
// recording (numbers only), the figures drawn from it (PNG files), and the HTML page around both.
// Private to fovea_record; pure functions of their arguments, any thread.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "fovea/gaze/main_sequence.hpp"
#include "fovea/latency_histogram.hpp"
#include "fovea/record/offline.hpp"
#include "fovea/record/report.hpp"
#include "fovea/result.hpp"

namespace fovea::record::report {

// One device-side hop measured from the gaze stream's own stamps.
struct HopDef {
    const char* key;    // file name part: latency_<key>.png
    const char* title;  // table row and figure title
};
inline constexpr std::array<HopDef, 4> kHops = {{
    {"capture_to_receive", "device capture -> host receive"},
    {"receive_to_processed", "host receive -> processed"},
    {"processed_to_publish", "processed -> published in ring"},
    {"capture_to_publish", "total: device capture -> published"},
}};

struct Saccade {
    double t_s, amplitude, peak;
};

// Per 100 ms bin of the raw stream.
struct Timeline {
    double bin_s = 0.1;
    std::vector<double> lo, hi;       // bin edges, s from t0
    std::vector<double> missing;      // samples lost before the host (device counter gaps)
    std::vector<double> ring_gap;     // samples not recorded (ring index gaps)
    std::vector<double> total;        // raw samples received
    std::vector<double> valid_left;   // of which the left eye was valid
    std::vector<double> valid_right;  // ... and the right eye
};

struct Analysis {
    Recording rec;    // pre-roll removed
    int64_t t0 = 0;   // ns: the first raw receive time, else the first capture, else the origin
    double rate = 0;  // nominal rate, 1000 Hz when the recording does not say
    std::array<LatencyHistogram, kHops.size()> hops;
    std::vector<Saccade> saccades;
    std::array<uint64_t, 6> event_samples{};  // samples per gaze::Event
    Timeline timeline;                        // empty without raw samples
    ReportSummary summary;                    // counts and ratios; paths filled by the caller
};

// How the page names an event ("fixation", "PSO", ...).
const char* event_label(gaze::Event e);

// The main sequence the report compares detected saccades with: the lund2013 coders' fit.
inline constexpr const gaze::MainSequence& kExpectedMainSequence = gaze::kLund2013Labels;

Analysis analyse(Recording rec);

// A PNG written to the output folder and its caption in the page.
struct Figure {
    std::string file, caption;
};
// Draw every figure of `a` into out_dir (which exists), in page order.
Result<std::vector<Figure>> draw_figures(const Analysis& a, const std::string& out_dir);

// The self-contained page: the summary and hop tables, then every figure read back from out_dir
// and embedded as a data URI.
std::string html_page(const Analysis& a, const std::string& source,
                      const std::vector<Figure>& figures, const std::string& out_dir);

}  // namespace fovea::record::report
