// The CSV `fovea record --out FILE.csv` writes: "# fovea gaze recording v1 ...", a column line,
// one published sample a row. Columns are found by name.
#include "reader_base.hpp"

namespace fovea::import::detail {
namespace {

gaze::Event event_from_name(std::string_view s) {
    s = trim(s);
    if (s == "fixation") return gaze::Event::kFixation;
    if (s == "saccade") return gaze::Event::kSaccade;
    if (s == "pso") return gaze::Event::kPso;
    if (s == "pursuit") return gaze::Event::kPursuit;
    if (s == "blink") return gaze::Event::kBlink;
    return gaze::Event::kUnknown;
}

class FoveaCsvReader final : public ReaderBase {
public:
    FoveaCsvReader(std::unique_ptr<ByteSource> src, const std::string& path, const Options& o)
        : ReaderBase(path, Format::kFoveaCsv, o), lines_(std::move(src)) {}

    Result<void> start(double rate_hint) {
        std::string_view line;
        if (!lines_.next(line)) return make_error(info_.path + ": empty file");
        if (!trim(line).starts_with("# fovea"))
            return make_error(info_.path + ":1: not a fovea CSV ('# fovea ...' header)");
        info_.device = std::string(trim(trim(line).substr(1)));
        while (lines_.next(line) && (trim(line).empty() || trim(line).front() == '#')) {}
        if (trim(line).empty() || trim(line).front() == '#')
            return make_error(info_.path + ": missing the column line");
        split(trim(line), ',', fields_);
        for (auto f : fields_) columns_.emplace_back(trim(f));
        const uint64_t n = lines_.line_number();
        t_ = column_index(columns_, "t_capture_ns");
        for (int e = 0; e < 2; ++e) {
            const std::string p = e == 0 ? "left_" : "right_";
            eye_[e] = {column_index(columns_, p + "x"), column_index(columns_, p + "y"),
                       column_index(columns_, p + "pupil_mm"), column_index(columns_, p + "valid")};
        }
        event_col_ = column_index(columns_, "event");
        if (t_ < 0 || eye_[0].x < 0 || eye_[0].y < 0 || eye_[0].valid < 0)
            return make_error(info_.path + ":" + std::to_string(n) +
                              ": the column line needs t_capture_ns, left_x, left_y, left_valid");
        info_.binocular = eye_[1].x >= 0 && eye_[1].y >= 0 && eye_[1].valid >= 0;
        if (!info_.binocular) eye_[1] = {};
        info_.has_pupil = eye_[0].pupil >= 0;
        info_.clock = {64, 1e9};
        info_.measured_rate_hz = rate_hint;
        info_.coordinates = Coordinates::kDisplay;
        info_.variant = info_.binocular ? "binocular" : "left eye";
        if (event_col_ >= 0) {
            info_.label_columns = {"event"};
            info_.label_codes = "the chain's own event names (fixation, saccade, ...)";
        }
        return {};
    }

    Item next() override {
        std::string_view line;
        uint64_t n = 0;
        while (next_row(lines_, {.comment = '#'}, columns_.size(), line, fields_, n)) {
            int64_t t = 0;
            if (!parse_int(fields_[t_], t) || t < 0) {
                skip(n, "t_capture_ns is not a non-negative integer");
                continue;
            }
            reset_sample();
            if (!read_eye(eye_[0], sample_.raw.left) ||
                (info_.binocular && !read_eye(eye_[1], sample_.raw.right))) {
                skip(n, "eye fields are not numbers: '" + printable(line) + "'");
                continue;
            }
            if (!place(static_cast<double>(t) * 1e-9, n)) continue;
            if (!sample_.time_repaired) sample_.raw.device_ticks = static_cast<uint64_t>(t);
            if (event_col_ >= 0) {
                sample_.labels[0] = event_from_name(fields_[event_col_]);
                sample_.label_codes[0] = static_cast<int16_t>(sample_.labels[0]);
            }
            return emit_sample(n);
        }
        end_of_text(lines_);
        return Item::kEnd;
    }

private:
    struct EyeColumns {
        int x = -1, y = -1, pupil = -1, valid = -1;
    };

    bool read_eye(const EyeColumns& c, gaze::EyeSample& e) {
        double v = 0, x = 0, y = 0, p = 0;
        if (!parse_double(fields_[c.valid], v)) return false;
        if (v == 0) return true;
        if (!parse_double(fields_[c.x], x) || !parse_double(fields_[c.y], y) || !std::isfinite(x) ||
            !std::isfinite(y))
            return false;
        if (c.pupil >= 0 && parse_double(fields_[c.pupil], p) && std::isfinite(p)) e.pupil_mm = p;
        e.x = x;
        e.y = y;
        e.valid = true;
        return true;
    }

    LineReader lines_;
    std::vector<std::string> columns_;
    std::vector<std::string_view> fields_;
    int t_ = -1, event_col_ = -1;
    EyeColumns eye_[2];
};

}  // namespace

Result<std::unique_ptr<Reader>> open_fovea_csv(const SourceOpener& source, const std::string& path,
                                               const Options& options, double rate_hint) {
    return open_text_reader<FoveaCsvReader>(source, path, options, rate_hint);
}

}  // namespace fovea::import::detail
