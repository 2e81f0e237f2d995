// `fovea import` over every recording of ../shared/data/recordings: the XDF it writes is read by
// the project's own XDF reader, decodes as a Fovea recording, replays bit for bit through the
// chain, and `fovea report`'s generator accepts it; sample, marker and event counts and the
// first/last stamps match counts taken independently (recordings.hpp). A CSV output round-trips
// through the fovea-csv importer.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <string>

#include "../support/child_process.hpp"
#include "fovea/record/offline.hpp"
#include "fovea/record/report.hpp"
#include "fovea/record/xdf.hpp"
#include "recordings.hpp"

namespace fovea::import {
namespace {

namespace fs = std::filesystem;

struct Scratch {
    fs::path dir = fs::temp_directory_path() / ("fovea_import_cli_" + std::to_string(::getpid()));
    Scratch() { fs::create_directories(dir); }
    ~Scratch() { fs::remove_all(dir); }
};

int run_import(const std::vector<std::string>& args, const fs::path& log, std::string* err) {
    auto p = fovea::testing::spawn_logged(fovea::testing::kFoveaBinary, args,
                                          (log.string() + ".out"), (log.string() + ".err"));
    const int rc = p->wait();
    if (err) *err = p->err() + p->out();
    return rc;
}

TEST(ImportCli, EveryRecordingToXdfThatReplaysAndReports) {
    if (!fs::exists(test::kData / "recordings")) GTEST_SKIP() << "no ../shared/data/recordings";
    if (!fs::exists(fovea::testing::kFoveaBinary)) GTEST_SKIP() << "no fovea binary";
    Scratch tmp;
    int n = 0;
    for (const auto& u : test::recordings().units) {
        const fs::path out = tmp.dir / (std::to_string(n++) + ".xdf");
        std::string log;
        ASSERT_EQ(run_import({"import", u.path.string(), "--out", out.string()}, out, &log), 0)
            << u.path << "\n"
            << log;
        auto f = record::xdf::read_file(out.string());
        ASSERT_TRUE(f.ok()) << f.error().message;
        EXPECT_FALSE(f->truncated) << u.path;
        auto rec = record::decode_recording(*f);
        ASSERT_TRUE(rec.ok()) << rec.error().message;
        for (const auto& want : u.expect) {
            const char* name = want.kind == Item::kSample   ? record::kRawStreamName
                               : want.kind == Item::kMarker ? "FoveaMarkers"
                                                            : "FoveaTrackerEvents";
            const record::xdf::Stream* s = f->find(name);
            ASSERT_NE(s, nullptr) << u.path << " " << name;
            ASSERT_EQ(s->sample_count(), want.count.rows) << u.path << " " << name;
            if (s->sample_count() == 0 || !std::isfinite(want.count.first)) continue;
            const auto [lo, hi] = std::minmax_element(s->stamps.begin(), s->stamps.end());
            EXPECT_NEAR(*lo, want.count.first * want.scale, 1e-6) << u.path << " " << name;
            EXPECT_NEAR(*hi, want.count.last * want.scale, 1e-6) << u.path << " " << name;
        }
        // Every raw sample came out of the chain, and the chain reproduces itself from the file.
        EXPECT_EQ(rec->gaze.size(), rec->raw.size()) << u.path;
        const auto replayed = record::replay(*rec);
        EXPECT_EQ(replayed.mismatches, 0u) << u.path << " first at " << replayed.first_mismatch
                                           << " (" << replayed.first_mismatch_field << ")";
        if (!rec->raw.empty()) {
            auto report = record::make_report(*f, out.string(), (tmp.dir / "report").string());
            EXPECT_TRUE(report.ok()) << u.path << ": " << report.error().message;
        }
        fs::remove(out);
    }
}

TEST(ImportCli, CsvOutputReadsBackAsAFoveaCsv) {
    const fs::path asc = test::kData / "recordings/eyelink/mne-testing-data/test_eyelink.asc";
    if (!fs::exists(asc)) GTEST_SKIP() << "no " << asc;
    if (!fs::exists(fovea::testing::kFoveaBinary)) GTEST_SKIP() << "no fovea binary";
    Scratch tmp;
    const fs::path out = tmp.dir / "asc.csv";
    std::string log;
    ASSERT_EQ(run_import({"import", asc.string(), "--out", out.string()}, out, &log), 0) << log;
    auto r = open(out.string());
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ((*r)->info().format, Format::kFoveaCsv);
    uint64_t samples = 0;
    for (auto it = (*r)->next(); it != Item::kEnd; it = (*r)->next())
        samples += it == Item::kSample;
    EXPECT_EQ(samples, test::asc_count(asc, Item::kSample).rows);
    EXPECT_EQ((*r)->stats().skipped, 0u);
}

TEST(ImportCli, BadInputIsOneClearLine) {
    if (!fs::exists(fovea::testing::kFoveaBinary)) GTEST_SKIP() << "no fovea binary";
    Scratch tmp;
    const fs::path junk = tmp.dir / "junk.txt";
    std::ofstream(junk) << "hello\n";
    std::string log;
    EXPECT_NE(run_import({"import", junk.string(), "--out", (tmp.dir / "x.xdf").string()},
                         tmp.dir / "junk", &log),
              0);
    EXPECT_NE(log.find("junk.txt: unknown format"), std::string::npos) << log;
    EXPECT_NE(run_import({"import", junk.string(), "--out", (tmp.dir / "x.txt").string()},
                         tmp.dir / "ext", &log),
              0);
    EXPECT_NE(log.find("--out must end in .xdf or .csv"), std::string::npos) << log;
}

}  // namespace
}  // namespace fovea::import
