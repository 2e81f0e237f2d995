// Pupil Capture recordings: a folder (info.player.json, gaze.pldata or pupil.pldata,
// notify/annotation/blinks/fixations .pldata, each with its _timestamps.npy) or one .pldata file.
// Streams are merged by time; gaze (or pupil) datums pass a short reorder window because
// Pupil stores them in mapping order, which runs up to a dozen datums out of time order.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <queue>

#include <nlohmann/json.hpp>

#include "fovea/import/pupil_datum.hpp"
#include "pldata.hpp"
#include "reader_base.hpp"

namespace fovea::import::detail {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kReorderWindow = 64;  // datums; the real files need 12

struct Pending {
    Item kind = Item::kEnd;
    double t = 0.0;
    uint64_t record = 0;
    Sample sample;
    Marker marker;
    LabelledEvent event;
};

struct LaterFirst {
    bool operator()(const Pending& a, const Pending& b) const { return a.t > b.t; }
};

struct Stream {
    std::string name;  // file name, for issue lines
    std::unique_ptr<PldataStream> records;
    std::unique_ptr<NpyDoubles> stamps;
    bool samples = false;  // gaze or pupil datums of this stream become samples
    double blink_onset = gaze::kNaN;
    bool done = false;
    std::priority_queue<Pending, std::vector<Pending>, LaterFirst> ahead;
    bool reported = false;
};

struct StreamSpec {
    std::string name;
    SourceOpener open;
    std::string npy;  // "" if none
    bool samples = false;
};

class PupilReader final : public ReaderBase {
public:
    PupilReader(const std::string& path, const Options& o)
        : ReaderBase(path, Format::kPupilFolder, o) {}

    Result<void> start(const std::vector<StreamSpec>& specs, double rate_hint, bool eye_camera) {
        for (const auto& spec : specs) {
            auto src = spec.open();
            if (!src) return src.error();
            Stream s;
            s.name = spec.name;
            s.records = std::make_unique<PldataStream>(std::move(*src));
            s.samples = spec.samples;
            if (!spec.npy.empty()) {
                if (auto npy = NpyDoubles::open(spec.npy)) {
                    s.stamps = std::move(*npy);
                } else {
                    issue(0, npy.error().message + " (time stamps taken from the datums)");
                }
            }
            streams_.push_back(std::move(s));
        }
        info_.clock = {64, 1e9};  // ns of Pupil time
        info_.measured_rate_hz = rate_hint;
        info_.binocular = true;
        info_.has_pupil = true;
        info_.pupil_unit = "mm";
        info_.coordinates = eye_camera ? Coordinates::kEyeCamera : Coordinates::kSceneCamera;
        return {};
    }

    SourceInfo& mutable_info() { return info_; }

    Item next() override {
        for (;;) {
            Stream* best = nullptr;
            for (auto& s : streams_) {
                fill(s);
                if (!s.ahead.empty() && (!best || s.ahead.top().t < best->ahead.top().t)) best = &s;
            }
            if (!best) {
                finish();
                return Item::kEnd;
            }
            Pending p = best->ahead.top();
            best->ahead.pop();
            if (p.kind == Item::kSample) {
                if (have_last_ && p.t < last_sample_t_) {
                    skip(p.record, best->name + ": more than " + std::to_string(kReorderWindow) +
                                       " datums out of time order: dropped");
                    continue;
                }
                have_last_ = true;
                last_sample_t_ = p.t;
                sample_ = std::move(p.sample);
                return emit_sample(p.record);
            }
            if (p.kind == Item::kMarker) {
                marker_ = std::move(p.marker);
                ++stats_.markers;
                return Item::kMarker;
            }
            event_ = std::move(p.event);
            return emit_event(p.record);
        }
    }

private:
    // Keeps up to the reorder window of items read ahead (one for streams without samples).
    void fill(Stream& s) {
        const std::size_t want = s.samples ? kReorderWindow : 1;
        std::string_view topic, payload;
        while (!s.done && s.ahead.size() < want) {
            if (!s.records->next(topic, payload)) {
                s.done = true;
                break;
            }
            double npy_t = gaze::kNaN;
            if (s.stamps && !s.stamps->next(npy_t) && !s.reported) {
                s.reported = true;
                issue(s.records->records(), s.name + ": more records than _timestamps.npy has");
            }
            datum(s, topic, payload, npy_t);
        }
        if (s.done && !s.reported) {
            s.reported = true;
            if (s.records->resyncs() > 0 || s.records->truncated())
                issue(s.records->records(), s.name + ": " + s.records->last_problem() + " (" +
                                                std::to_string(s.records->resyncs()) + " resyncs)");
            if (s.records->truncated()) stats_.truncated = true;
            stats_.skipped += s.records->resyncs();
            if (s.stamps && s.stamps->size() != s.records->records())
                issue(s.records->records(), s.name + ": " + std::to_string(s.records->records()) +
                                                " records but " + std::to_string(s.stamps->size()) +
                                                " time stamps");
            if (!s.records->error().empty()) error_ = s.name + ": " + s.records->error();
        }
    }

    void datum(Stream& s, std::string_view topic, std::string_view payload, double npy_t) {
        const uint64_t rec = s.records->records();
        auto d = decode_pupil_datum(payload);
        if (!d) {
            skip(rec, s.name + " record " + std::to_string(rec) + ": " + d.error().message);
            return;
        }
        if (d->topic.empty()) d->topic = std::string(topic);
        if (!std::isfinite(d->timestamp)) d->timestamp = npy_t;
        if (!std::isfinite(d->timestamp) || d->timestamp < 0 || d->timestamp > 9e9) {
            skip(rec, s.name + " record " + std::to_string(rec) + ": no usable time stamp");
            return;
        }
        if (std::isfinite(npy_t) && std::fabs(npy_t - d->timestamp) > 1e-6 && !npy_noted_) {
            npy_noted_ = true;
            issue(rec, s.name + ": datum time stamps differ from _timestamps.npy (datums used)");
        }
        Pending p;
        p.t = d->timestamp;
        p.record = rec;
        if (s.samples && (d->is_gaze() || d->is_pupil())) {
            p.kind = Item::kSample;
            p.sample.labels.fill(gaze::Event::kUnknown);
            p.sample.label_codes.fill(-1);
            if (!pupil_sample(*d, options_.min_confidence, p.sample.raw)) {
                skip(rec, s.name + " record " + std::to_string(rec) + ": no norm_pos");
                return;
            }
            p.sample.time_s = d->timestamp;
            p.sample.confidence = d->confidence;
            p.sample.pupil_raw = {d->diameter_mm[1], d->diameter_mm[0]};  // left = eye1
            if (!d->from_eye(0) || !d->from_eye(1)) saw_monocular_ = true;
        } else if (d->topic.starts_with("notify.") || d->topic == "annotation" ||
                   d->topic.starts_with("annotation.")) {
            p.kind = Item::kMarker;
            p.marker.time_s = d->timestamp;
            p.marker.device_ticks = ticks(d->timestamp);
            p.marker.line = rec;
            p.marker.text = d->topic;
            if (d->topic.starts_with("annotation")) {
                auto label = label_of(payload);
                if (!label.empty()) p.marker.text = "annotation " + label;
            }
        } else if (d->topic.starts_with("blinks")) {
            if (d->type == "onset") s.blink_onset = d->timestamp;
            if (d->type != "offset" || !std::isfinite(s.blink_onset)) return;
            p.kind = Item::kEvent;
            p.event.type = gaze::Event::kBlink;
            p.event.start_s = s.blink_onset;
            p.event.end_s = d->timestamp;
            s.blink_onset = gaze::kNaN;
        } else if (d->topic.starts_with("fixations")) {
            if (!(d->duration_ms >= 0)) return;
            p.kind = Item::kEvent;
            p.event.type = gaze::Event::kFixation;
            p.event.start_s = d->timestamp;
            p.event.end_s = d->timestamp + d->duration_ms * 1e-3;
            p.t = p.event.end_s;  // delivered once it has ended
            if (std::isfinite(d->norm_x)) {
                p.event.x = d->norm_x;
                p.event.y = 1.0 - d->norm_y;
            }
        } else {
            ++unused_;
            return;
        }
        if (p.kind == Item::kEvent) {
            p.event.source = "pupil";
            p.event.eye = Eye::kBoth;
        }
        s.ahead.push(std::move(p));
    }

    // Annotations carry their text under "label".
    static std::string label_of(std::string_view payload) {
        msgpack::object_handle oh;
        if (!msgpack_read::unpack_one(payload, oh)) return {};
        return msgpack_read::text(msgpack_read::find(oh.get(), "label")).value_or("");
    }

    void finish() {
        for (const auto& s : streams_) stats_.bytes += s.records->bytes();
        stats_.lines = 0;
        for (const auto& s : streams_) stats_.lines += s.records->records();
        if (unused_ && !unused_noted_) {
            unused_noted_ = true;
            issue(0, std::to_string(unused_) + " datums of other topics not used");
        }
        if (saw_monocular_ && !variant_noted_) {
            variant_noted_ = true;
            info_.variant += " (some monocular datums)";
        }
    }

    std::vector<Stream> streams_;
    double last_sample_t_ = 0;
    bool have_last_ = false, npy_noted_ = false, saw_monocular_ = false;
    bool unused_noted_ = false, variant_noted_ = false;
    uint64_t unused_ = 0;
};

// The folder's streams: samples from gaze.pldata, else pupil.pldata; every other .pldata for
// its markers and events.
Result<std::vector<StreamSpec>> folder_streams(const fs::path& dir, bool& eye_camera) {
    std::vector<fs::path> files;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec))
        if (e.path().extension() == ".pldata") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    if (files.empty()) return make_error(dir.string() + ": no .pldata files");
    const bool has_gaze = fs::exists(dir / "gaze.pldata", ec);
    eye_camera = true;
    std::vector<StreamSpec> out;
    for (const auto& f : files) {
        const std::string stem = f.stem().string();
        if (has_gaze && stem == "pupil") continue;  // its diameters are in gaze's base_data
        StreamSpec s;
        s.name = f.filename().string();
        s.open = [p = f.string()] { return ByteSource::file(p); };
        const fs::path npy = dir / (stem + "_timestamps.npy");
        if (fs::exists(npy, ec)) s.npy = npy.string();
        const bool gaze = stem.find("gaze") != std::string::npos;
        s.samples = gaze || (!has_gaze && stem == "pupil");
        if (gaze) eye_camera = false;
        out.push_back(std::move(s));
    }
    return out;
}

// The recording software from info.player.json (Pupil Capture 1.16+ writes it).
std::string recording_software(const fs::path& dir) {
    std::ifstream in(dir / "info.player.json", std::ios::binary);
    if (!in) return "Pupil (no info.player.json)";
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    return pupil_recording_software(text);
}

Result<std::unique_ptr<PupilReader>> make(const std::string& path,
                                          const std::vector<StreamSpec>& specs,
                                          const Options& options, double rate, bool eye_camera) {
    auto r = std::make_unique<PupilReader>(path, options);
    if (auto ok = r->start(specs, rate, eye_camera); !ok) return ok.error();
    return r;
}

Result<std::unique_ptr<Reader>> open_specs(const std::string& path,
                                           const std::vector<StreamSpec>& specs,
                                           const Options& options, bool eye_camera,
                                           const std::function<void(SourceInfo&)>& describe) {
    double rate = options.rate_hz;
    if (rate <= 0) {
        auto first = make(path, specs, options, 0.0, eye_camera);
        if (!first) return first.error();
        rate = measure_rate(**first);
    }
    auto r = make(path, specs, options, rate, eye_camera);
    if (!r) return r.error();
    describe((*r)->mutable_info());
    return std::unique_ptr<Reader>(std::move(*r));
}

}  // namespace

std::string pupil_recording_software(std::string_view info_player_json) {
    try {
        const auto j = nlohmann::json::parse(info_player_json);
        return j.value("recording_software_name", std::string("Pupil")) + " " +
               j.value("recording_software_version", std::string());
    } catch (const std::exception&) { return "Pupil (info.player.json unreadable)"; }
}

Result<std::unique_ptr<Reader>> open_pldata(const SourceOpener& source, const std::string& path,
                                            const Options& options, double) {
    StreamSpec s{fs::path(path).filename().string(), source, "", true};
    return open_specs(path, {s}, options, false,
                      [](SourceInfo& i) { i.variant = "pldata stream"; });
}

Result<std::unique_ptr<Reader>> open_pupil_path(const std::string& path, const Options& options) {
    const fs::path p(path);
    std::error_code ec;
    if (fs::is_directory(p, ec)) {
        bool eye_camera = false;
        auto specs = folder_streams(p, eye_camera);
        if (!specs) return specs.error();
        return open_specs(path, *specs, options, eye_camera, [&](SourceInfo& i) {
            i.device = recording_software(p);
            i.variant = eye_camera ? "recording, pupil datums (no gaze.pldata)" : "recording, gaze";
        });
    }
    StreamSpec s;
    s.name = p.filename().string();
    s.open = [path] { return ByteSource::file(path); };
    const fs::path npy = p.parent_path() / (p.stem().string() + "_timestamps.npy");
    if (fs::exists(npy, ec)) s.npy = npy.string();
    s.samples = true;
    const bool eye_camera = p.stem() == "pupil";
    return open_specs(path, {s}, options, eye_camera,
                      [](SourceInfo& i) { i.variant = "pldata file"; });
}

}  // namespace fovea::import::detail
