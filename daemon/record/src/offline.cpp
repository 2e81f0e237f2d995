#include "fovea/record/offline.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>

namespace fovea::record {

namespace {

void put_double(std::string& out, double v) {
    if (std::isnan(v)) return;
    char b[32];
    const auto r = std::to_chars(b, b + sizeof b, v);
    out.append(b, r.ptr);
}

bool bits_equal(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

Result<std::vector<CsvFile>> export_csv(const xdf::File& file, const std::string& dir) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) return make_error("cannot create " + dir + ": " + ec.message());
    std::vector<CsvFile> out;
    for (const auto& s : file.streams) {
        std::string name = s.name.empty() ? "stream" + std::to_string(s.id) : s.name;
        for (char& c : name) {
            if (c == '/' || c == '\\' || c == ' ') c = '_';
        }
        const std::string path = (std::filesystem::path(dir) / (name + ".csv")).string();
        std::FILE* f = std::fopen(path.c_str(), "w");
        if (!f) return make_error("cannot write " + path + ": " + std::strerror(errno), errno);
        const std::string origin_text = xdf::xml_text(s.header_xml, "time_origin_ns");
        const bool has_origin = !origin_text.empty();
        const int64_t origin = has_origin ? std::strtoll(origin_text.c_str(), nullptr, 10) : 0;
        const int hi = s.channel_index("device_ticks_hi");
        const int lo = s.channel_index("device_ticks_lo");
        const bool ticks = has_origin && hi >= 0 && lo >= 0;
        std::vector<int> kind(static_cast<std::size_t>(s.channel_count),
                              0);  // 0 value, 1 abs ns, 2 skip
        std::string line = "timestamp_s";
        for (int c = 0; c < s.channel_count; ++c) {
            const std::string label = c < static_cast<int>(s.labels.size()) &&
                                              !s.labels[static_cast<std::size_t>(c)].empty()
                                          ? s.labels[static_cast<std::size_t>(c)]
                                          : "ch" + std::to_string(c);
            if (ticks && c == hi) {
                line += ",device_ticks";
                kind[static_cast<std::size_t>(c)] = 3;
                continue;
            }
            if (ticks && c == lo) {
                kind[static_cast<std::size_t>(c)] = 2;
                continue;
            }
            if (has_origin && is_relative_ns_channel(label)) kind[static_cast<std::size_t>(c)] = 1;
            line += "," + label;
        }
        line += "\n";
        std::fputs(line.c_str(), f);
        for (std::size_t i = 0; i < s.sample_count(); ++i) {
            line.clear();
            put_double(line, s.stamps[i]);
            for (int c = 0; c < s.channel_count; ++c) {
                const int k = kind[static_cast<std::size_t>(c)];
                if (k == 2) continue;
                line += ',';
                if (s.format == xdf::Format::kString) {
                    line += s.string_values[i * static_cast<std::size_t>(s.channel_count) +
                                            static_cast<std::size_t>(c)];
                    continue;
                }
                const double v = s.value(i, c);
                if (k == 1) {
                    if (!std::isnan(v)) line += std::to_string(origin + static_cast<int64_t>(v));
                } else if (k == 3) {
                    const uint64_t t =
                        (static_cast<uint64_t>(v) << 32) | static_cast<uint64_t>(s.value(i, lo));
                    line += std::to_string(t);
                } else {
                    put_double(line, v);
                }
            }
            line += '\n';
            std::fwrite(line.data(), 1, line.size(), f);
        }
        if (std::fclose(f) != 0)
            return make_error("writing " + path + ": " + std::strerror(errno), errno);
        out.push_back({path, s.name, s.sample_count()});
    }
    return out;
}

Result<Recording> decode_recording(const xdf::File& file) {
    const auto* raw = file.find(kRawStreamName);
    const auto* gz = file.find(kGazeStreamName);
    if (!raw || !gz)
        return make_error("not a Fovea recording: streams FoveaRawGaze/FoveaGaze missing");
    if (raw->channel_count != raw_channel_count() || gz->channel_count != gaze_channel_count()) {
        return make_error("Fovea recording of another layout (channel counts differ)");
    }
    auto info = recording_info_from_xml(raw->header_xml);
    if (!info) return info.error();
    Recording r;
    r.info = *info;
    const int64_t o = r.info.time_origin_ns;
    for (std::size_t i = 0; i < raw->sample_count(); ++i) {
        bool pl = true, pre = false;
        r.raw.push_back(decode_raw(&raw->values[i * static_cast<std::size_t>(raw->channel_count)],
                                   o, &pl, &pre));
        r.raw_predict_landing.push_back(pl);
        r.raw_preroll.push_back(pre);
    }
    for (std::size_t i = 0; i < gz->sample_count(); ++i) {
        int64_t pub = 0;
        uint64_t idx = 0;
        r.gaze.push_back(decode_gaze(&gz->values[i * static_cast<std::size_t>(gz->channel_count)],
                                     o, &pub, &idx));
        r.t_publish_ns.push_back(pub);
        r.ring_index.push_back(idx);
    }
    return r;
}

gaze::PipelineConfig pipeline_config(const RecordingInfo& info) {
    gaze::PipelineConfig c;
    c.clock = info.clock;
    c.display = info.display;
    if (info.nominal_rate_hz > 0) c.nominal_rate_hz = info.nominal_rate_hz;
    return c;
}

std::string first_difference(const gaze::GazeSample& a, const gaze::GazeSample& b) {
#define FOVEA_CMP(f) \
    if (!bits_equal(static_cast<double>(a.f), static_cast<double>(b.f))) return #f
#define FOVEA_CMP_EYE(e)   \
    FOVEA_CMP(e.x);        \
    FOVEA_CMP(e.y);        \
    FOVEA_CMP(e.pupil_mm); \
    FOVEA_CMP(e.valid)
    FOVEA_CMP(t_capture_ns);
    FOVEA_CMP(t_receive_ns);
    FOVEA_CMP(clock_uncertainty_us);
    FOVEA_CMP(clock_converged);
    FOVEA_CMP_EYE(left);
    FOVEA_CMP_EYE(right);
    FOVEA_CMP_EYE(combined);
    FOVEA_CMP(left_deg_x);
    FOVEA_CMP(left_deg_y);
    FOVEA_CMP(right_deg_x);
    FOVEA_CMP(right_deg_y);
    FOVEA_CMP(combined_deg_x);
    FOVEA_CMP(combined_deg_y);
    FOVEA_CMP(event);
    FOVEA_CMP(saccade.onset_ns);
    FOVEA_CMP(saccade.amplitude_deg);
    FOVEA_CMP(saccade.peak_velocity_dps);
    FOVEA_CMP(saccade.direction_deg);
    FOVEA_CMP(saccade.landing_valid);
    FOVEA_CMP(saccade.landing_x);
    FOVEA_CMP(saccade.landing_y);
    FOVEA_CMP(saccade.landing_deg_x);
    FOVEA_CMP(saccade.landing_deg_y);
    FOVEA_CMP(saccade.landing_uncertainty_deg);
    FOVEA_CMP(calibrated);
    FOVEA_CMP(device_id);
    FOVEA_CMP(truth);
#undef FOVEA_CMP_EYE
#undef FOVEA_CMP
    return {};
}

ReplayResult replay(const Recording& rec) {
    ReplayResult res;
    res.recorded = rec.gaze.size();
    std::map<uint32_t, std::unique_ptr<gaze::Pipeline>> pipelines;
    std::map<uint32_t, bool> predict;
    std::map<uint32_t, std::vector<gaze::GazeSample>> per_device;
    std::vector<gaze::GazeSample> out;
    const gaze::PipelineConfig cfg = pipeline_config(rec.info);
    for (std::size_t i = 0; i < rec.raw.size(); ++i) {
        const auto& raw = rec.raw[i];
        auto& p = pipelines[raw.device_id];
        if (!p) {
            // construct in the state the live chain had, not toggled afterwards
            gaze::PipelineConfig c = cfg;
            c.predict_landing = rec.raw_predict_landing[i];
            p = std::make_unique<gaze::Pipeline>(c);
            predict[raw.device_id] = c.predict_landing;
        }
        const bool pl = rec.raw_predict_landing[i];
        if (predict[raw.device_id] != pl) {
            p->set_predict_landing(pl);
            predict[raw.device_id] = pl;
        }
        p->process(raw, out);
        if (rec.raw_preroll[i]) continue;  // published before the recording started
        for (auto& s : out) {
            s.device_id = raw.device_id;  // as the daemon stamps it on publish
            per_device[raw.device_id].push_back(s);
            res.gaze.push_back(s);
        }
    }
    for (auto& [id, p] : pipelines) {
        p->flush(out);
        for (auto& s : out) {
            s.device_id = id;
            per_device[id].push_back(s);
            res.gaze.push_back(s);
        }
    }
    res.replayed = res.gaze.size();
    std::map<uint32_t, std::size_t> cursor;
    for (std::size_t i = 0; i < rec.gaze.size(); ++i) {
        const auto& live = rec.gaze[i];
        auto& k = cursor[live.device_id];
        const auto& mine = per_device[live.device_id];
        ++res.compared;
        std::string diff;
        if (k >= mine.size()) {
            diff = "missing in replay";
        } else {
            diff = first_difference(live, mine[k]);
            if (live.event != mine[k].event) ++res.event_mismatches;
        }
        ++k;
        if (!diff.empty()) {
            ++res.mismatches;
            if (res.first_mismatch < 0) {
                res.first_mismatch = static_cast<int64_t>(i);
                res.first_mismatch_field = diff;
            }
        }
    }
    return res;
}

}  // namespace fovea::record
