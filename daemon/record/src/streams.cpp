#include "fovea/record/streams.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace fovea::record {

namespace {

struct Ch {
    const char* label;
    const char* unit;
    const char* type;
};

constexpr Ch kRaw[] = {
    {"device_ticks_hi", "ticks*2^32", "DeviceClock"},
    {"device_ticks_lo", "ticks", "DeviceClock"},
    {"t_receive_ns", "ns", "Time"},
    {"left_x", "normalized", "ScreenX"},
    {"left_y", "normalized", "ScreenY"},
    {"left_pupil_mm", "mm", "Diameter"},
    {"left_valid", "bool", "Flag"},
    {"right_x", "normalized", "ScreenX"},
    {"right_y", "normalized", "ScreenY"},
    {"right_pupil_mm", "mm", "Diameter"},
    {"right_valid", "bool", "Flag"},
    {"device_id", "index", "Id"},
    {"truth_event", "fovea_event", "Event"},
    {"predict_landing", "bool", "Flag"},
    {"preroll", "bool", "Flag"},  // from before record.start: replay warms the chain up on it
};

constexpr Ch kGaze[] = {
    {"t_capture_ns", "ns", "Time"},
    {"t_receive_ns", "ns", "Time"},
    {"t_processed_ns", "ns", "Time"},
    {"t_publish_ns", "ns", "Time"},
    {"ring_index", "index", "Id"},
    {"clock_uncertainty_us", "us", "Time"},
    {"clock_converged", "bool", "Flag"},
    {"left_x", "normalized", "ScreenX"},
    {"left_y", "normalized", "ScreenY"},
    {"left_pupil_mm", "mm", "Diameter"},
    {"left_valid", "bool", "Flag"},
    {"right_x", "normalized", "ScreenX"},
    {"right_y", "normalized", "ScreenY"},
    {"right_pupil_mm", "mm", "Diameter"},
    {"right_valid", "bool", "Flag"},
    {"combined_x", "normalized", "ScreenX"},
    {"combined_y", "normalized", "ScreenY"},
    {"combined_pupil_mm", "mm", "Diameter"},
    {"combined_valid", "bool", "Flag"},
    {"left_deg_x", "deg", "VisualAngleX"},
    {"left_deg_y", "deg", "VisualAngleY"},
    {"right_deg_x", "deg", "VisualAngleX"},
    {"right_deg_y", "deg", "VisualAngleY"},
    {"combined_deg_x", "deg", "VisualAngleX"},
    {"combined_deg_y", "deg", "VisualAngleY"},
    {"event", "fovea_event", "Event"},
    {"saccade_onset_ns", "ns", "Time"},
    {"saccade_amplitude_deg", "deg", "Amplitude"},
    {"saccade_peak_velocity_dps", "deg/s", "Velocity"},
    {"saccade_direction_deg", "deg", "Direction"},
    {"landing_valid", "bool", "Flag"},
    {"landing_x", "normalized", "ScreenX"},
    {"landing_y", "normalized", "ScreenY"},
    {"landing_deg_x", "deg", "VisualAngleX"},
    {"landing_deg_y", "deg", "VisualAngleY"},
    {"landing_uncertainty_deg", "deg", "Uncertainty"},
    {"calibrated", "bool", "Flag"},
    {"device_id", "index", "Id"},
    {"truth_event", "fovea_event", "Event"},
};

constexpr Ch kLatency[] = {
    {"ring_index", "index", "Id"},
    {"capture_to_receive_us", "us", "Latency"},
    {"receive_to_processed_us", "us", "Latency"},
    {"processed_to_publish_us", "us", "Latency"},
    {"clock_uncertainty_us", "us", "Uncertainty"},
};

std::string num(double v) {
    char b[40];
    std::snprintf(b, sizeof b, "%.17g", v);
    return b;
}

std::string setup_xml(const RecordingInfo& i) {
    std::string x;
    x += "    <time_origin_ns>" + std::to_string(i.time_origin_ns) + "</time_origin_ns>\n";
    x += "    <time_note>channels with unit ns are offsets from time_origin_ns "
         "(CLOCK_MONOTONIC)</time_note>\n";
    x += "    <acquisition><manufacturer>Fovea</manufacturer><model>" +
         xdf::xml_escape(i.device_name) + "</model><driver>" + xdf::xml_escape(i.driver) +
         "</driver><address>" + xdf::xml_escape(i.address) + "</address><hostname>" +
         xdf::xml_escape(i.hostname) + "</hostname></acquisition>\n";
    x += "    <device><nominal_rate_hz>" + num(i.nominal_rate_hz) +
         "</nominal_rate_hz><counter_bits>" + std::to_string(i.clock.counter_bits) +
         "</counter_bits><tick_hz>" + num(i.clock.tick_hz) + "</tick_hz><host_synced>" +
         (i.clock.host_synced ? "1" : "0") + "</host_synced><sync_uncertainty_us>" +
         num(i.clock.sync_uncertainty_us) + "</sync_uncertainty_us><binocular>" +
         (i.binocular ? "1" : "0") + "</binocular><has_pupil>" + (i.has_pupil ? "1" : "0") +
         "</has_pupil></device>\n";
    const auto& d = i.display;
    x += "    <display><width_px>" + std::to_string(d.width_px) + "</width_px><height_px>" +
         std::to_string(d.height_px) + "</height_px><width_m>" + num(d.width_m) +
         "</width_m><height_m>" + num(d.height_m) + "</height_m><distance_m>" + num(d.distance_m) +
         "</distance_m></display>\n";
    x += "    <preroll_from_start>" + std::string(i.preroll_from_start ? "1" : "0") +
         "</preroll_from_start>\n";
    x += "    <events>0=unknown 1=fixation 2=saccade 3=pso 4=pursuit 5=blink</events>\n";
    return x;
}

xdf::StreamInfo make_info(const RecordingInfo& i, const char* name, const char* type,
                          const Ch* chans, std::size_t n, double srate, const char* suffix) {
    xdf::StreamInfo s;
    s.name = name;
    s.type = type;
    s.format = xdf::Format::kDouble64;
    s.nominal_srate = srate;
    s.source_id = "fovea:" + i.driver + ":" + i.address + ":" + suffix;
    s.created_at = static_cast<double>(i.time_origin_ns) * 1e-9;
    for (std::size_t k = 0; k < n; ++k)
        s.channels.push_back({chans[k].label, chans[k].unit, chans[k].type});
    s.desc_extra_xml = setup_xml(i);
    return s;
}

double rel(int64_t t, int64_t origin) { return static_cast<double>(t - origin); }
int64_t unrel(double v, int64_t origin) { return origin + static_cast<int64_t>(v); }
double b(bool v) { return v ? 1.0 : 0.0; }

void put_eye(const gaze::EyeSample& e, double*& r) {
    *r++ = e.x;
    *r++ = e.y;
    *r++ = e.pupil_mm;
    *r++ = b(e.valid);
}
gaze::EyeSample get_eye(const double*& r) {
    gaze::EyeSample e;
    e.x = *r++;
    e.y = *r++;
    e.pupil_mm = *r++;
    e.valid = *r++ != 0.0;
    return e;
}

}  // namespace

xdf::StreamInfo raw_stream_info(const RecordingInfo& i) {
    return make_info(i, kRawStreamName, "Gaze", kRaw, std::size(kRaw), i.nominal_rate_hz, "raw");
}
xdf::StreamInfo gaze_stream_info(const RecordingInfo& i) {
    return make_info(i, kGazeStreamName, "Gaze", kGaze, std::size(kGaze), i.nominal_rate_hz,
                     "gaze");
}
xdf::StreamInfo latency_stream_info(const RecordingInfo& i) {
    return make_info(i, kLatencyStreamName, "Latency", kLatency, std::size(kLatency),
                     i.nominal_rate_hz, "latency");
}

int raw_channel_count() { return static_cast<int>(std::size(kRaw)); }
int gaze_channel_count() { return static_cast<int>(std::size(kGaze)); }
int latency_channel_count() { return static_cast<int>(std::size(kLatency)); }

bool is_relative_ns_channel(const std::string& label) {
    const bool t_ns = label.size() > 5 && label.compare(0, 2, "t_") == 0 &&
                      label.compare(label.size() - 3, 3, "_ns") == 0;
    return t_ns || label == "saccade_onset_ns";
}

Result<RecordingInfo> recording_info_from_xml(const std::string& x) {
    RecordingInfo i;
    const std::string origin = xdf::xml_text(x, "time_origin_ns");
    if (origin.empty())
        return make_error("stream header has no <time_origin_ns>: not a Fovea recording");
    i.time_origin_ns = std::strtoll(origin.c_str(), nullptr, 10);
    i.device_name = xdf::xml_text(x, "model");
    i.driver = xdf::xml_text(x, "driver");
    i.address = xdf::xml_text(x, "address");
    i.hostname = xdf::xml_text(x, "hostname");
    auto d = [&](const char* tag, double def) {
        const std::string t = xdf::xml_text(x, tag);
        return t.empty() ? def : std::strtod(t.c_str(), nullptr);
    };
    i.nominal_rate_hz = d("nominal_rate_hz", 0.0);
    i.clock.counter_bits = static_cast<int>(d("counter_bits", 64));
    i.clock.tick_hz = d("tick_hz", 1e9);
    i.clock.host_synced = d("host_synced", 0) != 0;
    i.clock.sync_uncertainty_us = d("sync_uncertainty_us", 0.0);
    i.binocular = d("binocular", 1) != 0;
    i.has_pupil = d("has_pupil", 0) != 0;
    i.preroll_from_start = d("preroll_from_start", 0) != 0;
    i.display.width_px = static_cast<int>(d("width_px", i.display.width_px));
    i.display.height_px = static_cast<int>(d("height_px", i.display.height_px));
    i.display.width_m = d("width_m", i.display.width_m);
    i.display.height_m = d("height_m", i.display.height_m);
    i.display.distance_m = d("distance_m", i.display.distance_m);
    return i;
}

void encode_raw(const gaze::RawSample& s, bool predict_landing, int64_t origin, double* r,
                bool preroll) {
    *r++ = static_cast<double>(s.device_ticks >> 32);
    *r++ = static_cast<double>(s.device_ticks & 0xFFFFFFFFull);
    *r++ = rel(s.t_receive_ns, origin);
    put_eye(s.left, r);
    put_eye(s.right, r);
    *r++ = static_cast<double>(s.device_id);
    *r++ = static_cast<double>(static_cast<int>(s.truth));
    *r++ = b(predict_landing);
    *r++ = b(preroll);
}

gaze::RawSample decode_raw(const double* r, int64_t origin, bool* predict_landing, bool* preroll) {
    gaze::RawSample s;
    s.device_ticks = (static_cast<uint64_t>(r[0]) << 32) | static_cast<uint64_t>(r[1]);
    r += 2;
    s.t_receive_ns = unrel(*r++, origin);
    s.left = get_eye(r);
    s.right = get_eye(r);
    s.device_id = static_cast<uint32_t>(*r++);
    s.truth = static_cast<gaze::Event>(static_cast<int>(*r++));
    if (predict_landing) *predict_landing = r[0] != 0.0;
    if (preroll) *preroll = r[1] != 0.0;
    return s;
}

void encode_gaze(const gaze::GazeSample& s, int64_t t_publish_ns, uint64_t ring_index,
                 int64_t origin, double* r) {
    *r++ = rel(s.t_capture_ns, origin);
    *r++ = rel(s.t_receive_ns, origin);
    *r++ = rel(s.t_processed_ns, origin);
    *r++ = rel(t_publish_ns, origin);
    *r++ = static_cast<double>(ring_index);
    *r++ = s.clock_uncertainty_us;
    *r++ = b(s.clock_converged);
    put_eye(s.left, r);
    put_eye(s.right, r);
    put_eye(s.combined, r);
    *r++ = s.left_deg_x;
    *r++ = s.left_deg_y;
    *r++ = s.right_deg_x;
    *r++ = s.right_deg_y;
    *r++ = s.combined_deg_x;
    *r++ = s.combined_deg_y;
    *r++ = static_cast<double>(static_cast<int>(s.event));
    // onset 0 means "no saccade yet"; keep it distinguishable from a real time
    *r++ = s.saccade.onset_ns == 0 ? gaze::kNaN : rel(s.saccade.onset_ns, origin);
    *r++ = s.saccade.amplitude_deg;
    *r++ = s.saccade.peak_velocity_dps;
    *r++ = s.saccade.direction_deg;
    *r++ = b(s.saccade.landing_valid);
    *r++ = s.saccade.landing_x;
    *r++ = s.saccade.landing_y;
    *r++ = s.saccade.landing_deg_x;
    *r++ = s.saccade.landing_deg_y;
    *r++ = s.saccade.landing_uncertainty_deg;
    *r++ = b(s.calibrated);
    *r++ = static_cast<double>(s.device_id);
    *r++ = static_cast<double>(static_cast<int>(s.truth));
}

gaze::GazeSample decode_gaze(const double* r, int64_t origin, int64_t* t_publish_ns,
                             uint64_t* ring_index) {
    gaze::GazeSample s;
    s.t_capture_ns = unrel(*r++, origin);
    s.t_receive_ns = unrel(*r++, origin);
    s.t_processed_ns = unrel(*r++, origin);
    const int64_t pub = unrel(*r++, origin);
    const uint64_t idx = static_cast<uint64_t>(*r++);
    if (t_publish_ns) *t_publish_ns = pub;
    if (ring_index) *ring_index = idx;
    s.clock_uncertainty_us = *r++;
    s.clock_converged = *r++ != 0.0;
    s.left = get_eye(r);
    s.right = get_eye(r);
    s.combined = get_eye(r);
    s.left_deg_x = *r++;
    s.left_deg_y = *r++;
    s.right_deg_x = *r++;
    s.right_deg_y = *r++;
    s.combined_deg_x = *r++;
    s.combined_deg_y = *r++;
    s.event = static_cast<gaze::Event>(static_cast<int>(*r++));
    const double onset = *r++;
    s.saccade.onset_ns = std::isnan(onset) ? 0 : unrel(onset, origin);
    s.saccade.amplitude_deg = *r++;
    s.saccade.peak_velocity_dps = *r++;
    s.saccade.direction_deg = *r++;
    s.saccade.landing_valid = *r++ != 0.0;
    s.saccade.landing_x = *r++;
    s.saccade.landing_y = *r++;
    s.saccade.landing_deg_x = *r++;
    s.saccade.landing_deg_y = *r++;
    s.saccade.landing_uncertainty_deg = *r++;
    s.calibrated = *r++ != 0.0;
    s.device_id = static_cast<uint32_t>(*r++);
    s.truth = static_cast<gaze::Event>(static_cast<int>(*r++));
    return s;
}

void encode_latency(const gaze::GazeSample& s, int64_t t_publish_ns, uint64_t ring_index,
                    double* r) {
    *r++ = static_cast<double>(ring_index);
    *r++ = static_cast<double>(s.t_receive_ns - s.t_capture_ns) / 1000.0;
    *r++ = static_cast<double>(s.t_processed_ns - s.t_receive_ns) / 1000.0;
    *r++ = static_cast<double>(t_publish_ns - s.t_processed_ns) / 1000.0;
    *r++ = s.clock_uncertainty_us;
}

}  // namespace fovea::record
