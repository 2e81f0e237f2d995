// `fovea report`: a self-contained HTML page (PNG plots embedded as data URIs and also written
// next to it) from a Fovea XDF recording: per-hop latency histograms, gaze trace with events
// coloured, saccade main sequence against Vp = 560 (1 - e^(-A/4.25)) deg/s, drop and validity
// timelines. Any thread.
#pragma once

#include <string>
#include <vector>

#include "fovea/record/xdf.hpp"
#include "fovea/result.hpp"

namespace fovea::record {

struct ReportSummary {
    std::string html_path;
    std::vector<std::string> pngs;
    uint64_t raw_samples = 0, gaze_samples = 0, saccades = 0, missing_samples = 0;
    double duration_s = 0.0;
    double main_sequence_median_ratio = 0.0;  // measured / expected peak velocity
};

Result<ReportSummary> make_report(const xdf::File& file, const std::string& source,
                                  const std::string& out_dir);

}  // namespace fovea::record
