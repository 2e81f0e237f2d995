// fovea import FILE|DIR --out X.xdf|X.csv: a recording another tracker wrote (any format
// fovea::import reads) through the gaze chain into a Fovea recording. The XDF holds the raw and
// processed streams `fovea replay` and `fovea report` read, plus the file's markers
// (FoveaMarkers) and the tracker's own events (FoveaTrackerEvents) and, for files with several
// label columns, every column (FoveaImportLabels). Streams in constant memory.
//
// Host time: there was no live host, so the file's own clock stands in for it (receive time =
// capture time = the file's stamp); XDF stamps are the file's seconds.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "command.hpp"
#include "fovea/gaze/pipeline.hpp"
#include "fovea/import/reader.hpp"
#include "fovea/record/offline.hpp"
#include "fovea/record/streams.hpp"
#include "fovea/record/xdf.hpp"
#include "gaze_format.hpp"
#include "ring_record.hpp"

namespace fovea::cli {
namespace {

namespace xdf = record::xdf;

constexpr uint32_t kMarkerStreamId = 4;
constexpr uint32_t kEventStreamId = 5;
constexpr uint32_t kLabelStreamId = 6;
constexpr std::size_t kFlushSamples = 4096;

constexpr const char* kEventChannels[] = {"type",
                                          "eye",
                                          "start_s",
                                          "end_s",
                                          "amplitude_deg",
                                          "peak_velocity_dps",
                                          "start_x",
                                          "start_y",
                                          "end_x",
                                          "end_y",
                                          "x",
                                          "y"};

int64_t ns(double t_s) { return static_cast<int64_t>(std::llround(t_s * 1e9)); }

// One numeric or string stream being written: rows pending until the next flush.
struct StreamOut {
    StreamOut() = default;
    StreamOut(uint32_t stream_id, xdf::Format stream_format, int stream_channels)
        : id(stream_id), format(stream_format), channels(stream_channels) {}

    uint32_t id = 0;
    xdf::Format format = xdf::Format::kDouble64;
    int channels = 0;
    std::vector<double> stamps, rows;
    std::vector<std::string> texts;
    uint64_t count = 0;
    double first = 0, last = 0;

    void add(double stamp) {
        if (count++ == 0) first = stamp;
        last = stamp;
        stamps.push_back(stamp);
    }
    void encode(xdf::ChunkEncoder& enc) {
        if (stamps.empty()) return;
        if (format == xdf::Format::kString)
            enc.string_samples(id, stamps.data(), texts.data(), stamps.size());
        else
            enc.samples(id, format, channels, stamps.data(), rows.data(), stamps.size());
        stamps.clear();
        rows.clear();
        texts.clear();
    }
};

class XdfOut {
public:
    XdfOut(const std::string& path, const import::SourceInfo& src,
           const record::RecordingInfo& info)
        : file_(path, std::ios::binary | std::ios::trunc), path_(path) {
        if (!file_) throw std::runtime_error("cannot write " + path);
        enc_.magic();
        enc_.file_header("<source>" + xdf::xml_escape(src.path) + "</source><format>" +
                         import::format_name(src.format) + "</format>");
        raw_ = {record::kRawStreamId, xdf::Format::kDouble64, record::raw_channel_count()};
        gaze_ = {record::kGazeStreamId, xdf::Format::kDouble64, record::gaze_channel_count()};
        markers_ = {kMarkerStreamId, xdf::Format::kString, 1};
        events_ = {kEventStreamId, xdf::Format::kDouble64,
                   static_cast<int>(std::size(kEventChannels))};
        labels_ = {kLabelStreamId, xdf::Format::kDouble64,
                   static_cast<int>(src.label_columns.size())};
        enc_.stream_header(raw_.id, record::raw_stream_info(info));
        enc_.stream_header(gaze_.id, record::gaze_stream_info(info));
        xdf::StreamInfo m;
        m.name = "FoveaMarkers";
        m.type = "Markers";
        m.format = xdf::Format::kString;
        m.source_id = src.path;
        m.channels = {{"text", "", "Marker"}};
        enc_.stream_header(markers_.id, m);
        xdf::StreamInfo e;
        e.name = "FoveaTrackerEvents";
        e.type = "Events";
        e.source_id = src.path;
        for (const char* c : kEventChannels) e.channels.push_back({c, "", "Event"});
        e.desc_extra_xml =
            "<note>the tracker software's own events; type is a fovea_event, eye "
            "0 left 1 right 2 both, times in seconds of the file's clock, x/y "
            "normalized display</note>";
        enc_.stream_header(events_.id, e);
        if (src.label_columns.size() > 1) {
            xdf::StreamInfo l;
            l.name = "FoveaImportLabels";
            l.type = "Labels";
            l.source_id = src.path;
            for (const auto& c : src.label_columns) l.channels.push_back({c, "code", "Label"});
            l.desc_extra_xml = "<codes>" + xdf::xml_escape(src.label_codes) + "</codes>";
            enc_.stream_header(labels_.id, l);
            with_labels_ = true;
        }
    }

    void raw(const gaze::RawSample& s, const import::Sample& from, int64_t origin) {
        raw_.add(static_cast<double>(s.t_receive_ns) * 1e-9);
        raw_.rows.resize(raw_.rows.size() + static_cast<std::size_t>(raw_.channels));
        record::encode_raw(s, true, origin, raw_.rows.data() + raw_.rows.size() - raw_.channels);
        if (with_labels_) {
            labels_.add(from.time_s);
            for (int k = 0; k < labels_.channels; ++k)
                labels_.rows.push_back(from.label_codes[static_cast<std::size_t>(k)]);
        }
        if (raw_.stamps.size() >= kFlushSamples) flush();
    }
    void gaze(const gaze::GazeSample& g, uint64_t index, int64_t origin) {
        gaze_.add(static_cast<double>(g.t_capture_ns) * 1e-9);
        gaze_.rows.resize(gaze_.rows.size() + static_cast<std::size_t>(gaze_.channels));
        record::encode_gaze(g, g.t_processed_ns, index, origin,
                            gaze_.rows.data() + gaze_.rows.size() - gaze_.channels);
    }
    void marker(const import::Marker& m) {
        markers_.add(m.time_s);
        markers_.texts.push_back(m.text);
    }
    void event(const import::LabelledEvent& e) {
        events_.add(e.start_s);
        for (double v : {static_cast<double>(e.type), static_cast<double>(e.eye), e.start_s,
                         e.end_s, e.amplitude_deg, e.peak_velocity_dps, e.start_x, e.start_y,
                         e.end_x, e.end_y, e.x, e.y})
            events_.rows.push_back(v);
    }
    void flush() {
        for (StreamOut* s : {&raw_, &gaze_, &markers_, &events_, &labels_}) s->encode(enc_);
        enc_.boundary();
        write();
    }
    void close() {
        flush();
        for (StreamOut* s : {&raw_, &gaze_, &markers_, &events_, &labels_})
            if (s != &labels_ || with_labels_)
                enc_.stream_footer(s->id, s->first, s->last, s->count);
        write();
        file_.close();
        if (!file_) throw std::runtime_error("writing " + path_ + " failed");
    }

private:
    void write() {
        const auto& b = enc_.buffer();
        file_.write(reinterpret_cast<const char*>(b.data()),
                    static_cast<std::streamsize>(b.size()));
        enc_.clear();
        if (!file_) throw std::runtime_error("writing " + path_ + " failed (disk full?)");
    }

    std::ofstream file_;
    std::string path_;
    xdf::ChunkEncoder enc_;
    StreamOut raw_, gaze_, markers_, events_, labels_;
    bool with_labels_ = false;
};

// The recording's setup for the stream headers; replay rebuilds the chain from it.
record::RecordingInfo recording_info(const import::SourceInfo& src, int64_t origin_ns) {
    record::RecordingInfo info;
    info.device_name = src.device.empty() ? import::format_name(src.format) : src.device;
    info.driver = std::string("import:") + import::format_name(src.format);
    info.address = src.path;
    info.nominal_rate_hz = src.rate_hz();
    info.clock = src.clock;
    info.display = src.screen.resolve(gaze::DisplayGeometry{});
    info.binocular = src.binocular;
    info.has_pupil = src.has_pupil;
    info.time_origin_ns = origin_ns;
    info.hostname = "import";
    info.preroll_from_start = true;
    return info;
}

// Time of the first sample (or marker/event): the recording's time origin, whole seconds.
int64_t first_time_ns(const std::string& path, const import::Options& o) {
    auto r = import::open(path, o);
    if (!r) throw std::runtime_error(r.error().message);
    for (auto it = (*r)->next(); it != import::Item::kEnd; it = (*r)->next()) {
        const double t = it == import::Item::kSample   ? (*r)->sample().time_s
                         : it == import::Item::kMarker ? (*r)->marker().time_s
                                                       : (*r)->event().start_s;
        return ns(std::floor(t));
    }
    return 0;
}

void setup_import(CLI::App& app) {
    static std::string input, out, format;
    static double min_confidence = 0.6;
    app.add_option("input", input, "Recording file, or a Pupil recording folder")->required();
    app.add_option("--out,-o", out, "Output: X.xdf (every stream) or X.csv (processed gaze)")
        ->required();
    app.add_option("--format", format, "Force a format (default: detected from the content)");
    app.add_option("--min-confidence", min_confidence, "Pupil: gaze below it is invalid")
        ->check(CLI::Range(0.0, 1.0));
    app.callback([] {
        import::Options o;
        o.min_confidence = min_confidence;
        if (!format.empty()) {
            o.format = import::format_from_name(format);
            if (!o.format) throw std::runtime_error("unknown format '" + format + "'");
        }
        const bool csv = out.size() > 4 && out.compare(out.size() - 4, 4, ".csv") == 0;
        if (!csv && !(out.size() > 4 && out.compare(out.size() - 4, 4, ".xdf") == 0))
            throw std::runtime_error("--out must end in .xdf or .csv");
        const int64_t origin = first_time_ns(input, o);
        auto opened = import::open(input, o);
        if (!opened) throw std::runtime_error(opened.error().message);
        import::Reader& r = **opened;
        const import::SourceInfo src = r.info();
        const record::RecordingInfo info = recording_info(src, origin);
        gaze::Pipeline chain(record::pipeline_config(info));

        std::unique_ptr<XdfOut> x;
        std::FILE* c = nullptr;
        if (csv) {
            c = std::fopen(out.c_str(), "w");
            if (!c) throw std::runtime_error("cannot write " + out);
            write_csv_header(c,
                             "source=" + src.path + " format=" + import::format_name(src.format));
        } else {
            x = std::make_unique<XdfOut>(out, src, info);
        }
        uint64_t index = 0;
        std::vector<gaze::GazeSample> done;
        const auto publish = [&] {
            for (auto& g : done) {
                g.t_processed_ns = g.t_receive_ns;  // no live host: keep the output reproducible
                if (x) x->gaze(g, index, origin);
                if (c) {
                    fovea_gaze_record rec = daemon::to_ring_record(g, false);
                    rec.index = index;
                    rec.t_publish_ns = g.t_processed_ns;
                    write_csv_row(c, rec);
                }
                ++index;
            }
        };
        for (auto it = r.next(); it != import::Item::kEnd; it = r.next()) {
            if (it == import::Item::kMarker && x) x->marker(r.marker());
            if (it == import::Item::kEvent && x) x->event(r.event());
            if (it != import::Item::kSample) continue;
            gaze::RawSample s = r.sample().raw;
            s.t_receive_ns = ns(r.sample().time_s);
            if (x) x->raw(s, r.sample(), origin);
            chain.process(s, done);
            publish();
        }
        chain.flush(done);
        publish();
        if (x) x->close();
        if (c && std::fclose(c) != 0) throw std::runtime_error("writing " + out + " failed");

        const import::ReadStats& st = r.stats();
        for (const auto& i : st.issues) std::fprintf(stderr, "fovea import: %s\n", i.c_str());
        if (st.issue_count > st.issues.size())
            std::fprintf(stderr, "fovea import: ... %llu more issues\n",
                         static_cast<unsigned long long>(st.issue_count - st.issues.size()));
        if (!r.error().empty()) throw std::runtime_error(r.error());
        std::printf("%s: %s (%s%s%s), %.2f Hz, %s coordinates\n", src.path.c_str(),
                    import::format_name(src.format), src.variant.c_str(),
                    src.device.empty() ? "" : ", ", src.device.c_str(), r.info().rate_hz(),
                    import::coordinates_name(src.coordinates));
        std::printf(
            "samples %llu (%llu without valid gaze), markers %llu, events %llu, "
            "skipped %llu%s -> %s (%llu processed)\n",
            static_cast<unsigned long long>(st.samples),
            static_cast<unsigned long long>(st.invalid_samples),
            static_cast<unsigned long long>(st.markers), static_cast<unsigned long long>(st.events),
            static_cast<unsigned long long>(st.skipped), st.truncated ? " (last line cut off)" : "",
            out.c_str(), static_cast<unsigned long long>(index));
        if (csv && (st.markers || st.events))
            std::printf("markers and events are not written to CSV: use --out X.xdf\n");
        if (st.samples + st.markers + st.events == 0)
            throw std::runtime_error(src.path + ": nothing to import");
    });
}

const Command kImport{"import", "Import another tracker's recording into a Fovea recording",
                      &setup_import};

}  // namespace
}  // namespace fovea::cli
