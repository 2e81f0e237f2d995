// Pupil's CSV files, told apart by their columns: Pupil Player's gaze_positions.csv,
// pupil_positions.csv, blinks.csv and fixations.csv exports, and gaze relayed by Pupil's LSL
// plugin and recorded to CSV. Rows become PupilDatums, so the sample mapping is the one the
// recording importer and the live driver use. Pupil writes gaze in mapping order (up to a
// dozen rows out of time order): samples pass a reorder window.
#include <queue>

#include "fovea/import/pupil_datum.hpp"
#include "reader_base.hpp"

namespace fovea::import::detail {
namespace {

constexpr std::size_t kReorderWindow = 64;

enum class Kind { kGaze, kPupil, kLsl, kBlinks, kFixations };

struct Later {
    bool operator()(const Sample& a, const Sample& b) const { return a.time_s > b.time_s; }
};

class PupilCsvReader final : public ReaderBase {
public:
    PupilCsvReader(std::unique_ptr<ByteSource> src, const std::string& path, const Options& o)
        : ReaderBase(path, Format::kPupilCsv, o), lines_(std::move(src)) {}

    Result<void> start(double rate_hint) {
        std::string_view line;
        if (!lines_.next(line)) return make_error(info_.path + ": empty file");
        split(trim(line), ',', fields_);
        for (auto f : fields_) columns_.emplace_back(trim(f));
        const auto has = [&](const char* c) { return column_index(columns_, c) >= 0; };
        if (has("gaze_timestamp")) {
            kind_ = Kind::kGaze;
            t_ = col("gaze_timestamp");
        } else if (has("pupil_timestamp") && has("eye_id")) {
            kind_ = Kind::kPupil;
            t_ = col("pupil_timestamp");
        } else if (has("timestamp") && has("norm_pos_x")) {
            kind_ = Kind::kLsl;
            t_ = col("timestamp");
        } else if (has("start_timestamp") && has("end_timestamp")) {
            kind_ = Kind::kBlinks;
            t_ = col("start_timestamp");
        } else if (has("start_timestamp") && has("duration") && has("dispersion")) {
            kind_ = Kind::kFixations;
            t_ = col("start_timestamp");
        } else {
            return make_error(info_.path +
                              ":1: not a Pupil CSV (expected gaze_timestamp, pupil_timestamp, "
                              "timestamp + norm_pos_x, or a blinks/fixations export)");
        }
        static const char* kVariant[] = {"player gaze_positions export",
                                         "player pupil_positions export", "LSL relay recording",
                                         "player blinks export", "player fixations export"};
        info_.variant = kVariant[static_cast<int>(kind_)];
        info_.device = "Pupil";
        info_.clock = {64, 1e9};
        info_.measured_rate_hz = rate_hint;
        info_.binocular = kind_ != Kind::kPupil;
        info_.has_pupil = kind_ == Kind::kLsl || kind_ == Kind::kPupil;
        info_.pupil_unit = "mm";
        info_.coordinates =
            kind_ == Kind::kPupil ? Coordinates::kEyeCamera : Coordinates::kSceneCamera;
        conf_ = col("confidence");
        x_ = col("norm_pos_x");
        y_ = col("norm_pos_y");
        base_ = col("base_data");
        point3d_ = col("gaze_point_3d_x");
        eye_id_ = col("eye_id");
        for (int e = 0; e < 2; ++e) {
            const std::string k = std::to_string(e);
            d3_[e] = col(("diameter" + k + "_3d").c_str());
            center_[e] = col(("eye_center" + k + "_3d_x").c_str());
        }
        diameter_3d_ = col("diameter_3d");
        end_ = col("end_timestamp");
        duration_ = col("duration");
        return {};
    }

    Item next() override {
        for (;;) {
            while (!eof_ && !have_event_ && ahead_.size() < kReorderWindow) read_one();
            if (have_event_) {
                have_event_ = false;
                return emit_event(event_.line);
            }
            if (ahead_.empty()) {
                end_of_text(lines_);
                return Item::kEnd;
            }
            Sample s = ahead_.top();
            ahead_.pop();
            if (have_last_ && s.time_s < last_t_) {
                skip(s.line, "more than " + std::to_string(kReorderWindow) +
                                 " rows out of time order: dropped");
                continue;
            }
            have_last_ = true;
            last_t_ = s.time_s;
            sample_ = std::move(s);
            return emit_sample(sample_.line);
        }
    }

private:
    int col(const char* name) const { return column_index(columns_, name); }

    double field(int c) const {
        double v = gaze::kNaN;
        if (c >= 0 && static_cast<std::size_t>(c) < fields_.size()) parse_double(fields_[c], v);
        return v;
    }

    // Reads lines until one row became a sample in the window or the pending event, or the
    // input ended.
    void read_one() {
        std::string_view line;
        uint64_t n = 0;
        while (next_row(lines_, {}, columns_.size(), line, fields_, n)) {
            const double t = field(t_);
            if (!std::isfinite(t) || t < 0 || t > 9e9) {
                skip(n, "time stamp is not a number of seconds: '" + printable(line) + "'");
                continue;
            }
            if (kind_ == Kind::kBlinks || kind_ == Kind::kFixations ? event_row(n, t)
                                                                    : sample_row(n, t))
                return;
        }
        eof_ = true;
    }

    bool event_row(uint64_t n, double t) {
        reset_event();
        event_.source = "pupil";
        event_.eye = Eye::kBoth;
        event_.start_s = t;
        if (kind_ == Kind::kBlinks) {
            event_.type = gaze::Event::kBlink;
            event_.end_s = field(end_);
        } else {
            event_.type = gaze::Event::kFixation;
            event_.end_s = t + field(duration_) * 1e-3;  // Player writes fixation ms
            event_.x = field(x_);
            event_.y = 1.0 - field(y_);
        }
        if (!(event_.end_s >= event_.start_s)) {
            skip(n, "event ends before it starts");
            return false;
        }
        event_.line = n;
        have_event_ = true;
        return true;
    }

    bool sample_row(uint64_t n, double t) {
        PupilDatum d;
        d.timestamp = t;
        d.confidence = field(conf_);
        d.norm_x = field(x_);
        d.norm_y = field(y_);
        const char* dims = point3d_ >= 0 ? "3d" : "2d";
        if (kind_ == Kind::kPupil) {
            const double id = field(eye_id_);
            if (!(id == 0 || id == 1)) {
                skip(n, "eye_id is not 0 or 1");
                return false;
            }
            d.eye_id = static_cast<int>(id);
            d.topic = "pupil." + std::to_string(d.eye_id);
            d.diameter_mm[static_cast<std::size_t>(d.eye_id)] = field(diameter_3d_);
        } else {
            bool eye[2] = {false, false};
            if (kind_ == Kind::kGaze && base_ >= 0) {
                // "1216.221478-0 1216.215944-1": the pupil datums' times and eye ids.
                const std::string_view b = fields_[base_];
                eye[0] = b.find("-0") != std::string_view::npos;
                eye[1] = b.find("-1") != std::string_view::npos;
            } else {
                for (int e = 0; e < 2; ++e)
                    eye[e] = std::isfinite(field(d3_[e])) || std::isfinite(field(center_[e]));
            }
            if (!eye[0] && !eye[1]) eye[0] = eye[1] = true;  // no eye information: both
            d.topic =
                std::string("gaze.") + dims + "." + (eye[0] ? "0" : "") + (eye[1] ? "1" : "") + ".";
            for (int e = 0; e < 2; ++e) d.diameter_mm[static_cast<std::size_t>(e)] = field(d3_[e]);
        }
        Sample s;
        s.labels.fill(gaze::Event::kUnknown);
        s.label_codes.fill(-1);
        pupil_sample(d, options_.min_confidence, s.raw);
        s.time_s = t;
        s.confidence = d.confidence;
        s.pupil_raw = {d.diameter_mm[1], d.diameter_mm[0]};
        s.line = n;
        ahead_.push(std::move(s));
        return true;
    }

    LineReader lines_;
    std::vector<std::string> columns_;
    std::vector<std::string_view> fields_;
    Kind kind_ = Kind::kGaze;
    int t_ = -1, conf_ = -1, x_ = -1, y_ = -1, base_ = -1, point3d_ = -1, eye_id_ = -1;
    int d3_[2] = {-1, -1}, center_[2] = {-1, -1}, diameter_3d_ = -1, end_ = -1, duration_ = -1;
    std::priority_queue<Sample, std::vector<Sample>, Later> ahead_;
    bool eof_ = false, have_event_ = false, have_last_ = false;
    double last_t_ = 0;
};

}  // namespace

Result<std::unique_ptr<Reader>> open_pupil_csv(const SourceOpener& source, const std::string& path,
                                               const Options& options, double rate_hint) {
    return open_text_reader<PupilCsvReader>(source, path, options, rate_hint);
}

}  // namespace fovea::import::detail
