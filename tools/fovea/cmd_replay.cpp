// fovea replay FILE.xdf: run a recording's raw samples through the gaze chain again and check
// that every processed sample matches what the daemon published, bit for bit.
#include <cstdio>
#include <stdexcept>
#include <string>

#include "command.hpp"
#include "fovea/record/offline.hpp"
#include "fovea/record/xdf.hpp"

namespace fovea::cli {
namespace {

void setup_replay(CLI::App& app) {
    static std::string file, csv_dir;
    app.add_option("file", file, "Recording (.xdf)")->required();
    app.add_option("--csv", csv_dir, "Also write the replayed samples as FoveaGaze.csv in DIR");
    app.callback([] {
        auto f = record::xdf::read_file(file);
        if (!f) throw std::runtime_error(f.error().message);
        auto rec = record::decode_recording(*f);
        if (!rec) throw std::runtime_error(rec.error().message);
        const auto res = record::replay(*rec);
        uint64_t events[6] = {};
        for (const auto& g : res.gaze) events[std::min<int>(5, static_cast<int>(g.event))]++;
        std::printf("replayed %zu raw samples -> %llu processed (recording has %llu)\n",
                    rec->raw.size(), static_cast<unsigned long long>(res.replayed),
                    static_cast<unsigned long long>(res.recorded));
        std::printf(
            "events: fixation %llu, saccade %llu, pso %llu, pursuit %llu, blink %llu, "
            "unknown %llu\n",
            (unsigned long long)events[1], (unsigned long long)events[2],
            (unsigned long long)events[3], (unsigned long long)events[4],
            (unsigned long long)events[5], (unsigned long long)events[0]);
        std::printf("compared %llu samples: %llu differ (%llu in their event)\n",
                    static_cast<unsigned long long>(res.compared),
                    static_cast<unsigned long long>(res.mismatches),
                    static_cast<unsigned long long>(res.event_mismatches));
        if (!csv_dir.empty()) {
            // write the replayed stream through the same exporter as recordings
            record::xdf::ChunkEncoder enc;
            enc.magic();
            enc.file_header();
            enc.stream_header(record::kGazeStreamId, record::gaze_stream_info(rec->info));
            std::vector<double> stamps, rows(res.gaze.size() * record::gaze_channel_count());
            for (std::size_t i = 0; i < res.gaze.size(); ++i) {
                stamps.push_back(static_cast<double>(res.gaze[i].t_capture_ns) * 1e-9);
                record::encode_gaze(res.gaze[i], 0, i, rec->info.time_origin_ns,
                                    &rows[i * record::gaze_channel_count()]);
            }
            enc.samples(record::kGazeStreamId, record::xdf::Format::kDouble64,
                        record::gaze_channel_count(), stamps.data(), rows.data(), stamps.size());
            auto parsed = record::xdf::parse(enc.buffer().data(), enc.buffer().size());
            if (!parsed) throw std::runtime_error(parsed.error().message);
            auto out = record::export_csv(*parsed, csv_dir);
            if (!out) throw std::runtime_error(out.error().message);
            std::printf("replayed samples written to %s\n", out->front().path.c_str());
        }
        if (res.mismatches) {
            std::fprintf(stderr, "fovea replay: first difference at sample %lld (%s)\n",
                         static_cast<long long>(res.first_mismatch),
                         res.first_mismatch_field.c_str());
            throw CLI::RuntimeError(3);
        }
        std::printf("identical to the live run\n");
    });
}

const Command kReplay{"replay", "Re-run a recording through the gaze chain and compare",
                      &setup_replay};

}  // namespace
}  // namespace fovea::cli
