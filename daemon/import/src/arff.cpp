// ARFF as GazeCom and Startsev's tools write it: "%@METADATA width_px 1280" lines, @ATTRIBUTE
// time (µs), x, y (px), optional confidence, label columns (integer codes 0 UNKNOWN 1 FIX
// 2 SACC 3 SP 4 NOISE, or a nominal {UNKNOWN,FIX,SACCADE,SP,NOISE}), then @DATA rows.
#include <algorithm>
#include <cctype>

#include "reader_base.hpp"

namespace fovea::import::detail {
namespace {

std::string lower(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

// GazeCom's codes, and the names of the nominal variant.
int16_t code_from_name(std::string_view name) {
    const std::string n = lower(trim(name));
    if (n == "unknown") return 0;
    if (n == "fix" || n == "fixation") return 1;
    if (n == "sacc" || n == "saccade") return 2;
    if (n == "sp" || n == "pursuit" || n == "smooth_pursuit") return 3;
    if (n == "noise") return 4;
    return -1;
}

gaze::Event event_from_code(int64_t code) {
    switch (code) {
        case 1: return gaze::Event::kFixation;
        case 2: return gaze::Event::kSaccade;
        case 3: return gaze::Event::kPursuit;
        default: return gaze::Event::kUnknown;  // 0 UNKNOWN, 4 NOISE
    }
}

std::string_view unquote(std::string_view s) {
    s = trim(s);
    if (s.size() >= 2 && (s.front() == '\'' || s.front() == '"') && s.back() == s.front())
        return s.substr(1, s.size() - 2);
    return s;
}

struct Attribute {
    std::string name;
    std::string type;                 // lower case: integer, numeric, real, string, nominal
    std::vector<int16_t> nominal;     // code per nominal value, in declaration order
    std::vector<std::string> values;  // nominal names
};

class ArffReader final : public ReaderBase {
public:
    ArffReader(std::unique_ptr<ByteSource> src, const std::string& path, const Options& o)
        : ReaderBase(path, Format::kArff, o), lines_(std::move(src)) {}

    Result<void> start(double rate_hint) {
        std::string_view line;
        bool data = false;
        std::vector<std::string_view> tok;
        while (!data && lines_.next(line)) {
            const uint64_t n = lines_.line_number();
            const std::string where = info_.path + ":" + std::to_string(n) + ": ";
            line = trim(line);
            if (line.starts_with("%@METADATA")) {
                split_blanks(line.substr(10), tok);
                double v = 0;
                if (tok.size() < 2 || !parse_double(tok[1], v)) continue;
                const std::string key = lower(tok[0]);
                if (key == "width_px" || key == "height_px") {
                    if (!(v >= 1 && v <= 1e6)) {  // also keeps the int conversion defined
                        issue(n, "@METADATA " + key + " is not a pixel count; ignored");
                        continue;
                    }
                    (key == "width_px" ? info_.screen.width_px : info_.screen.height_px) =
                        static_cast<int>(v);
                }
                if (key == "width_mm") info_.screen.width_m = v / 1000;
                if (key == "height_mm") info_.screen.height_m = v / 1000;
                if (key == "distance_mm") info_.screen.distance_m = v / 1000;
                continue;
            }
            if (line.empty() || line.front() == '%') continue;
            const std::string head = lower(line.substr(0, std::min<std::size_t>(line.size(), 10)));
            if (head.starts_with("@relation")) {
                info_.variant = std::string(unquote(line.substr(9)));
            } else if (head.starts_with("@attribute")) {
                if (auto a = attribute(line.substr(10)); a) {
                    attrs_.push_back(std::move(*a));
                } else {
                    return make_error(where + a.error().message);
                }
            } else if (head.starts_with("@data")) {
                data = true;
            } else {
                return make_error(where + "expected @RELATION, @ATTRIBUTE or @DATA, got '" +
                                  printable(line) + "'");
            }
        }
        if (!data) return make_error(info_.path + ": no @DATA section (not an ARFF file?)");
        for (std::size_t i = 0; i < attrs_.size(); ++i) {
            const std::string n = lower(attrs_[i].name);
            if (n == "time")
                t_ = static_cast<int>(i);
            else if (n == "x")
                x_ = static_cast<int>(i);
            else if (n == "y")
                y_ = static_cast<int>(i);
            else if (n == "confidence")
                conf_ = static_cast<int>(i);
            else if (attrs_[i].type == "integer" || attrs_[i].type == "nominal") {
                if (labels_.size() < kMaxLabelColumns) {
                    labels_.push_back(static_cast<int>(i));
                    info_.label_columns.push_back(attrs_[i].name);
                } else {
                    issue(0, "label column '" + attrs_[i].name + "' beyond the first " +
                                 std::to_string(kMaxLabelColumns) + " ignored");
                }
            }
        }
        if (t_ < 0 || x_ < 0 || y_ < 0)
            return make_error(info_.path + ": ARFF needs attributes time, x and y");
        // GTA-VI's 360-degree recordings (Agtzidis et al. 2019): x/y are an equirectangular
        // frame's longitude and latitude and the head turns freely, which no flat display maps.
        if (lower(info_.variant) == "gaze_360") {
            return make_error(info_.path +
                              ": @RELATION gaze_360 (equirectangular 360-degree gaze, head "
                              "free) is not supported: its x/y are not on a display");
        }
        width_px_ = info_.screen.width_px;
        height_px_ = info_.screen.height_px;
        if (!info_.screen.has_pixels()) {
            const auto d =
                fallback_display(lines_.line_number(), "no %@METADATA width_px/height_px");
            width_px_ = d.width_px;
            height_px_ = d.height_px;
        } else if (!info_.screen.has_size()) {
            // Pixels without the display's size and distance (or with zeros) give no degrees.
            fallback_display(lines_.line_number(),
                             "no %@METADATA width_mm/height_mm/distance_mm above zero");
        }
        if (!labels_.empty()) info_.label_codes = "0 UNKNOWN, 1 FIX, 2 SACC, 3 SP, 4 NOISE";
        info_.clock = {64, 1e6};
        info_.measured_rate_hz = rate_hint;
        info_.binocular = false;
        info_.coordinates = Coordinates::kDisplay;
        return {};
    }

    Item next() override {
        std::string_view line;
        uint64_t n = 0;
        const RowFormat row{.comment = '%', .exact = true, .what = "values"};
        while (next_row(lines_, row, attrs_.size(), line, fields_, n)) {
            double t = 0, x = gaze::kNaN, y = gaze::kNaN, conf = 1.0;
            if (!parse_double(fields_[t_], t)) {
                skip(n, "time is not a number: '" + printable(line) + "'");
                continue;
            }
            const bool have_xy = parse_double(fields_[x_], x) && parse_double(fields_[y_], y);
            if (!have_xy && trim(fields_[x_]) != "?" && trim(fields_[y_]) != "?") {
                skip(n, "x/y is not a number: '" + printable(line) + "'");
                continue;
            }
            reset_sample();
            if (conf_ >= 0 && parse_double(fields_[conf_], conf)) sample_.confidence = conf;
            bool labels_ok = true;
            for (std::size_t k = 0; k < labels_.size(); ++k) {
                const Attribute& a = attrs_[labels_[k]];
                const std::string_view v = unquote(fields_[labels_[k]]);
                int64_t code = -1;
                if (a.type == "nominal") {
                    const auto it = std::find(a.values.begin(), a.values.end(), v);
                    if (it != a.values.end())
                        code = a.nominal[it - a.values.begin()];
                    else if (v != "?")
                        labels_ok = false;
                } else if (!parse_int(v, code) && v != "?") {
                    labels_ok = false;
                }
                sample_.label_codes[k] = static_cast<int16_t>(code >= -1 && code < 100 ? code : -1);
                sample_.labels[k] = event_from_code(code);
            }
            if (!labels_ok) {
                skip(n, "a label is not one of its attribute's values: '" + printable(line) + "'");
                continue;
            }
            if (!place(t * 1e-6, n)) continue;
            if (have_xy && std::isfinite(x) && std::isfinite(y) && !(conf <= 0))
                sample_.raw.left = {x / width_px_, y / height_px_, 0.0, true};
            return emit_sample(n);
        }
        end_of_text(lines_);
        return Item::kEnd;
    }

private:
    // "name TYPE" with the name possibly quoted and TYPE possibly {a,b,c}.
    static Result<Attribute> attribute(std::string_view rest) {
        rest = trim(rest);
        Attribute a;
        std::size_t i = 0;
        if (!rest.empty() && (rest[0] == '\'' || rest[0] == '"')) {
            const auto close = rest.find(rest[0], 1);
            if (close == std::string_view::npos) return make_error("unterminated attribute name");
            a.name = std::string(rest.substr(1, close - 1));
            i = close + 1;
        } else {
            while (i < rest.size() && rest[i] != ' ' && rest[i] != '\t') ++i;
            a.name = std::string(rest.substr(0, i));
        }
        const std::string_view type = trim(rest.substr(i));
        if (a.name.empty() || type.empty()) return make_error("@ATTRIBUTE needs a name and a type");
        if (type.front() == '{') {
            if (type.back() != '}') return make_error("unterminated nominal type of " + a.name);
            a.type = "nominal";
            std::vector<std::string_view> values;
            split(type.substr(1, type.size() - 2), ',', values);
            for (auto v : values) {
                a.values.emplace_back(unquote(v));
                a.nominal.push_back(code_from_name(a.values.back()));
            }
        } else {
            a.type = lower(type);
            if (a.type == "real") a.type = "numeric";
        }
        return a;
    }

    LineReader lines_;
    std::vector<Attribute> attrs_;
    std::vector<int> labels_;
    std::vector<std::string_view> fields_;
    int t_ = -1, x_ = -1, y_ = -1, conf_ = -1;
    double width_px_ = 1, height_px_ = 1;  // normalizes x/y
};

}  // namespace

Result<std::unique_ptr<Reader>> open_arff(const SourceOpener& source, const std::string& path,
                                          const Options& options, double rate_hint) {
    return open_text_reader<ArffReader>(source, path, options, rate_hint);
}

}  // namespace fovea::import::detail
