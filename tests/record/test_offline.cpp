#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include <gtest/gtest.h>

#include "fovea/gaze/pipeline.hpp"
#include "fovea/record/offline.hpp"
#include "fovea/record/plot.hpp"
#include "fovea/record/recorder.hpp"
#include "fovea/record/report.hpp"
#include "sim/sim_tracker.hpp"
#include "synthetic.hpp"
#include "test_util.hpp"

using namespace fovea::record;
namespace gaze = fovea::gaze;

namespace {

struct LiveRun {
    std::string path;
    std::vector<gaze::GazeSample> published;
    std::vector<int64_t> t_publish;
};

// What fovead does per sample, with the simulated tracker: process, publish, record. Landing
// prediction is toggled mid-run as the daemon does when readers come and go.
// With warmup_s > 0 the chain runs that long before the recording starts, as in a daemon that
// was up before record.start; `preroll` then hands that history to the recorder.
LiveRun record_sim(const std::string& path, double seconds, uint64_t seed, double warmup_s = 0,
                   bool preroll = true) {
    fovea::drivers::sim::SimConfig sc;
    sc.seed = seed;
    sc.start_ns = 5'000'000'000'000;
    fovea::drivers::sim::SimTracker tracker(sc);
    RecorderOptions o;
    o.path = path;
    o.info.device_name = "sim";
    o.info.driver = "sim";
    o.info.nominal_rate_hz = sc.rate_hz;
    o.info.clock.counter_bits = sc.counter_bits;
    o.info.clock.tick_hz = sc.tick_hz;
    o.info.display = sc.display;
    o.flush_interval_ns = 50'000'000;
    // as fovead: built without landing prediction, switched on when a reader attaches
    gaze::PipelineConfig pc = pipeline_config(o.info);
    pc.predict_landing = false;
    gaze::Pipeline pipeline(pc);
    LiveRun live{path, {}, {}};
    std::vector<gaze::GazeSample> out;
    bool predict = false;
    std::vector<std::pair<gaze::RawSample, bool>> history;
    for (int i = 0; i < static_cast<int>(warmup_s * sc.rate_hz); ++i) {
        auto f = tracker.next();
        f.raw.t_receive_ns = f.t_true_ns + 1'800'000 + (i * 104729) % 400'000;
        pipeline.process(f.raw, out);  // published before the recording: not compared
        history.emplace_back(f.raw, predict);
    }
    o.info.preroll_from_start = preroll;
    auto rec = Recorder::start(o);
    EXPECT_TRUE(rec.ok());
    if (preroll) {
        for (const auto& [raw, p] : history) (*rec)->push_raw(raw, p, true);
    }
    const int n = static_cast<int>(seconds * sc.rate_hz);
    uint64_t index = 0;
    for (int i = 0; i < n; ++i) {
        auto f = tracker.next();
        f.raw.t_receive_ns = f.t_true_ns + 1'800'000 + (i * 7919) % 400'000;  // transport jitter
        if (i == n / 3 || i == 2 * n / 3) {
            predict = !predict;
            pipeline.set_predict_landing(predict);
        }
        (*rec)->push_raw(f.raw, predict);
        pipeline.process(f.raw, out);
        for (auto& s : out) {
            if (s.t_processed_ns == 0) s.t_processed_ns = f.raw.t_receive_ns + 25'000;
            s.device_id = f.raw.device_id;
            const int64_t pub = s.t_processed_ns + 3'000;
            (*rec)->push_gaze(s, pub, index++);
            live.published.push_back(s);
            live.t_publish.push_back(pub);
        }
    }
    auto st = (*rec)->stop();
    EXPECT_TRUE(st.ok());
    return live;
}

std::vector<std::vector<std::string>> read_csv(const std::string& path) {
    std::ifstream in(path);
    std::vector<std::vector<std::string>> rows;
    std::string line;
    while (std::getline(in, line)) {
        std::vector<std::string> cells;
        std::stringstream ss(line);
        std::string c;
        while (std::getline(ss, c, ',')) cells.push_back(c);
        if (!line.empty() && line.back() == ',') cells.emplace_back();
        rows.push_back(cells);
    }
    return rows;
}

}  // namespace

TEST(Replay, SimRecordingReplaysBitIdenticallyThroughThePipeline) {
    const test::ScratchDir dir("replay");
    const auto live = record_sim((dir / "sim.xdf").string(), 10.0, 42);
    auto f = xdf::read_file(live.path);
    ASSERT_TRUE(f.ok()) << f.error().message;
    auto rec = decode_recording(*f);
    ASSERT_TRUE(rec.ok()) << rec.error().message;
    ASSERT_EQ(rec->gaze.size(), live.published.size());
    const auto res = replay(*rec);
    EXPECT_EQ(res.compared, live.published.size());
    EXPECT_EQ(res.mismatches, 0u) << "first at " << res.first_mismatch << ": "
                                  << res.first_mismatch_field;
    EXPECT_EQ(res.event_mismatches, 0u);
    EXPECT_GE(res.replayed, res.recorded);
    uint64_t saccades = 0;
    for (const auto& g : rec->gaze) saccades += g.event == gaze::Event::kSaccade;
    EXPECT_GT(saccades, 100u);  // the comparison covered real events
}

TEST(Replay, PrerollRebuildsTheChainStateOfARecordingStartedLate) {
    const test::ScratchDir dir("preroll");
    const auto live = record_sim((dir / "late.xdf").string(), 3.0, 21, 4.0, true);
    auto f = xdf::read_file(live.path);
    ASSERT_TRUE(f.ok());
    auto rec = decode_recording(*f);
    ASSERT_TRUE(rec.ok());
    EXPECT_TRUE(rec->info.preroll_from_start);
    EXPECT_EQ(std::count(rec->raw_preroll.begin(), rec->raw_preroll.end(), true), 4000);
    const auto res = replay(*rec);
    EXPECT_EQ(res.compared, live.published.size());
    EXPECT_EQ(res.mismatches, 0u) << "first at " << res.first_mismatch << ": "
                                  << res.first_mismatch_field;
}

TEST(Replay, WithoutPrerollALateRecordingIsReportedAsDifferent) {
    // the chain's state (clock mapping, filters, adaptive thresholds) depends on its history
    const test::ScratchDir dir("nopreroll");
    const auto live = record_sim((dir / "late.xdf").string(), 3.0, 21, 4.0, false);
    auto f = xdf::read_file(live.path);
    ASSERT_TRUE(f.ok());
    auto rec = decode_recording(*f);
    ASSERT_TRUE(rec.ok());
    EXPECT_FALSE(rec->info.preroll_from_start);
    EXPECT_GT(replay(*rec).mismatches, 0u);
}

TEST(Replay, ATamperedRecordingIsReportedAsAMismatch) {
    const test::ScratchDir dir("tamper");
    const auto live = record_sim((dir / "sim.xdf").string(), 2.0, 7);
    auto f = xdf::read_file(live.path);
    ASSERT_TRUE(f.ok());
    auto rec = decode_recording(*f);
    ASSERT_TRUE(rec.ok());
    rec->raw[500].left.x += 1e-12;  // one raw sample nudged by far less than a pixel
    const auto res = replay(*rec);
    EXPECT_GT(res.mismatches, 0u);
    EXPECT_GE(res.first_mismatch, 400);
}

TEST(Export, CsvRowsEqualWhatWasPublished) {
    const test::ScratchDir dir("csv");
    const auto live = record_sim((dir / "sim.xdf").string(), 3.0, 3);
    auto f = xdf::read_file(live.path);
    ASSERT_TRUE(f.ok());
    auto files = export_csv(*f, (dir / "csv").string());
    ASSERT_TRUE(files.ok()) << files.error().message;
    ASSERT_EQ(files->size(), 3u);
    const auto rows = read_csv((dir / "csv" / "FoveaGaze.csv").string());
    ASSERT_EQ(rows.size(), live.published.size() + 1);
    const auto& head = rows[0];
    auto col = [&](const std::string& name) {
        const auto it = std::find(head.begin(), head.end(), name);
        EXPECT_NE(it, head.end()) << name;
        return static_cast<std::size_t>(it - head.begin());
    };
    const std::size_t c_cap = col("t_capture_ns"), c_pub = col("t_publish_ns"),
                      c_x = col("combined_x"), c_ev = col("event"),
                      c_amp = col("saccade_amplitude_deg");
    for (std::size_t i = 0; i < live.published.size(); ++i) {
        const auto& r = rows[i + 1];
        const auto& s = live.published[i];
        ASSERT_EQ(std::stoll(r[c_cap]), s.t_capture_ns);
        ASSERT_EQ(std::stoll(r[c_pub]), live.t_publish[i]);
        if (std::isnan(s.combined.x)) {
            ASSERT_TRUE(r[c_x].empty());
        } else {
            ASSERT_EQ(std::strtod(r[c_x].c_str(), nullptr), s.combined.x);
        }
        ASSERT_EQ(std::stoi(r[c_ev]), static_cast<int>(s.event));
        if (!std::isnan(s.saccade.amplitude_deg)) {
            ASSERT_EQ(std::strtod(r[c_amp].c_str(), nullptr), s.saccade.amplitude_deg);
        }
    }
    const auto raw = read_csv((dir / "csv" / "FoveaRawGaze.csv").string());
    EXPECT_EQ(raw[0][1], "device_ticks");
    EXPECT_EQ(raw.size(), 3001u);
}

// A latency percentile of 0 on a log axis sits at -inf: every drawing call must stay defined
// (the ASan tree's float-cast-overflow check found the report casting it to int).
TEST(Plot, ValuesOffALogAxisOrNotFiniteDrawNothingAndCastNothingUndefined) {
    Plot p(320, 200, "t", "x", "y");
    p.set_x(1, 1000, true);
    p.set_y(0, 10);
    const double inf = std::numeric_limits<double>::infinity();
    for (double x : {0.0, -5.0, inf, -inf, std::nan("")}) {
        EXPECT_TRUE(std::isfinite(p.px(x))) << x;
        p.vline(x, {200, 0, 0}, "p50");
        p.xspan(x, 10, {0, 0, 200});
        p.bars({x}, {x}, {5}, {0, 200, 0});
        p.line({x, 10}, {1, std::nan("")}, {0, 0, 0});
        p.points({x}, {x}, {0, 0, 0});
    }
    EXPECT_TRUE(std::isfinite(p.py(inf)));
    const Canvas& c = p.finish();
    EXPECT_EQ(c.width(), 320);
}

TEST(Report, WritesHtmlAndEveryPlot) {
    const test::ScratchDir dir("report");
    const auto live = record_sim((dir / "sim.xdf").string(), 5.0, 11);
    auto f = xdf::read_file(live.path);
    ASSERT_TRUE(f.ok());
    auto rep = make_report(*f, live.path, (dir / "report").string());
    ASSERT_TRUE(rep.ok()) << rep.error().message;
    EXPECT_EQ(rep->pngs.size(), 8u);  // 4 latency + trace + main sequence + drops + validity
    EXPECT_GT(rep->saccades, 5u);
    // simulated saccades follow the main sequence by construction; detection must agree within
    // a factor the 1 kHz sampling and the filter allow
    EXPECT_GT(rep->main_sequence_median_ratio, 0.6);
    EXPECT_LT(rep->main_sequence_median_ratio, 1.4);
    std::ifstream html(rep->html_path);
    std::stringstream ss;
    ss << html.rdbuf();
    EXPECT_NE(ss.str().find("data:image/png;base64,iVBORw0KGgo"), std::string::npos);
    for (const auto& p : rep->pngs) EXPECT_GT(std::filesystem::file_size(p), 1000u) << p;
}

TEST(Report, ForeignXdfIsRejectedClearly) {
    xdf::ChunkEncoder e;
    e.magic();
    e.file_header();
    xdf::StreamInfo s;
    s.name = "EEG";
    s.channels = {{"c1", "uV", "EEG"}};
    e.stream_header(1, s);
    auto f = xdf::parse(e.buffer().data(), e.buffer().size());
    ASSERT_TRUE(f.ok());
    const test::ScratchDir dir("foreign");
    auto r = make_report(*f, "x", dir.path().string());
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("not a Fovea recording"), std::string::npos);
}
