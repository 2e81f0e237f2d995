// Working with finished recordings: CSV export and replay through the gaze chain.
// Any thread; no state shared between calls.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "fovea/gaze/pipeline.hpp"
#include "fovea/gaze/sample.hpp"
#include "fovea/record/streams.hpp"
#include "fovea/record/xdf.hpp"
#include "fovea/result.hpp"

namespace fovea::record {

struct CsvFile {
    std::string path;
    std::string stream;
    uint64_t rows = 0;
};

// One CSV per stream, named <dir>/<stream name>.csv (created if needed): a `timestamp_s` column
// then one column per channel label. Fovea's relative-ns channels are written back as absolute
// CLOCK_MONOTONIC ns integers and the split device counter as one `device_ticks` column, so the
// numbers equal what the daemon published. Doubles use the shortest text that round-trips;
// NaN is an empty field.
Result<std::vector<CsvFile>> export_csv(const xdf::File& file, const std::string& dir);

// Samples of our streams, decoded.
struct Recording {
    RecordingInfo info;
    std::vector<gaze::RawSample> raw;
    std::vector<bool> raw_predict_landing;
    std::vector<bool> raw_preroll;
    std::vector<gaze::GazeSample> gaze;
    std::vector<int64_t> t_publish_ns;
    std::vector<uint64_t> ring_index;
};
Result<Recording> decode_recording(const xdf::File& file);

// Rebuild the pipeline configuration a recording was made with.
gaze::PipelineConfig pipeline_config(const RecordingInfo& info);

struct ReplayResult {
    std::vector<gaze::GazeSample> gaze;  // in output order, all devices
    uint64_t compared = 0;               // recorded samples compared
    uint64_t mismatches = 0;             // samples differing in any field
    uint64_t event_mismatches = 0;       // samples whose event differs
    int64_t first_mismatch = -1;         // index into the recorded gaze stream
    std::string first_mismatch_field;
    uint64_t recorded = 0, replayed = 0;
};

// Feed every raw sample (pre-roll first, to rebuild the chain state; in file order, one pipeline
// per device_id, predict_landing as it was live) through a fresh gaze::Pipeline and compare with
// the recorded processed stream, field by field and bit for bit (times that the daemon stamps
// itself, t_processed_ns, excepted: the replay stamps its own). The live daemon may stop before its
// pipeline's look-ahead drained, so only the first `recorded` samples per device are compared.
ReplayResult replay(const Recording& rec);

// First field where two samples differ bit for bit ("" if none). Skips t_processed_ns.
std::string first_difference(const gaze::GazeSample& a, const gaze::GazeSample& b);

}  // namespace fovea::record
