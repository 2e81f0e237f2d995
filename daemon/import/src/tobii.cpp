// Tobii exports. kTobiiCsv: the Tobii Pro SDK's gaze data fields, one row per sample
// (';'-separated, or tab-separated with a leading row index as pandas writes them):
// device_time_stamp (µs), per eye gaze_point_on_display_area "(x, y)" (normalized, top-left),
// gaze_point_validity, pupil_diameter (mm), pupil_validity. kTobiiTsv: Tobii Studio / Pro Lab
// TSV exports — a "Key: value" preamble, then a column line: gaze data (Studio or Pro Lab
// column names), fixation data (-> fixation events) or event data (-> markers).
#include <cctype>

#include "reader_base.hpp"

namespace fovea::import::detail {
namespace {

// "(0.137, 0.636)" -> 0.137, 0.636; false for junk.
bool tuple2(std::string_view s, double& a, double& b) {
    s = trim(s);
    if (s.size() < 2 || s.front() != '(' || s.back() != ')') return false;
    s = s.substr(1, s.size() - 2);
    const auto comma = s.find(',');
    return comma != std::string_view::npos && parse_double(s.substr(0, comma), a) &&
           parse_double(s.substr(comma + 1), b);
}

class TobiiSdkReader final : public ReaderBase {
public:
    TobiiSdkReader(std::unique_ptr<ByteSource> src, const std::string& path, const Options& o)
        : ReaderBase(path, Format::kTobiiCsv, o), lines_(std::move(src)) {}

    Result<void> start(double rate_hint) {
        std::string_view line;
        if (!lines_.next(line)) return make_error(info_.path + ": empty file");
        sep_ = line.find(';') != std::string_view::npos ? ';' : '\t';
        split(line, sep_, fields_);
        for (auto f : fields_) columns_.emplace_back(trim(f));
        t_ = column_index(columns_, "device_time_stamp");
        const char* eyes[2] = {"left_", "right_"};
        for (int e = 0; e < 2; ++e) {
            const std::string p = eyes[e];
            eye_[e] = {column_index(columns_, p + "gaze_point_on_display_area"),
                       column_index(columns_, p + "gaze_point_validity"),
                       column_index(columns_, p + "pupil_diameter"),
                       column_index(columns_, p + "pupil_validity")};
        }
        if (t_ < 0 || eye_[0].point < 0 || eye_[1].point < 0 || eye_[0].valid < 0 ||
            eye_[1].valid < 0)
            return make_error(info_.path +
                              ":1: a Tobii Pro SDK export needs device_time_stamp and "
                              "left/right_gaze_point_on_display_area and _validity");
        info_.device = "Tobii Pro SDK";
        info_.variant = sep_ == ';' ? "';'-separated" : "tab-separated";
        info_.clock = {64, 1e6};
        info_.measured_rate_hz = rate_hint;
        info_.binocular = true;
        info_.has_pupil = eye_[0].pupil >= 0;
        info_.pupil_unit = "mm";
        info_.coordinates = Coordinates::kDisplay;
        return {};
    }

    Item next() override {
        std::string_view line;
        uint64_t n = 0;
        const RowFormat row{.sep = sep_, .trim_line = false, .exact = true};
        while (next_row(lines_, row, columns_.size(), line, fields_, n)) {
            double t = 0;
            if (!parse_double(fields_[t_], t) || !std::isfinite(t)) {
                skip(n, "device_time_stamp is not a number");
                continue;
            }
            reset_sample();
            bool ok = true;
            for (int e = 0; e < 2; ++e)
                ok = ok && eye(eye_[e], e == 0 ? sample_.raw.left : sample_.raw.right,
                               sample_.pupil_raw[static_cast<std::size_t>(e)]);
            if (!ok) {
                skip(n, "gaze point or validity unreadable: '" + printable(line) + "'");
                continue;
            }
            if (!place(t * 1e-6, n)) continue;
            return emit_sample(n);
        }
        end_of_text(lines_);
        return Item::kEnd;
    }

private:
    struct EyeColumns {
        int point = -1, valid = -1, pupil = -1, pupil_valid = -1;
    };

    bool eye(const EyeColumns& c, gaze::EyeSample& e, double& pupil_raw) {
        double v = 0, x = 0, y = 0;
        if (!parse_double(fields_[c.valid], v)) return false;
        if (c.pupil >= 0) {
            double pv = 1, p = 0;
            if (c.pupil_valid >= 0) parse_double(fields_[c.pupil_valid], pv);
            if (parse_double(fields_[c.pupil], p) && std::isfinite(p) && p > 0 && pv == 1) {
                e.pupil_mm = p;
                pupil_raw = p;
            }
        }
        if (v != 1) return true;  // the tracker says this eye is not valid
        if (!tuple2(fields_[c.point], x, y)) return false;
        if (!std::isfinite(x) || !std::isfinite(y)) return true;
        e.x = x;
        e.y = y;
        e.valid = true;
        return true;
    }

    LineReader lines_;
    char sep_ = ';';
    std::vector<std::string> columns_;
    std::vector<std::string_view> fields_;
    int t_ = -1;
    EyeColumns eye_[2];
};

// EMDAT's list of Tobii fixations and saccades: "label,x,y,start,end,duration" with start/end
// in µs of the SDK's system clock. x/y are in units the file does not state: not used.
class TobiiEventListReader final : public ReaderBase {
public:
    TobiiEventListReader(std::unique_ptr<ByteSource> src, const std::string& path, const Options& o)
        : ReaderBase(path, Format::kTobiiCsv, o), lines_(std::move(src)) {}

    Result<void> start(double) {
        std::string_view line;
        if (!lines_.next(line) || !trim(line).starts_with("label,x,y,start,end"))
            return make_error(info_.path + ":1: not a label,x,y,start,end,duration list");
        info_.device = "Tobii (EMDAT event list)";
        info_.variant = "fixation/saccade list";
        info_.clock = {64, 1e6};
        return {};
    }

    Item next() override {
        std::string_view line;
        std::vector<std::string_view> f;
        while (lines_.next(line)) {
            const uint64_t n = lines_.line_number();
            if (trim(line).empty()) continue;
            if (cut_off(lines_, n)) break;
            split(trim(line), ',', f);
            double start = 0, end = 0;
            const std::string_view label = f.empty() ? "" : trim(f[0]);
            if (f.size() < 5 || !parse_double(f[3], start) || !parse_double(f[4], end) ||
                !(end >= start) || (label != "fixation" && label != "saccade")) {
                skip(n, "expected fixation|saccade,x,y,start_us,end_us,...: '" + printable(line) +
                            "'");
                continue;
            }
            reset_event();
            event_.type = label == "fixation" ? gaze::Event::kFixation : gaze::Event::kSaccade;
            event_.source = "tobii";
            event_.start_s = start * 1e-6;
            event_.end_s = end * 1e-6;
            return emit_event(n);
        }
        end_of_text(lines_);
        return Item::kEnd;
    }

private:
    LineReader lines_;
};

// ---- Tobii Studio / Pro Lab TSV -------------------------------------------------------------

enum class TsvKind { kGaze, kFixations, kEvents };

class TobiiTsvReader final : public ReaderBase {
public:
    TobiiTsvReader(std::unique_ptr<ByteSource> src, const std::string& path, const Options& o)
        : ReaderBase(path, Format::kTobiiTsv, o), lines_(std::move(src)) {}

    Result<void> start(double rate_hint) {
        std::string_view line;
        while (lines_.next(line)) {
            if (lines_.line_number() > 200) break;
            const std::string_view l = trim(line);
            if (l.empty()) continue;
            split(line, '\t', fields_);
            std::vector<std::string> cols;
            for (auto f : fields_) cols.emplace_back(trim(f));
            while (!cols.empty() && cols.back().empty()) cols.pop_back();
            if (header(cols)) break;
            preamble(l);
        }
        if (columns_.empty())
            return make_error(info_.path +
                              ": no Tobii column line (Timestamp / RecordingTimestamp / "
                              "Recording timestamp ...) in the first 200 lines");
        info_.device = "Tobii Studio / Pro Lab";
        info_.clock = {64, 1e6};
        info_.measured_rate_hz = rate_hint;
        info_.coordinates = Coordinates::kDisplay;
        return {};
    }

    Item next() override {
        std::string_view line;
        uint64_t n = 0;
        const RowFormat row{.sep = '\t', .trim_line = false};
        while (next_row(lines_, row, min_fields_, line, fields_, n)) {
            double t = 0;
            if (!parse_double(fields_[t_], t) || !std::isfinite(t) || t < 0) {
                skip(n, "time stamp is not a number: '" + printable(line) + "'");
                continue;
            }
            const double t_s = t * time_scale_;
            if (kind_ == TsvKind::kEvents) {
                std::string text;
                for (std::size_t i = 0; i < fields_.size(); ++i) {
                    if (static_cast<int>(i) == t_) continue;
                    const auto f = trim(fields_[i]);
                    if (!f.empty()) text += (text.empty() ? "" : " ") + std::string(f);
                }
                return emit_marker(t_s, std::move(text), n);
            }
            if (kind_ == TsvKind::kFixations) {
                double dur = 0, x = gaze::kNaN, y = gaze::kNaN;
                if (!parse_double(fields_[dur_], dur) || dur < 0) {
                    skip(n, "FixationDuration is not a number");
                    continue;
                }
                reset_event();
                event_.type = gaze::Event::kFixation;
                event_.source = "tobii";
                event_.eye = Eye::kBoth;
                event_.start_s = t_s;
                event_.end_s = t_s + dur * 1e-3;
                if (parse_double(fields_[x_], x) && parse_double(fields_[y_], y))
                    normalize(x, y, event_.x, event_.y);
                return emit_event(n);
            }
            if (gaze_row(n, t_s)) return emit_sample(n);
        }
        end_of_text(lines_);
        return Item::kEnd;
    }

private:
    int col(const std::vector<std::string>& c, std::initializer_list<const char*> names) const {
        for (const char* n : names)
            if (const int i = column_index(c, n); i >= 0) return i;
        return -1;
    }

    // Recognizes the column line of one of the three exports.
    bool header(const std::vector<std::string>& c) {
        const int t = col(c, {"RecordingTimestamp", "Recording timestamp", "Timestamp",
                              "Recording timestamp [ms]", "Recording timestamp [μs]"});
        if (t < 0) return false;
        t_ = t;
        // Pro Lab states its unit; Studio and older Pro Lab use ms.
        time_scale_ = c[t].find("μs") != std::string::npos ? 1e-6 : 1e-3;
        if (const int f = col(c, {"FixationIndex"}); f >= 0 && col(c, {"FixationDuration"}) >= 0) {
            kind_ = TsvKind::kFixations;
            dur_ = col(c, {"FixationDuration"});
            x_ = col(c, {"MappedFixationPointX", "FixationPointX (MCSpx)", "FixationPointX"});
            y_ = col(c, {"MappedFixationPointY", "FixationPointY (MCSpx)", "FixationPointY"});
            if (x_ < 0 || y_ < 0) return false;
            info_.variant = "fixation data export";
        } else if (col(c, {"Event"}) >= 0 && col(c, {"EventKey"}) >= 0) {
            kind_ = TsvKind::kEvents;
            info_.variant = "event data export";
        } else {
            kind_ = TsvKind::kGaze;
            const char* side[2] = {"Left", "Right"};
            const char* pro[2] = {"left", "right"};
            for (int e = 0; e < 2; ++e) {
                const std::string s = side[e], p = pro[e];
                eye_[e].x =
                    col(c, {("GazePoint" + s + "X (ADCSpx)").c_str(), ("GazePointX" + s).c_str(),
                            ("Gaze point " + p + " X").c_str()});
                eye_[e].y =
                    col(c, {("GazePoint" + s + "Y (ADCSpx)").c_str(), ("GazePointY" + s).c_str(),
                            ("Gaze point " + p + " Y").c_str()});
                eye_[e].valid = col(c, {("Validity" + s).c_str(), ("Validity " + p).c_str()});
                eye_[e].pupil = col(c, {("Pupil" + s).c_str(), ("Pupil diameter " + p).c_str()});
            }
            movement_ = col(c, {"GazeEventType", "Eye movement type"});
            res_w_ = col(c, {"Recording resolution width"});
            res_h_ = col(c, {"Recording resolution height"});
            if (eye_[0].x < 0 || eye_[0].y < 0 || eye_[1].x < 0 || eye_[1].y < 0) return false;
            info_.variant = "gaze data export";
            info_.binocular = true;
            info_.has_pupil = eye_[0].pupil >= 0;
            info_.pupil_unit = "mm";
            if (movement_ >= 0) {
                info_.label_columns = {c[static_cast<std::size_t>(movement_)]};
                info_.label_codes = "1 Fixation, 2 Saccade, 0 Unclassified / EyesNotFound";
            }
        }
        columns_ = c;
        min_fields_ = 1;
        for (int i : {t_, dur_, x_, y_, eye_[0].x, eye_[0].y, eye_[1].x, eye_[1].y})
            min_fields_ = std::max(min_fields_, static_cast<std::size_t>(i + 1));
        return true;
    }

    // "Recording resolution: 1280 x 1024" / "Screen resolution: 1280 x 1024".
    void preamble(std::string_view l) {
        const auto colon = l.find(':');
        if (colon == std::string_view::npos) return;
        const std::string_view key = trim(l.substr(0, colon)), value = trim(l.substr(colon + 1));
        if (key.find("resolution") == std::string_view::npos) return;
        const auto x = value.find('x');
        double w = 0, h = 0;
        if (x != std::string_view::npos && parse_double(value.substr(0, x), w) &&
            parse_double(value.substr(x + 1), h) && w >= 1 && h >= 1 && w < 1e6 && h < 1e6) {
            info_.screen.width_px = static_cast<int>(w);
            info_.screen.height_px = static_cast<int>(h);
        }
    }

    void normalize(double x, double y, double& nx, double& ny) {
        double w = info_.screen.width_px, h = info_.screen.height_px;
        if (res_w_ >= 0 && res_h_ >= 0) {
            double rw = 0, rh = 0;
            if (parse_double(optional_field(res_w_), rw) &&
                parse_double(optional_field(res_h_), rh) && rw >= 1 && rh >= 1) {
                w = rw;
                h = rh;
            }
        }
        if (!(w >= 1 && h >= 1)) {
            const auto d = fallback_display(lines_.line_number(), "no recording resolution");
            w = d.width_px;
            h = d.height_px;
        }
        nx = x / w;
        ny = y / h;
    }

    // Validity and pupil columns may be cut from a short row (min_fields_ covers only the
    // columns a row cannot do without): absent reads as empty.
    std::string_view optional_field(int i) const {
        return static_cast<std::size_t>(i) < fields_.size() ? fields_[static_cast<std::size_t>(i)]
                                                            : std::string_view{};
    }

    bool gaze_row(uint64_t n, double t_s) {
        reset_sample();
        for (int e = 0; e < 2; ++e) {
            gaze::EyeSample& s = e == 0 ? sample_.raw.left : sample_.raw.right;
            const auto& c = eye_[e];
            double x = 0, y = 0, p = 0;
            bool valid = true;
            if (c.valid >= 0) {
                const auto v = trim(optional_field(c.valid));
                double code = 0;
                // Studio: 0 (certain) .. 4 (eye not found), 0 and 1 usable; Pro Lab: Valid/Invalid.
                valid = v == "Valid" || (parse_double(v, code) && code <= 1);
            }
            if (c.pupil >= 0 && parse_double(optional_field(c.pupil), p) && std::isfinite(p) &&
                p > 0) {
                s.pupil_mm = p;
                sample_.pupil_raw[static_cast<std::size_t>(e)] = p;
            }
            if (valid && parse_double(fields_[c.x], x) && parse_double(fields_[c.y], y) &&
                std::isfinite(x) && std::isfinite(y)) {
                normalize(x, y, s.x, s.y);
                s.valid = true;
            }
        }
        if (movement_ >= 0 && static_cast<std::size_t>(movement_) < fields_.size()) {
            const auto m = trim(fields_[movement_]);
            const bool fix = m == "Fixation", sac = m == "Saccade";
            sample_.labels[0] = fix   ? gaze::Event::kFixation
                                : sac ? gaze::Event::kSaccade
                                      : gaze::Event::kUnknown;
            sample_.label_codes[0] = fix ? 1 : sac ? 2 : 0;
        }
        return place(t_s, n);
    }

    struct EyeColumns {
        int x = -1, y = -1, valid = -1, pupil = -1;
    };

    LineReader lines_;
    std::vector<std::string> columns_;
    std::vector<std::string_view> fields_;
    TsvKind kind_ = TsvKind::kGaze;
    int t_ = -1, dur_ = -1, x_ = -1, y_ = -1, movement_ = -1, res_w_ = -1, res_h_ = -1;
    double time_scale_ = 1e-3;
    std::size_t min_fields_ = 1;
    EyeColumns eye_[2];
};

}  // namespace

Result<std::unique_ptr<Reader>> open_tobii_csv(const SourceOpener& source, const std::string& path,
                                               const Options& options, double rate_hint) {
    auto src = source();
    if (!src) return src.error();
    char head[32] = {};
    const std::size_t n = (*src)->read(head, sizeof head);
    if (std::string_view(head, n).starts_with("label,x,y,start,end"))
        return open_text_reader<TobiiEventListReader>(source, path, options, rate_hint);
    return open_text_reader<TobiiSdkReader>(source, path, options, rate_hint);
}

Result<std::unique_ptr<Reader>> open_tobii_tsv(const SourceOpener& source, const std::string& path,
                                               const Options& options, double rate_hint) {
    return open_text_reader<TobiiTsvReader>(source, path, options, rate_hint);
}

}  // namespace fovea::import::detail
