// Event detection against the hand-labelled lund2013 recordings (Andersson et al. 2017 scoring).
// Floors: the targets where the detector reaches them, otherwise the measured value
// minus 0.02 (a regression floor, marked "below target"; README.md has the honest numbers).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include "../support/child_process.hpp"
#include "fovea/eval/dataset.hpp"
#include "fovea/eval/detect.hpp"
#include "fovea/eval/scoring.hpp"

namespace fovea::eval {

using gaze::DetectorMode;
using gaze::DetectorParams;
using gaze::Event;
namespace {

const std::string kDir = std::string(FOVEA_SHARED_DATA_DIR) + "/lund2013";

DatasetScore evaluate(DetectorMode mode, double lookahead_s = DetectorParams{}.lookahead_s) {
    auto set = load_lund2013(kDir);
    EXPECT_TRUE(set.ok());
    DetectorParams params;
    params.lookahead_s = lookahead_s;
    std::vector<std::vector<Event>> det;
    for (const auto& r : set->recordings) det.push_back(detect(r, mode, params));
    return score(*set, det);
}

double kappa(const DatasetScore& s, const char* stimulus, const char* event) {
    return s.cells.at(stimulus).at(event).at(kAllCoders).kappa();
}

struct Floor {
    const char* stimulus;
    const char* event;
    double floor;
    bool target;  // true: the target; false: regression floor below target
};

const Floor kOffline[] = {
    {"img", "saccade", 0.85, true},
    {"dots", "saccade", 0.78, true},
    {"video", "saccade", 0.84, true},
    {"img", "fixation", 0.75, true},
    {"dots", "fixation", 0.55, true},
    // Video fixation: .559 in sample with the fitted 1/sqrt(span) speed threshold (target .55),
    // .524 (in sample = held out) with the 1-deg displacement bound shipped 2026-12-06, which
    // generalizes (held out .489 before; daemon/eval/README.md): the floor is .524 - .02.
    {"video", "fixation", 0.50, false},
    {"img", "pso", 0.65, true},
    {"dots", "pso", 0.60, true},
    {"video", "pso", 0.63, true},
};

class Lund2013 : public ::testing::Test {
protected:
    void SetUp() override {
        if (!std::filesystem::is_directory(kDir)) GTEST_SKIP() << "no labelled data at " << kDir;
    }
};

TEST_F(Lund2013, OfflineKappaMeetsTargetsOrRegressionFloors) {
    const DatasetScore r = evaluate(DetectorMode::kOffline);
    EXPECT_GT(r.samples, 100000u);
    for (const auto& f : kOffline) {
        const double k = kappa(r, f.stimulus, f.event);
        std::printf("offline %-5s %-8s kappa %.3f  floor %.2f (%s)\n", f.stimulus, f.event, k,
                    f.floor, f.target ? "target" : "below target");
        EXPECT_GE(k, f.floor) << f.stimulus << " " << f.event;
    }
}

// At the default look-ahead (350 ms, the smallest bound that keeps every event within 0.05;
// 300 ms loses 0.06 on dots fixations). At 100 ms the fixation/pursuit split loses 0.02-0.23
// kappa, saccades and PSO do not (their thresholds learn at stage 2, so they do not depend on
// the look-ahead at all).
TEST_F(Lund2013, OnlineAtDefaultLookaheadWithinFiveHundredthsOfOffline) {
    const DatasetScore off = evaluate(DetectorMode::kOffline);
    const DatasetScore on = evaluate(DetectorMode::kOnline);
    for (const auto& f : kOffline) {
        const double a = kappa(off, f.stimulus, f.event);
        const double b = kappa(on, f.stimulus, f.event);
        std::printf("online %-5s %-8s kappa %.3f (offline %.3f)\n", f.stimulus, f.event, b, a);
        EXPECT_GE(b, a - 0.05) << f.stimulus << " " << f.event;
    }
}

TEST_F(Lund2013, OnlineShortLookaheadKeepsSaccadesAndPso) {
    const DatasetScore off = evaluate(DetectorMode::kOffline);
    const DatasetScore on = evaluate(DetectorMode::kOnline, 0.100);
    for (const char* stim : {"img", "dots", "video"}) {
        for (const char* ev : {"saccade", "pso"}) {
            const double a = kappa(off, stim, ev);
            const double b = kappa(on, stim, ev);
            EXPECT_GE(b, a - 0.05) << stim << " " << ev;
        }
    }
}

// `fovea eval-events --per-file --dump`: the per-recording table and one CSV per recording with
// the detector's event next to each coder's label, on a generated pair of labelled files.
TEST(EvalEventsCli, PerFileTableAndDumpCarryDetectionsAndCoderLabels) {
    const std::string& fovea = fovea::testing::kFoveaBinary;
    if (!std::filesystem::exists(fovea)) GTEST_SKIP() << "no fovea binary at " << fovea;
    const auto dir = std::filesystem::temp_directory_path() /
                     ("fovea_eval_events_cli_" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir / "in");
    const int n = 1500, onset = 700, len = 20;  // 500 Hz; a 300 px saccade at sample 700
    for (const char* coder : {"MN", "RA"}) {
        std::FILE* f = std::fopen(
            (dir / "in" / ("img__SYN_labelled_" + std::string(coder) + ".csv")).c_str(), "w");
        ASSERT_NE(f, nullptr);
        std::fprintf(f,
                     "# sampFreq=500 viewDist_m=0.67 screenDim_m=0.38,0.3 "
                     "screenRes_px=1024,768\nt_us,pupil_h,pupil_v,x_px,y_px,label\n");
        const int shift = coder[0] == 'R' ? 1 : 0;  // the coders disagree by one sample
        for (int i = 0; i < n; ++i) {
            const double tau = std::clamp((i - onset) / static_cast<double>(len), 0.0, 1.0);
            const double x = 350.0 + 300.0 * tau * tau * tau * (10 - 15 * tau + 6 * tau * tau) +
                             0.3 * std::sin(i * 1.7);
            const bool sacc = i >= onset + shift && i < onset + len + shift;
            std::fprintf(f, "%d,20,20,%.3f,%.3f,%d\n", i * 2000, x, 380.0 + 0.3 * std::cos(i),
                         sacc ? 2 : 1);
        }
        std::fclose(f);
    }
    auto p = fovea::testing::spawn_logged(
        fovea,
        {"eval-events", (dir / "in").string(), "--per-file", "--dump", (dir / "out").string()},
        (dir / "stdout").string(), (dir / "stderr").string());
    ASSERT_EQ(p->wait(), 0) << p->err();
    EXPECT_NE(p->out().find("SYN_labelled"), std::string::npos) << p->out();
    std::ifstream dump(dir / "out" / "img__SYN_labelled.csv");
    ASSERT_TRUE(dump.good());
    std::string line;
    std::getline(dump, line);
    EXPECT_EQ(line, "i,t_s,x_px,y_px,det,MN,RA");
    int rows = 0, detected = 0, mn = 0, ra = 0;
    while (std::getline(dump, line)) {
        int i = 0, det = 0, a = 0, b = 0;
        double t = 0, x = 0, y = 0;
        ASSERT_EQ(
            std::sscanf(line.c_str(), "%d,%lf,%lf,%lf,%d,%d,%d", &i, &t, &x, &y, &det, &a, &b), 7)
            << line;
        EXPECT_EQ(i, rows++);
        detected += det == 2 && i >= onset && i < onset + len;
        mn += a == 2;
        ra += b == 2 && i > onset;
    }
    EXPECT_EQ(rows, n);
    EXPECT_EQ(mn, len);
    EXPECT_EQ(ra, len);
    EXPECT_GE(detected, len * 3 / 4);
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace fovea::eval
