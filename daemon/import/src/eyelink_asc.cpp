// EyeLink ASC (SR Research edf2asc output). Recording blocks run from START to END; a SAMPLES
// line gives the layout of the sample lines that follow (eyes, GAZE/HREF, VEL, RES, INPUT);
// MSG/INPUT/BUTTON lines become markers, EFIX/ESACC/EBLINK the tracker's own parser events.
// Samples: "time x y pupil [xv yv] [xr yr] [input] flags" (monocular, 3 flag characters) or
// "time xl yl pl xr yr pr [xvl yvl xvr yvr] [xr yr] [input] flags" (binocular, 5), "." missing.
#include <cctype>
#include <set>

#include "reader_base.hpp"

namespace fovea::import::detail {
namespace {

constexpr double kHrefDistance = 15000.0;       // HREF units: a plane 15000 units from the eye
constexpr uint64_t kHeaderScanLines = 200'000;  // the header ends at the first sample line

bool is_keyword(std::string_view line, std::string_view word) {
    return line.starts_with(word) &&
           (line.size() == word.size() || line[word.size()] == ' ' || line[word.size()] == '\t');
}

// The value of a field, NaN for EyeLink's "." (missing); false for junk.
bool value(std::string_view s, double& out) {
    if (s == "." || s == "...") {
        out = gaze::kNaN;
        return true;
    }
    return parse_double(s, out);
}

enum class Space { kGaze, kHref, kRaw };

struct Layout {
    bool left = false, right = false;
    Space space = Space::kGaze;
    bool vel = false, res = false, input = false;
    double rate = 0.0;
    bool binocular() const { return left && right; }
    std::size_t position_fields() const { return binocular() ? 6 : 3; }
};

class EyelinkReader final : public ReaderBase {
public:
    EyelinkReader(const std::string& path, const Options& o)
        : ReaderBase(path, Format::kEyelinkAsc, o) {}

    // The header (everything before the first sample) sets the source info; reading then
    // starts over from the first line so that its messages are delivered too.
    Result<void> start(const SourceOpener& open_source, double rate_hint) {
        auto src = open_source();
        if (!src) return src.error();
        LineReader scan(std::move(*src));
        std::string_view line;
        bool any_asc = false, saw_sample = false;
        while (scan.next(line) && scan.line_number() < kHeaderScanLines) {
            if (line.starts_with("**")) {
                any_asc = true;
                const auto body = trim(line.substr(2));
                if (body.starts_with("VERSION:") && info_.device.empty())
                    info_.device = std::string(trim(body.substr(8)));
                if (body.starts_with("SOURCE:")) info_.device = std::string(trim(body.substr(7)));
                continue;
            }
            if (!line.empty() && std::isdigit(static_cast<unsigned char>(line[0])) && in_block_) {
                saw_sample = true;
                break;
            }
            any_asc |= control(line, scan.line_number());
        }
        if (!any_asc)
            return make_error(info_.path +
                              ":1: not an EyeLink ASC file (no '**' header, START, "
                              "SAMPLES or MSG lines)");
        if (!saw_sample) issue(scan.line_number(), "no sample lines in the header's blocks");
        info_.binocular = layout_.binocular();
        info_.header_rate_hz = layout_.rate;
        info_.measured_rate_hz = rate_hint;
        info_.clock = {64, 1e6};  // ms stamps, with .5 at 2000 Hz
        info_.coordinates = Coordinates::kDisplay;
        info_.variant = std::string(layout_.space == Space::kHref  ? "HREF"
                                    : layout_.space == Space::kRaw ? "PUPIL (raw)"
                                                                   : "GAZE") +
                        (layout_.binocular() ? " binocular"
                         : layout_.left      ? " left"
                                             : " right");
        info_.pupil_unit = pupil_area_ ? "area (EyeLink a.u.)" : "diameter (EyeLink a.u.)";
        // Reading proper restarts from the first line with fresh state.
        layout_ = {};
        in_block_ = false;
        gaze_coords_ = {};
        auto again = open_source();
        if (!again) return again.error();
        lines_.emplace(std::move(*again));
        return {};
    }

    Item next() override {
        std::string_view line;
        while (lines_->next(line)) {
            const uint64_t n = lines_->line_number();
            if (line.empty()) continue;
            if (std::isdigit(static_cast<unsigned char>(line[0]))) {
                if (!in_block_) continue;  // continuation lines of multi-line !CAL messages
                if (cut_off(*lines_, n)) break;
                if (sample(line, n)) return emit_sample(n);
                continue;
            }
            if (is_keyword(line, "MSG")) {
                if (message(line, n)) return Item::kMarker;
                continue;
            }
            if (is_keyword(line, "INPUT") || is_keyword(line, "BUTTON")) {
                split_blanks(line, tok_);
                double t = 0;
                if (tok_.size() >= 3 && parse_double(tok_[1], t)) {
                    std::string text(tok_[0]);
                    for (std::size_t i = 2; i < tok_.size(); ++i)
                        text += " " + std::string(tok_[i]);
                    return emit_marker(t * 1e-3, std::move(text), n);
                }
                skip(n, "malformed " + std::string(tok_.empty() ? "" : tok_[0]) + " line");
                continue;
            }
            if (line[0] == 'E' && (is_keyword(line, "EFIX") || is_keyword(line, "ESACC") ||
                                   is_keyword(line, "EBLINK"))) {
                if (end_event(line, n)) return emit_event(n);
                continue;
            }
            if (line[0] == 'S' && (is_keyword(line, "SFIX") || is_keyword(line, "SSACC") ||
                                   is_keyword(line, "SBLINK")))
                continue;  // the E* line repeats the start time
            control(line, n);
        }
        end_of_text(*lines_);
        return Item::kEnd;
    }

private:
    // START/END/SAMPLES/EVENTS/PUPIL/GAZE_COORDS lines; true if the line was one of ours.
    bool control(std::string_view line, uint64_t n) {
        if (is_keyword(line, "START")) {
            split_blanks(line, tok_);
            layout_.left = layout_.right = false;
            for (auto t : tok_) {
                if (t == "LEFT") layout_.left = true;
                if (t == "RIGHT") layout_.right = true;
            }
            in_block_ = true;
            return true;
        }
        if (is_keyword(line, "END")) {
            in_block_ = false;
            return true;
        }
        if (is_keyword(line, "SAMPLES")) {
            split_blanks(line, tok_);
            Layout l;
            for (std::size_t i = 1; i < tok_.size(); ++i) {
                const auto t = tok_[i];
                if (t == "LEFT")
                    l.left = true;
                else if (t == "RIGHT")
                    l.right = true;
                else if (t == "HREF")
                    l.space = Space::kHref;
                else if (t == "PUPIL")
                    l.space = Space::kRaw;
                else if (t == "VEL")
                    l.vel = true;
                else if (t == "RES")
                    l.res = true;
                else if (t == "INPUT")
                    l.input = true;
                else if (t == "RATE" && i + 1 < tok_.size())
                    parse_double(tok_[i + 1], l.rate);
            }
            if (!l.left && !l.right) {
                issue(n, "SAMPLES line names no eye: assuming the START line's");
                l.left = layout_.left;
                l.right = layout_.right;
            }
            layout_ = l;
            return true;
        }
        if (is_keyword(line, "EVENTS")) {
            split_blanks(line, tok_);
            event_space_ = Space::kGaze;
            for (auto t : tok_)
                if (t == "HREF") event_space_ = Space::kHref;
            return true;
        }
        if (is_keyword(line, "PUPIL")) {
            pupil_area_ = line.find("AREA") != std::string_view::npos;
            return true;
        }
        if (is_keyword(line, "MSG")) {
            coords(line, n);
            return true;
        }
        return is_keyword(line, "PRESCALER") || is_keyword(line, "VPRESCALER");
    }

    // DISPLAY_COORDS / GAZE_COORDS in a message set the pixel frame of GAZE data.
    void coords(std::string_view line, uint64_t n) {
        const bool display = line.find("DISPLAY_COORDS") != std::string_view::npos;
        if (!display && line.find("GAZE_COORDS") == std::string_view::npos) return;
        split_blanks(line, tok_);
        std::vector<double> v;
        for (auto t : tok_) {
            double d = 0;
            if (parse_double(t, d)) v.push_back(d);
        }
        // MSG time [offset] left top right bottom: the last four numbers.
        if (v.size() < 5 || !(v[v.size() - 2] > v[v.size() - 4]) ||
            !(v[v.size() - 1] > v[v.size() - 3])) {
            issue(n, "unreadable DISPLAY_COORDS/GAZE_COORDS");
            return;
        }
        Coords c{v[v.size() - 4], v[v.size() - 3], v[v.size() - 2] - v[v.size() - 4] + 1,
                 v[v.size() - 1] - v[v.size() - 3] + 1};
        if (c.width > 1e6 || c.height > 1e6) {
            issue(n, "absurd DISPLAY_COORDS/GAZE_COORDS");
            return;
        }
        // GAZE_COORDS is the frame GAZE samples are in; DISPLAY_COORDS stands in until then.
        if (!display || gaze_coords_.width == 0) gaze_coords_ = c;
        if (!display || info_.screen.width_px == 0) {
            info_.screen.width_px = static_cast<int>(c.width);
            info_.screen.height_px = static_cast<int>(c.height);
        }
    }

    // Position in normalized display coordinates from the block's coordinate space.
    bool to_display(Space space, double x, double y, uint64_t n, double& nx, double& ny) {
        if (!std::isfinite(x) || !std::isfinite(y)) return false;
        if (space == Space::kHref) {
            if (!href_display_) href_display_ = fallback_display(n, "HREF coordinates");
            constexpr double kRadToDeg = 57.29577951308232;
            href_display_->to_normalized(std::atan(x / kHrefDistance) * kRadToDeg,
                                         std::atan(y / kHrefDistance) * kRadToDeg, nx, ny);
            return true;
        }
        if (gaze_coords_.width == 0) {
            const auto d = fallback_display(n, "no GAZE_COORDS/DISPLAY_COORDS");
            gaze_coords_ = {0, 0, static_cast<double>(d.width_px),
                            static_cast<double>(d.height_px)};
        }
        nx = (x - gaze_coords_.left) / gaze_coords_.width;
        ny = (y - gaze_coords_.top) / gaze_coords_.height;
        return true;
    }

    bool sample(std::string_view line, uint64_t n) {
        split_blanks(line, tok_);
        const Layout& l = layout_;
        if (!l.left && !l.right) {
            skip(n, "sample line before any SAMPLES/START line naming the eyes");
            return false;
        }
        const std::size_t pos = l.position_fields();
        const std::size_t expected = 1 + pos + (l.vel ? pos / 3 * 2 : 0) + (l.res ? 2 : 0) +
                                     (l.input ? 1 : 0) + 1;  // + flags
        if (tok_.size() < 1 + pos) {
            skip(n, "sample line with " + std::to_string(tok_.size()) + " fields, expected " +
                        std::to_string(expected));
            return false;
        }
        double t = 0;
        if (!parse_double(tok_[0], t)) {
            skip(n, "sample time is not a number: '" + printable(tok_[0]) + "'");
            return false;
        }
        double v[6];
        for (std::size_t i = 0; i < pos; ++i)
            if (!value(tok_[1 + i], v[i])) {
                skip(n, "sample field " + std::to_string(i + 2) + " is not a number or '.': '" +
                            printable(tok_[1 + i]) + "'");
                return false;
            }
        reset_sample();
        if (!place(t * 1e-3, n)) return false;
        // Flags: [0] I interpolated, then per eye C (corneal reflection missing), R (recovering).
        std::string_view flags;
        if (tok_.size() >= expected) flags = tok_[expected - 1];
        const auto eye = [&](int k, gaze::EyeSample& e, std::size_t off) {
            const double x = v[off], y = v[off + 1], p = v[off + 2];
            sample_.pupil_raw[k] = std::isfinite(p) ? p : gaze::kNaN;
            double nx = 0, ny = 0;
            if (!(std::isfinite(p) && p > 0) || !to_display(l.space, x, y, n, nx, ny)) return;
            e = {nx, ny, 0.0, true};
        };
        if (l.binocular()) {
            eye(0, sample_.raw.left, 0);
            eye(1, sample_.raw.right, 3);
        } else if (l.left) {
            eye(0, sample_.raw.left, 0);
        } else {
            eye(1, sample_.raw.right, 0);
        }
        if (flags.size() == (l.binocular() ? 5u : 3u)) {
            if (flags[0] == 'I') sample_.flags |= kInterpolated;
            for (int k = 0; k < (l.binocular() ? 2 : 1); ++k) {
                const bool left = l.binocular() ? k == 0 : l.left;
                if (flags[1 + 2 * k] == 'C')
                    sample_.flags |= left ? kLeftCrMissing : kRightCrMissing;
                if (flags[2 + 2 * k] == 'R')
                    sample_.flags |= left ? kLeftCrRecovering : kRightCrRecovering;
            }
        }
        return true;
    }

    bool message(std::string_view line, uint64_t n) {
        coords(line, n);
        // "MSG <time> [<offset>] <text>": the message's own time is time - offset.
        std::string_view rest = trim(line.substr(3));
        const auto sp = rest.find_first_of(" \t");
        double t = 0;
        if (!parse_double(rest.substr(0, sp), t)) {
            skip(n, "MSG without a time stamp");
            return false;
        }
        std::string_view text = sp == std::string_view::npos ? "" : trim(rest.substr(sp));
        const auto sp2 = text.find_first_of(" \t");
        int64_t offset = 0;
        if (sp2 != std::string_view::npos && parse_int(text.substr(0, sp2), offset)) {
            t -= static_cast<double>(offset);
            text = trim(text.substr(sp2));
        }
        emit_marker(t * 1e-3, std::string(text), n);
        return true;
    }

    bool end_event(std::string_view line, uint64_t n) {
        split_blanks(line, tok_);
        const std::string_view kind = tok_[0];
        const std::size_t need = kind == "EBLINK" ? 5 : kind == "EFIX" ? 8 : 11;
        if (tok_.size() < need || (tok_[1] != "L" && tok_[1] != "R")) {
            skip(n, std::string(kind) + " line with " + std::to_string(tok_.size()) +
                        " fields, expected " + std::to_string(need));
            return false;
        }
        double start = 0, end = 0;
        if (!parse_double(tok_[2], start) || !parse_double(tok_[3], end) || end < start) {
            skip(n, std::string(kind) + ": unreadable start/end time");
            return false;
        }
        reset_event();
        event_.source = "eyelink";
        event_.eye = tok_[1] == "L" ? Eye::kLeft : Eye::kRight;
        event_.start_s = start * 1e-3;
        event_.end_s = end * 1e-3;
        // tok_[4] is the duration; edf2asc sometimes writes garbage there, so it is not used.
        double a = 0, b = 0, c = 0, d = 0;
        if (kind == "EBLINK") {
            event_.type = gaze::Event::kBlink;
        } else if (kind == "EFIX") {
            event_.type = gaze::Event::kFixation;
            if (value(tok_[5], a) && value(tok_[6], b))
                to_display(event_space_, a, b, n, event_.x, event_.y);
            if (value(tok_[7], c)) event_.pupil_raw = c;
        } else {
            event_.type = gaze::Event::kSaccade;
            if (value(tok_[5], a) && value(tok_[6], b))
                to_display(event_space_, a, b, n, event_.start_x, event_.start_y);
            if (value(tok_[7], c) && value(tok_[8], d))
                to_display(event_space_, c, d, n, event_.end_x, event_.end_y);
            if (value(tok_[9], a)) event_.amplitude_deg = a;
            if (value(tok_[10], b)) event_.peak_velocity_dps = b;
        }
        return true;
    }

    struct Coords {
        double left = 0, top = 0, width = 0, height = 0;
    };

    std::optional<LineReader> lines_;
    std::vector<std::string_view> tok_;
    Layout layout_;
    Space event_space_ = Space::kGaze;
    bool in_block_ = false;
    bool pupil_area_ = true;
    Coords gaze_coords_;
    std::optional<gaze::DisplayGeometry> href_display_;
};

}  // namespace

Result<std::unique_ptr<Reader>> open_eyelink(const SourceOpener& open_source,
                                             const std::string& path, const Options& options,
                                             double rate_hint) {
    auto r = std::make_unique<EyelinkReader>(path, options);
    if (auto ok = r->start(open_source, rate_hint); !ok) return ok.error();
    return std::unique_ptr<Reader>(std::move(r));
}

}  // namespace fovea::import::detail
