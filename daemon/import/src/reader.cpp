// Format names, detection from content, and open(): a first pass over the first samples
// measures the rate, then the reader proper starts from the beginning.
#include <algorithm>
#include <cctype>
#include <filesystem>

#include "reader_base.hpp"

namespace fovea::import {
namespace {

constexpr std::size_t kDetectBytes = 64 * 1024;

struct FormatEntry {
    Format format;
    const char* name;
    detail::Factory factory;  // nullptr: not implemented over bytes (folders)
};

constexpr FormatEntry kFormats[] = {
    {Format::kLund2013, "lund2013", &detail::open_lund},
    {Format::kFoveaCsv, "fovea-csv", &detail::open_fovea_csv},
    {Format::kArff, "arff", &detail::open_arff},
    {Format::kEyelinkAsc, "eyelink-asc", &detail::open_eyelink},
    {Format::kPupilFolder, "pupil", &detail::open_pldata},
    {Format::kPupilCsv, "pupil-csv", &detail::open_pupil_csv},
    {Format::kTobiiCsv, "tobii-csv", &detail::open_tobii_csv},
    {Format::kTobiiTsv, "tobii-tsv", &detail::open_tobii_tsv},
};

const FormatEntry& entry(Format f) {
    for (const auto& e : kFormats)
        if (e.format == f) return e;
    return kFormats[0];
}

std::string lower(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

Result<std::unique_ptr<Reader>> open_with(const detail::SourceOpener& source,
                                          const std::string& name, const Options& options) {
    Format format;
    if (options.format) {
        format = *options.format;
    } else {
        auto src = source();
        if (!src) return src.error();
        std::string buffer;
        std::string_view head;
        if (const auto view = (*src)->memory_view()) {
            head = view->substr(0, kDetectBytes);
        } else {
            buffer.resize(kDetectBytes);
            buffer.resize((*src)->read(buffer.data(), buffer.size()));
            head = buffer;
        }
        if (head.empty()) return make_error(name + ": empty file");
        auto f = detect_memory(head, name);
        if (!f) return f.error();
        format = *f;
    }
    const detail::Factory factory = entry(format).factory;
    if (!factory)
        return make_error(name + ": format '" + format_name(format) +
                          "' cannot be read from this input");
    if (options.rate_hz > 0) return factory(source, name, options, options.rate_hz);
    auto first = factory(source, name, options, 0.0);
    if (!first) return first.error();
    const double rate = detail::measure_rate(**first);
    return factory(source, name, options, rate);
}

}  // namespace

const char* format_name(Format f) { return entry(f).name; }

std::optional<Format> format_from_name(std::string_view name) {
    for (const auto& e : kFormats)
        if (name == e.name) return e.format;
    return std::nullopt;
}

std::vector<Format> all_formats() {
    std::vector<Format> out;
    for (const auto& e : kFormats) out.push_back(e.format);
    return out;
}

const char* coordinates_name(Coordinates c) {
    switch (c) {
        case Coordinates::kDisplay: return "display";
        case Coordinates::kSceneCamera: return "scene camera";
        case Coordinates::kEyeCamera: return "eye camera";
    }
    return "display";
}

gaze::DisplayGeometry Screen::resolve(const gaze::DisplayGeometry& fallback) const {
    gaze::DisplayGeometry d = fallback;
    if (has_pixels()) {
        d.width_px = width_px;
        d.height_px = height_px;
    }
    if (width_m > 0 && height_m > 0) {
        d.width_m = width_m;
        d.height_m = height_m;
    }
    if (distance_m > 0) d.distance_m = distance_m;
    return d;
}

Result<Format> detect_memory(std::string_view head, const std::string& name) {
    std::string_view first = head.substr(0, head.find('\n'));
    first = detail::trim(first);
    if (first.starts_with("# sampFreq=")) return Format::kLund2013;
    if (first.starts_with("# fovea")) return Format::kFoveaCsv;
    const std::string low = lower(head.substr(0, std::min<std::size_t>(head.size(), 8192)));
    if (first.find("norm_pos_x") != first.npos &&
        (first.find("gaze_timestamp") != first.npos ||
         first.find("pupil_timestamp") != first.npos || first.starts_with("timestamp,")))
        return Format::kPupilCsv;
    if (first.find("device_time_stamp") != first.npos &&
        first.find("gaze_point_on_display_area") != first.npos)
        return Format::kTobiiCsv;
    if (first.starts_with("label,x,y,start,end")) return Format::kTobiiCsv;  // EMDAT event list
    if (first.starts_with("System Properties:") || first.starts_with("Data properties:") ||
        (first.find('\t') != first.npos &&
         (first.find("RecordingTimestamp") != first.npos ||
          first.find("Recording timestamp") != first.npos || first.starts_with("FixationIndex\t"))))
        return Format::kTobiiTsv;
    if (first.starts_with("id,start_timestamp,duration,"))
        return Format::kPupilCsv;  // Player's blinks / fixations exports
    // ARFF: comments and %@METADATA, then @relation / @attribute.
    {
        std::size_t pos = 0;
        while (pos < low.size()) {
            const std::size_t end = std::min(low.find('\n', pos), low.size());
            const std::string_view l = detail::trim(std::string_view(low).substr(pos, end - pos));
            pos = end + 1;
            if (l.empty() || l.front() == '%') continue;
            if (l.starts_with("@relation") || l.starts_with("@attribute")) return Format::kArff;
            break;
        }
    }
    if (head.size() >= 2 && static_cast<uint8_t>(head[0]) == 0x92 &&
        ((static_cast<uint8_t>(head[1]) >= 0xa0 && static_cast<uint8_t>(head[1]) <= 0xbf) ||
         static_cast<uint8_t>(head[1]) == 0xd9))
        return Format::kPupilFolder;  // a .pldata stream: [topic, datum] msgpack arrays
    if (head.starts_with("** CONVERTED FROM") || head.find("\n** TYPE: EDF_FILE") != head.npos ||
        head.find("\nSTART\t") != head.npos ||
        (head.starts_with("**") && head.find("\nMSG\t") != head.npos))
        return Format::kEyelinkAsc;
    return make_error(name +
                      ": unknown format (expected a lund2013 or fovea CSV, ARFF, EyeLink ASC, a "
                      "Pupil recording or export, or a Tobii export)");
}

Result<Format> detect(const std::string& path) {
    auto src = detail::ByteSource::file(path);
    if (!src) return src.error();
    std::string head(kDetectBytes, '\0');
    head.resize((*src)->read(head.data(), head.size()));
    if (head.empty()) return make_error(path + ": empty file");
    return detect_memory(head, path);
}

Result<std::unique_ptr<Reader>> open(const std::string& path, const Options& options) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) return detail::open_pupil_path(path, options);
    std::optional<Format> format = options.format;
    if (!format) {
        auto f = detect(path);
        if (!f) return f.error();
        format = *f;
    }
    Options forced = options;
    forced.format = format;
    if (*format == Format::kPupilFolder) return detail::open_pupil_path(path, forced);
    return open_with([path] { return detail::ByteSource::file(path); }, path, forced);
}

Result<std::unique_ptr<Reader>> open_memory(std::string_view data, const std::string& name,
                                            const Options& options) {
    if (data.empty()) return make_error(name + ": empty input");
    return open_with(
        [data]() -> Result<std::unique_ptr<detail::ByteSource>> {
            return detail::ByteSource::memory(data);
        },
        name, options);
}

}  // namespace fovea::import
