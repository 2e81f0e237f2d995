// The lund2013 labelled CSV (../shared/data/README.md): "# sampFreq=500 viewDist_m=0.67
// screenDim_m=0.38,0.3 screenRes_px=1024,768 ..." then "t_us,pupil_h,pupil_v,x_px,y_px,label".
#include <map>

#include "reader_base.hpp"

namespace fovea::import::detail {
namespace {

gaze::Event event_from_lund(int64_t code) {
    switch (code) {
        case 1: return gaze::Event::kFixation;
        case 2: return gaze::Event::kSaccade;
        case 3: return gaze::Event::kPso;
        case 4: return gaze::Event::kPursuit;
        case 5: return gaze::Event::kBlink;
        default: return gaze::Event::kUnknown;  // 6: undefined
    }
}

bool pair(std::string_view v, double& a, double& b) {
    const auto comma = v.find(',');
    return comma != std::string_view::npos && parse_double(v.substr(0, comma), a) &&
           parse_double(v.substr(comma + 1), b);
}

class LundReader final : public ReaderBase {
public:
    LundReader(std::unique_ptr<ByteSource> src, const std::string& path, const Options& o)
        : ReaderBase(path, Format::kLund2013, o), lines_(std::move(src)) {}

    Result<void> start(double rate_hint) {
        std::string_view line;
        if (!lines_.next(line)) return make_error(info_.path + ": empty file");
        line = trim(line);
        if (!line.starts_with("# sampFreq="))
            return make_error(info_.path + ":1: not a lund2013 header ('# sampFreq=...')");
        std::map<std::string, std::string, std::less<>> header;
        std::vector<std::string_view> tokens;
        split_blanks(line.substr(1), tokens);
        for (auto t : tokens)
            if (const auto eq = t.find('='); eq != std::string_view::npos)
                header.emplace(std::string(t.substr(0, eq)), std::string(t.substr(eq + 1)));
        const auto get = [&](const char* key) -> const std::string* {
            const auto it = header.find(key);
            return it == header.end() ? nullptr : &it->second;
        };
        double rate = 0, w = 0, h = 0;
        if (!parse_double(*get("sampFreq"), rate) || !(rate > 0 && rate <= 100'000))
            return make_error(info_.path + ":1: sampFreq must be a rate in Hz");
        if (!get("screenRes_px") || !pair(*get("screenRes_px"), w, h) || !(w >= 1 && h >= 1) ||
            w > 1e6 || h > 1e6)
            return make_error(info_.path + ":1: lund2013 header needs screenRes_px=W,H");
        info_.header_rate_hz = rate;
        info_.measured_rate_hz = rate_hint;
        info_.screen.width_px = static_cast<int>(w);
        info_.screen.height_px = static_cast<int>(h);
        if (const auto* dim = get("screenDim_m"); dim && pair(*dim, w, h) && w > 0 && h > 0) {
            info_.screen.width_m = w;
            info_.screen.height_m = h;
        }
        if (const auto* d = get("viewDist_m"); d && parse_double(*d, w) && w > 0)
            info_.screen.distance_m = w;
        if (const auto* s = get("source")) info_.device = *s;
        info_.clock = {64, 1e6};
        info_.binocular = false;
        info_.coordinates = Coordinates::kDisplay;

        if (!lines_.next(line)) return make_error(info_.path + ":2: missing the column line");
        split(trim(line), ',', fields_);
        for (auto f : fields_) columns_.emplace_back(trim(f));
        t_ = column_index(columns_, "t_us");
        x_ = column_index(columns_, "x_px");
        y_ = column_index(columns_, "y_px");
        label_ = column_index(columns_, "label");
        if (t_ < 0 || x_ < 0 || y_ < 0)
            return make_error(info_.path + ":2: the column line needs t_us, x_px and y_px");
        if (label_ >= 0) {
            info_.label_columns = {"label"};
            info_.label_codes =
                "1 fixation, 2 saccade, 3 PSO, 4 smooth pursuit, 5 blink, 6 undefined";
        }
        info_.variant = label_ >= 0 ? "labelled" : "unlabelled";
        return {};
    }

    Item next() override {
        std::string_view line;
        uint64_t n = 0;
        while (next_row(lines_, {}, columns_.size(), line, fields_, n)) {
            double t = gaze::kNaN, x = 0, y = 0, label = 6;
            if (!parse_double(fields_[x_], x) || !parse_double(fields_[y_], y)) {
                skip(n, "x_px/y_px is not a number: '" + printable(line) + "'");
                continue;
            }
            if (label_ >= 0 && (!parse_double(fields_[label_], label) || !std::isfinite(label))) {
                skip(n, "label is not a number: '" + printable(line) + "'");
                continue;
            }
            if (!parse_double(fields_[t_], t)) t = gaze::kNaN;
            reset_sample();
            if (!place(t * 1e-6, n)) continue;
            // Lost tracking is 0,0 (not NaN) in these files.
            if (std::isfinite(x) && std::isfinite(y) && !(x == 0 && y == 0)) {
                sample_.raw.left = {x / info_.screen.width_px, y / info_.screen.height_px, 0.0,
                                    true};
            }
            if (label_ >= 0) {
                const auto code = static_cast<int64_t>(std::llround(label));
                sample_.label_codes[0] = static_cast<int16_t>(code >= -1 && code < 100 ? code : -1);
                sample_.labels[0] = event_from_lund(code);
            }
            return emit_sample(n);
        }
        end_of_text(lines_);
        return Item::kEnd;
    }

private:
    LineReader lines_;
    std::vector<std::string> columns_;
    std::vector<std::string_view> fields_;
    int t_ = -1, x_ = -1, y_ = -1, label_ = -1;
};

}  // namespace

Result<std::unique_ptr<Reader>> open_lund(const SourceOpener& source, const std::string& path,
                                          const Options& options, double rate_hint) {
    return open_text_reader<LundReader>(source, path, options, rate_hint);
}

}  // namespace fovea::import::detail
