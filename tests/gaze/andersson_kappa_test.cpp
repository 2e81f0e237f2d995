// Event detection against the hand-labelled lund2013 recordings (Andersson et al. 2017 scoring).
// Floors: the targets where the detector reaches them, otherwise the measured value
// minus 0.02 (a regression floor, marked "below target"; README.md has the honest numbers).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>

#include "fovea/gaze/labelled.hpp"

namespace fovea::gaze {
namespace {

const std::string kDir = std::string(FOVEA_SHARED_DATA_DIR) + "/lund2013";

EvalResult evaluate(DetectorMode mode, double lookahead_s = DetectorParams{}.lookahead_s) {
    auto set = load_labelled_dir(kDir);
    EXPECT_TRUE(set.ok());
    DetectorParams params;
    params.lookahead_s = lookahead_s;
    std::vector<std::vector<Event>> det;
    for (const auto& r : set->recordings) det.push_back(run_pipeline(*r.data, mode, params));
    return score(*set, det);
}

struct Floor {
    const char* stimulus;
    const char* event;
    double floor;
    bool target;  // true: the target; false: regression floor below target
};

const Floor kOffline[] = {
    {"img", "saccade", 0.85, true},   {"dots", "saccade", 0.78, true},
    {"video", "saccade", 0.84, true}, {"img", "fixation", 0.75, true},
    {"dots", "fixation", 0.55, true}, {"video", "fixation", 0.55, true},
    {"img", "pso", 0.65, true},       {"dots", "pso", 0.60, true},
    {"video", "pso", 0.63, true},
};

class Lund2013 : public ::testing::Test {
protected:
    void SetUp() override {
        if (!std::filesystem::is_directory(kDir)) GTEST_SKIP() << "no labelled data at " << kDir;
    }
};

TEST_F(Lund2013, OfflineKappaMeetsTargetsOrRegressionFloors) {
    const EvalResult r = evaluate(DetectorMode::kOffline);
    EXPECT_GT(r.samples, 100000u);
    for (const auto& f : kOffline) {
        const double k = r.kappa.at(f.stimulus).at(f.event).at("both");
        std::printf("offline %-5s %-8s kappa %.3f  floor %.2f (%s)\n", f.stimulus, f.event, k,
                    f.floor, f.target ? "target" : "below target");
        EXPECT_GE(k, f.floor) << f.stimulus << " " << f.event;
    }
}

// With a 350 ms look-ahead (the smallest bound that keeps every event within 0.05; 300 ms
// loses 0.07 on dots fixations); at the daemon's default 100 ms the fixation/pursuit split
// loses 0.05-0.25 kappa, saccades and PSO do not (their thresholds learn at stage 2, so they
// do not depend on the look-ahead at all).
TEST_F(Lund2013, OnlineWith350msLookaheadWithinFiveHundredthsOfOffline) {
    const EvalResult off = evaluate(DetectorMode::kOffline);
    const EvalResult on = evaluate(DetectorMode::kOnline, 0.35);
    for (const auto& f : kOffline) {
        const double a = off.kappa.at(f.stimulus).at(f.event).at("both");
        const double b = on.kappa.at(f.stimulus).at(f.event).at("both");
        std::printf("online %-5s %-8s kappa %.3f (offline %.3f)\n", f.stimulus, f.event, b, a);
        EXPECT_GE(b, a - 0.05) << f.stimulus << " " << f.event;
    }
}

TEST_F(Lund2013, OnlineDefaultLookaheadKeepsSaccadesAndPso) {
    const EvalResult off = evaluate(DetectorMode::kOffline);
    const EvalResult on = evaluate(DetectorMode::kOnline);
    for (const char* stim : {"img", "dots", "video"}) {
        for (const char* ev : {"saccade", "pso"}) {
            const double a = off.kappa.at(stim).at(ev).at("both");
            const double b = on.kappa.at(stim).at(ev).at("both");
            EXPECT_GE(b, a - 0.05) << stim << " " << ev;
        }
    }
}

TEST(Agreement, KappaMatchesHandComputedExample) {
    Agreement a;
    // 20 both, 5 only a, 10 only b, 65 neither: po = .85, pe = .25*.30 + .75*.70 = .6
    for (int i = 0; i < 20; ++i) a.add(true, true);
    for (int i = 0; i < 5; ++i) a.add(true, false);
    for (int i = 0; i < 10; ++i) a.add(false, true);
    for (int i = 0; i < 65; ++i) a.add(false, false);
    EXPECT_NEAR(a.kappa(), (0.85 - 0.6) / 0.4, 1e-12);
    EXPECT_TRUE(std::isnan(Agreement{}.kappa()));
}

TEST(LabelledCsv, BadFilesAreErrorsNotCrashes) {
    const auto p = std::filesystem::temp_directory_path() / "fovea_bad_labelled.csv";
    {
        std::FILE* f = std::fopen(p.c_str(), "w");
        std::fputs("t_us,x\n1,2\n", f);
        std::fclose(f);
    }
    EXPECT_FALSE(load_labelled_csv(p.string()).ok());
    EXPECT_FALSE(load_labelled_dir("/nonexistent/dir").ok());
    std::filesystem::remove(p);
}

}  // namespace
}  // namespace fovea::gaze
