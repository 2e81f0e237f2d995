// What every importer shares: issue lines, counting, stamp repair, and the per-format factories.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "fovea/import/reader.hpp"
#include "text.hpp"

namespace fovea::import::detail {

class ReaderBase : public Reader {
protected:
    ReaderBase(const std::string& path, Format format, const Options& options) : options_(options) {
        info_.path = path;
        info_.format = format;
    }

    // One problem; the first Options::max_issues are kept as "FILE:LINE: what".
    void issue(uint64_t line, const std::string& what) {
        ++stats_.issue_count;
        if (stats_.issues.size() < options_.max_issues)
            stats_.issues.push_back(info_.path + ":" + std::to_string(line) + ": " + what);
    }
    void skip(uint64_t line, const std::string& what) {
        ++stats_.skipped;
        issue(line, what);
    }

    // Stamps past this many ticks (~292 years of ns) are refused rather than wrapped.
    static constexpr double kMaxTicks = 9.2e18;

    uint64_t ticks(double t_s) const {
        const double t = (t_s - info_.tick_origin_s) * info_.clock.tick_hz;
        if (!(t > 0)) return 0;
        return t < kMaxTicks ? static_cast<uint64_t>(std::llround(t)) : uint64_t{1} << 63;
    }

    // Fills sample_.time_s from the file's stamp (NaN if absent). A missing or non-increasing
    // stamp becomes the previous one plus a period when the rate is known (the row is kept:
    // labelled files stay aligned row for row); false when the sample cannot be placed.
    bool place(double t_s, uint64_t line) {
        sample_.time_repaired = false;
        const bool increasing = !have_prev_ || t_s > prev_s_;
        if (!std::isfinite(t_s) || !increasing) {
            const double rate = info_.rate_hz();
            if (!have_prev_ && !std::isfinite(t_s)) {
                t_s = 0.0;
            } else if (rate > 0) {
                t_s = prev_s_ + 1.0 / rate;
            } else {
                skip(line, "time stamp missing or not increasing");
                return false;
            }
            sample_.time_repaired = true;
            ++stats_.repaired_times;
            if (repair_notes_++ == 0)
                issue(line,
                      "time stamp missing or not increasing: previous + one period "
                      "(further repairs counted, not listed)");
        }
        if (t_s < info_.tick_origin_s ||
            !((t_s - info_.tick_origin_s) * info_.clock.tick_hz < kMaxTicks)) {
            skip(line, "time stamp out of range");
            return false;
        }
        if (have_prev_ && !(t_s > prev_s_)) {  // a period too small to add at this magnitude
            skip(line, "time stamp not increasing");
            return false;
        }
        prev_s_ = t_s;
        have_prev_ = true;
        sample_.time_s = t_s;
        sample_.raw.device_ticks = ticks(t_s);
        return true;
    }

    Item emit_sample(uint64_t line) {
        sample_.line = line;
        sample_.raw.truth = info_.label_columns.empty() ? gaze::Event::kUnknown : sample_.labels[0];
        ++stats_.samples;
        if (!sample_.raw.left.valid && !sample_.raw.right.valid) ++stats_.invalid_samples;
        return Item::kSample;
    }
    Item emit_marker(double t_s, std::string text, uint64_t line) {
        marker_.time_s = t_s;
        marker_.device_ticks = ticks(t_s);
        marker_.text = std::move(text);
        marker_.line = line;
        ++stats_.markers;
        return Item::kMarker;
    }
    Item emit_event(uint64_t line) {
        event_.line = line;
        event_.start_ticks = ticks(event_.start_s);
        event_.end_ticks = ticks(event_.end_s);
        ++stats_.events;
        return Item::kEvent;
    }
    void reset_sample() {
        sample_.raw = gaze::RawSample{};
        sample_.labels.fill(gaze::Event::kUnknown);
        sample_.label_codes.fill(-1);
        sample_.confidence = gaze::kNaN;
        sample_.pupil_raw = {gaze::kNaN, gaze::kNaN};
        sample_.flags = 0;
    }
    void reset_event() { event_ = LabelledEvent{}; }

    // The configured display, or the default one (noted once) where the file lacks geometry.
    gaze::DisplayGeometry fallback_display(uint64_t line, const char* what) {
        if (options_.display) return *options_.display;
        if (!fallback_noted_) {
            fallback_noted_ = true;
            issue(line, std::string(what) +
                            ": no display geometry configured; assuming the default display");
        }
        return gaze::DisplayGeometry{};
    }

    // A last line without its line end means the file was cut off: counted, reported, and the
    // end of the data. Text readers call it for each non-blank line before parsing it.
    bool cut_off(const LineReader& lines, uint64_t line) {
        if (!lines.unterminated()) return false;
        stats_.truncated = true;
        skip(line, "last line has no line end (file cut off?): dropped");
        return true;
    }

    // A row with too few (or, for `what` = "values", a different number of) fields: skipped.
    void skip_field_count(uint64_t line, std::size_t want, std::size_t got,
                          const char* what = "fields") {
        skip(line,
             "expected " + std::to_string(want) + " " + what + ", got " + std::to_string(got));
    }

    // How next_row cuts the lines of a delimited text into fields.
    struct RowFormat {
        char sep = ',';
        char comment = '\0';          // lines that start with it (after blanks) are passed over
        bool trim_line = true;        // the row is the line trimmed (false: as it is, blanks kept)
        bool exact = false;           // a row needs exactly `want` fields, not at least `want`
        const char* what = "fields";  // what skip_field_count calls them
    };

    // The next data row of a delimited text. Blank lines (and comments) are passed over, a cut-off
    // last line is reported (cut_off) and ends the rows, a row with too few fields (`exact`: any
    // other number) is skipped (skip_field_count). False at the end of the rows; otherwise `line`
    // is the row, `fields` its fields and `n` its line number.
    bool next_row(LineReader& lines, const RowFormat& format, std::size_t want,
                  std::string_view& line, std::vector<std::string_view>& fields, uint64_t& n) {
        while (lines.next(line)) {
            n = lines.line_number();
            if (format.trim_line) line = trim(line);
            const std::string_view content = format.trim_line ? line : trim(line);
            if (content.empty() || (format.comment != '\0' && content.front() == format.comment))
                continue;
            if (cut_off(lines, n)) return false;
            split(line, format.sep, fields);
            if (format.exact ? fields.size() != want : fields.size() < want) {
                skip_field_count(n, want, fields.size(), format.what);
                continue;
            }
            return true;
        }
        return false;
    }

    // Called by text readers at the end of input: reports a cut-off last line.
    void end_of_text(const LineReader& lines) {
        stats_.lines = lines.line_number();
        stats_.bytes = lines.bytes();
        if (!lines.error().empty()) error_ = info_.path + ": " + lines.error();
    }

    Options options_;

private:
    double prev_s_ = 0.0;
    bool have_prev_ = false;
    uint64_t repair_notes_ = 0;
    bool fallback_noted_ = false;
};

// Samples the first pass looks at to measure the rate.
inline constexpr std::size_t kRateSamples = 2000;

// Median step of the first samples' stamps, as a rate rounded to 0.01 Hz; 0 if too few.
inline double measure_rate(Reader& r) {
    std::vector<double> steps;
    double prev = 0;
    bool have = false;
    for (Item it = r.next(); it != Item::kEnd && steps.size() < kRateSamples; it = r.next()) {
        if (it != Item::kSample) continue;
        const Sample& s = r.sample();
        if (s.time_repaired) {
            have = false;
            continue;
        }
        if (have && s.time_s > prev) steps.push_back(s.time_s - prev);
        prev = s.time_s;
        have = true;
    }
    if (steps.size() < 2) return 0.0;
    std::nth_element(steps.begin(), steps.begin() + static_cast<long>(steps.size() / 2),
                     steps.end());
    const double step = steps[steps.size() / 2];
    return step > 0 ? std::round(100.0 / step) / 100.0 : 0.0;
}

// A fresh source over the same bytes each call (readers that scan their header first).
using SourceOpener = std::function<Result<std::unique_ptr<ByteSource>>()>;

// A text reader R(source, path, options) whose start(rate_hint) reads the header.
template <typename R>
Result<std::unique_ptr<Reader>> open_text_reader(const SourceOpener& open_source,
                                                 const std::string& path, const Options& options,
                                                 double rate_hint) {
    auto src = open_source();
    if (!src) return src.error();
    auto r = std::make_unique<R>(std::move(*src), path, options);
    if (auto ok = r->start(rate_hint); !ok) return ok.error();
    return std::unique_ptr<Reader>(std::move(r));
}

// The per-format factories. `rate_hint` is the measured rate of a first pass (0 on the first).
using Factory = Result<std::unique_ptr<Reader>> (*)(const SourceOpener& source,
                                                    const std::string& path, const Options& options,
                                                    double rate_hint);
Result<std::unique_ptr<Reader>> open_lund(const SourceOpener&, const std::string&, const Options&,
                                          double);
Result<std::unique_ptr<Reader>> open_fovea_csv(const SourceOpener&, const std::string&,
                                               const Options&, double);
Result<std::unique_ptr<Reader>> open_arff(const SourceOpener&, const std::string&, const Options&,
                                          double);
Result<std::unique_ptr<Reader>> open_eyelink(const SourceOpener&, const std::string&,
                                             const Options&, double);
// One .pldata stream (no _timestamps.npy): bytes in memory, fuzzing.
Result<std::unique_ptr<Reader>> open_pldata(const SourceOpener&, const std::string&, const Options&,
                                            double);
Result<std::unique_ptr<Reader>> open_pupil_csv(const SourceOpener&, const std::string&,
                                               const Options&, double);
Result<std::unique_ptr<Reader>> open_tobii_csv(const SourceOpener&, const std::string&,
                                               const Options&, double);
Result<std::unique_ptr<Reader>> open_tobii_tsv(const SourceOpener&, const std::string&,
                                               const Options&, double);
// A Pupil recording folder, or a .pldata file with its _timestamps.npy.
Result<std::unique_ptr<Reader>> open_pupil_path(const std::string& path, const Options& options);

}  // namespace fovea::import::detail
