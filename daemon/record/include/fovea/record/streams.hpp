// The three streams Fovea records and how a sample maps to an XDF row (all double64, so every
// value round-trips exactly):
//   1 "FoveaRawGaze"   (type "Gaze")    one row per RawSample the driver delivered
//   2 "FoveaGaze"      (type "Gaze")    one row per processed GazeSample, as published
//   3 "FoveaLatency"   (type "Latency") per published sample: the device-side hops in µs
// Times in ns are stored relative to the recording's time_origin_ns (in every stream's <desc>),
// exact for recordings up to 104 days; the 64-bit device counter is split into hi/lo 32-bit
// halves. XDF time stamps are seconds of CLOCK_MONOTONIC: receive time (raw), mapped capture
// time (gaze), publish time (latency).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "fovea/gaze/sample.hpp"
#include "fovea/record/xdf.hpp"

namespace fovea::record {

inline constexpr uint32_t kRawStreamId = 1;
inline constexpr uint32_t kGazeStreamId = 2;
inline constexpr uint32_t kLatencyStreamId = 3;
inline constexpr const char* kRawStreamName = "FoveaRawGaze";
inline constexpr const char* kGazeStreamName = "FoveaGaze";
inline constexpr const char* kLatencyStreamName = "FoveaLatency";

// What the stream headers say about the device and the setup. Replay rebuilds the
// gaze::PipelineConfig from it.
struct RecordingInfo {
    std::string device_name = "unknown";
    std::string driver;
    std::string address;
    double nominal_rate_hz = 0.0;
    gaze::DeviceClock clock;
    gaze::DisplayGeometry display;
    bool binocular = true;
    bool has_pupil = false;
    int64_t time_origin_ns = 0;  // CLOCK_MONOTONIC at the start of the recording
    std::string hostname;
    // The raw stream starts with every sample the chain has seen since it was created (pre-roll
    // rows flagged), so replay reproduces the live chain state exactly.
    bool preroll_from_start = false;
};

xdf::StreamInfo raw_stream_info(const RecordingInfo& info);
xdf::StreamInfo gaze_stream_info(const RecordingInfo& info);
xdf::StreamInfo latency_stream_info(const RecordingInfo& info);
// Rebuild RecordingInfo from a stream header written by raw_stream_info & co.
Result<RecordingInfo> recording_info_from_xml(const std::string& header_xml);

// Row widths (channels) of the three streams.
int raw_channel_count();
int gaze_channel_count();
int latency_channel_count();

// sample <-> row. `row` has the stream's channel count.
void encode_raw(const gaze::RawSample& s, bool predict_landing, int64_t origin_ns, double* row,
                bool preroll = false);
gaze::RawSample decode_raw(const double* row, int64_t origin_ns, bool* predict_landing = nullptr,
                           bool* preroll = nullptr);
void encode_gaze(const gaze::GazeSample& s, int64_t t_publish_ns, uint64_t ring_index,
                 int64_t origin_ns, double* row);
gaze::GazeSample decode_gaze(const double* row, int64_t origin_ns, int64_t* t_publish_ns = nullptr,
                             uint64_t* ring_index = nullptr);
void encode_latency(const gaze::GazeSample& s, int64_t t_publish_ns, uint64_t ring_index,
                    double* row);

// Channel labels of the ns-relative channels (CSV export adds time_origin_ns back).
bool is_relative_ns_channel(const std::string& label);

}  // namespace fovea::record
