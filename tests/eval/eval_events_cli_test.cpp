// `fovea eval-events` on ../shared/data (skips without it): every shared dataset scored on its
// own under datasets.<name>, today's keys kept, and the peer table against EyeLink's parser.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

#include "../support/child_process.hpp"

namespace {

const std::string kData = FOVEA_SHARED_DATA_DIR;

nlohmann::json run_json(const std::vector<std::string>& args, const char* tag,
                        std::chrono::seconds timeout = std::chrono::seconds(60)) {
    const auto tmp = std::filesystem::temp_directory_path() /
                     ("fovea_eval_events_" + std::string(tag) + std::to_string(::getpid()));
    std::filesystem::create_directories(tmp);
    auto p = fovea::testing::spawn_logged(fovea::testing::kFoveaBinary, args,
                                          (tmp / "stdout").string(), (tmp / "stderr").string());
    EXPECT_EQ(p->wait(timeout * fovea::testing::kSlowdown), 0) << p->err();
    nlohmann::json j = nlohmann::json::parse(p->out(), nullptr, false);
    std::filesystem::remove_all(tmp);
    return j;
}

bool have_data() {
    return std::filesystem::is_directory(kData + "/lund2013") &&
           std::filesystem::exists(fovea::testing::kFoveaBinary);
}

// `fovea eval-events ../shared/data --cv dataset --json` with `extra` arguments (a probe such as
// --decimate, or --mode online).
nlohmann::json run_cv_json(std::vector<std::string> extra, const char* tag) {
    std::vector<std::string> args{"eval-events", kData, "--cv", "dataset", "--json"};
    args.insert(args.end(), extra.begin(), extra.end());
    return run_json(args, tag, std::chrono::seconds(240));
}

// A held-out kappa (all coders) as measured; checked with a margin of 0.03 for run-to-run and
// coder-to-coder spread.
struct Floor {
    const char *dataset, *stimulus, *event;
    double held_out;
};

void expect_held_out_above(const nlohmann::json& j, std::span<const Floor> floors,
                           const char* where) {
    for (const Floor& f : floors) {
        const auto& held = j["datasets"][f.dataset]["held_out"]["kappa"];
        ASSERT_TRUE(held.contains(f.stimulus) && held[f.stimulus].contains(f.event))
            << f.dataset << " " << f.stimulus << " " << f.event;
        const auto& k = held[f.stimulus][f.event]["all"];
        ASSERT_TRUE(k.is_number()) << f.dataset << " " << f.stimulus << " " << f.event;
        EXPECT_GE(k.get<double>(), f.held_out - 0.03)
            << f.dataset << " " << f.stimulus << " " << f.event << " " << where;
    }
}

TEST(EvalEventsCli, EverySharedDatasetIsScoredOnItsOwnAndTodaysKeysStay) {
    if (!have_data()) GTEST_SKIP() << "no shared data at " << kData << " or no fovea binary";
    const nlohmann::json j = run_json({"eval-events", kData, "--json"}, "all");
    ASSERT_FALSE(j.is_discarded());
    for (const char* d : {"lund2013", "hooge2018", "uneye", "gazecom", "eyelink"}) {
        ASSERT_TRUE(j["datasets"].contains(d)) << d;
        for (const char* k : {"kappa", "f1_sample", "f1_event"})
            EXPECT_TRUE(j["datasets"][d].contains(k)) << d << " " << k;
    }
    // Today's keys: lund2013's kappa with the coders stacked as "both".
    EXPECT_EQ(j["kappa"]["img"]["saccade"]["both"],
              j["datasets"]["lund2013"]["kappa"]["img"]["saccade"]["all"]);
    EXPECT_EQ(j["samples"], j["datasets"]["lund2013"]["samples"]);
    // What each dataset labels, and only that, is scored: Hooge's coders marked fixations.
    EXPECT_FALSE(j["datasets"]["hooge2018"]["kappa"]["adult"].contains("saccade"));
    EXPECT_EQ(j["datasets"]["hooge2018"]["kappa"]["infant"]["fixation"].size(), 13u);  // 12 + all
    EXPECT_TRUE(j["datasets"]["gazecom"]["f1_event"]["all"].contains("pursuit"));
    EXPECT_FALSE(j["datasets"]["eyelink"]["human_labels"].get<bool>());
    // The coders' own agreement is the human reference (Andersson et al.: fixation .84 on img).
    EXPECT_NEAR(
        j["datasets"]["lund2013"]["coder_agreement"]["img"]["fixation"]["kappa"].get<double>(),
        0.84, 0.01);
}

TEST(EvalEventsCli, AgainstEyelinkScoresEveryAscSourceAgainstTheTrackersParser) {
    if (!have_data()) GTEST_SKIP() << "no shared data at " << kData << " or no fovea binary";
    const std::string dir = kData + "/recordings/eyelink";
    if (!std::filesystem::is_directory(dir)) GTEST_SKIP() << "no " << dir;
    const nlohmann::json j =
        run_json({"eval-events", dir, "--against", "eyelink", "--json"}, "peer");
    ASSERT_FALSE(j.is_discarded());
    const nlohmann::json& k = j["datasets"]["eyelink"]["kappa"];
    int sources = 0;
    for (const char* s :
         {"eyelinkparser/data1", "mne-testing-data/test_eyelink", "sp_tool/eyelink_data_example"}) {
        ASSERT_TRUE(k.contains(s)) << s;
        ++sources;
        // Both detectors see the same samples: their saccades agree far above chance once the
        // PSO is scored as the parser's fixation (Dataset::pso_without_label; as the saccade's
        // tail, mne-testing-data's kappa was .571 and its event F1 .466).
        EXPECT_GT(k[s]["saccade"]["all"].get<double>(), 0.70) << s;
        EXPECT_GT(j["datasets"]["eyelink"]["f1_event"][s]["saccade"]["all"].get<double>(), 0.80)
            << s;
        EXPECT_GT(j["datasets"]["eyelink"]["f1_event"][s]["fixation"]["all"].get<double>(), 0.6)
            << s;
    }
    EXPECT_EQ(sources, 3);
}

}  // namespace

// Leave-one-dataset-out (--cv dataset): every human-labelled dataset scored with constants fitted
// on the others. The floors are the held-out kappas (all coders stacked) measured at landing
// minus 0.03: offline detection is deterministic, so the margin only absorbs floating-point
// differences between builds and changes smaller than the coders' own spread (MN vs RA on
// lund2013 differ by .01-.16 kappa per cell). Where a floor is far below the coders' agreement
// that is the measured state (daemon/eval/README.md), not a target. The fixation and pursuit
// floors of lund2013 and GazeCom were reset to the held-out kappas of the 1-deg displacement
// bound for pursuit (2026-12-06, pursuit_dps no longer fitted): Lund dots fixation .665 -> .644
// and pursuit .701 -> .684 fell with it (one trial, UH25_trial1), the rest rose. The offline
// microsaccade stage (Engbert & Kliegl 2003, 2026-12-06) raised U'n'Eye saccade .459 -> .600 and
// Hooge adult .628 -> .635; it lowered GazeCom saccade .794 -> .790, fixation .693 -> .690 and
// Lund saccade (img .873 -> .870, dots .793 -> .791, video .874 -> .865), whose floors were
// kept at their earlier values, not lowered. Pooling pursuit across catch-up saccades
// (pursuit_catch_up, 2026-12-06 later) raised Lund dots fixation .644 -> .707 and pursuit .684
// -> .734, video fixation .524 -> .533 and pursuit .526 -> .536; no cell fell. The pursuit floor
// as a 3-SD bound on noise and drift (stop 41) moved img fixation .804 -> .794, video fixation
// .533 -> .538 and Hooge adult .635 -> .630, and nothing is fitted any more.
TEST(EvalEventsCli, HeldOutKappaPerDatasetStaysAboveItsFloor) {
    if (!have_data()) GTEST_SKIP() << "no shared data at " << kData << " or no fovea binary";
    const auto j = run_cv_json({}, "cv");
    ASSERT_FALSE(j.is_discarded());
    const Floor floors[] = {
        {"lund2013", "img", "fixation", 0.803},    {"lund2013", "dots", "fixation", 0.707},
        {"lund2013", "video", "fixation", 0.533},  {"lund2013", "img", "saccade", 0.873},
        {"lund2013", "dots", "saccade", 0.793},    {"lund2013", "video", "saccade", 0.874},
        {"lund2013", "img", "pso", 0.694},         {"lund2013", "dots", "pso", 0.632},
        {"lund2013", "video", "pso", 0.642},       {"lund2013", "dots", "pursuit", 0.734},
        {"lund2013", "video", "pursuit", 0.536},   {"lund2013", "img", "blink", 0.891},
        {"hooge2018", "adult", "fixation", 0.635}, {"hooge2018", "infant", "fixation", 0.850},
        {"gazecom", "all", "fixation", 0.693},     {"gazecom", "all", "saccade", 0.794},
        {"gazecom", "all", "pursuit", 0.572},      {"uneye", "all", "saccade", 0.600},
    };
    expect_held_out_above(j, floors, "held out");
    // Nothing is fitted (pursuit_dps is the literature's 1-deg bound, pursuit_floor_sd a
    // significance level): one candidate, no fold fits anything, and every dataset's held-out
    // score is its in-sample score, cell by cell.
    EXPECT_EQ(j["cv"]["candidates"].get<int>(), 1);
    EXPECT_FALSE(j["cv"].contains("shipped"));
    int cells = 0;
    for (const char* d : {"lund2013", "hooge2018", "gazecom", "uneye"}) {
        const auto& held = j["datasets"][d]["held_out"];
        EXPECT_FALSE(held.contains("fitted") && !held["fitted"].empty()) << d;
        EXPECT_TRUE(held.contains("f1_event")) << d;
        for (const auto& [stimulus, events] : j["datasets"][d]["kappa"].items()) {
            for (const auto& [event, coders] : events.items()) {
                EXPECT_EQ(held["kappa"][stimulus][event]["all"], coders["all"])
                    << d << " " << stimulus << " " << event;
                ++cells;
            }
        }
    }
    EXPECT_GE(cells, 20);
}

// The same recordings at half their rate (--decimate 2: Lund at 250 Hz, GazeCom at 125, Hooge
// at 150, U'n'Eye at 250, EyeLink at 250/500), held out. The pursuit floor's position noise was
// the per-sample second difference, which grows as the interval does (drift adds up): at 250 Hz
// Lund dots fixation / pursuit fell from .707 / .734 to .221 / .275 and video to .263 / .204.
// With the noise over a fixed 2 ms and the floor a 3-SD bound on noise and drift (2026-12-06,
// stop 41) they are .654 / .684 and .518 / .525; GazeCom and Hooge held. Since stop 42 the
// saccade bounds move in by the velocity window's excess at 167 Hz and below
// (trim_window_excess): GazeCom at 125 Hz saccade .715 -> .763 and fixation .646 -> .674, Hooge
// at 150 Hz adult fixation .683 -> .633 (its native .630: Hooge's coders keep wider saccades than
// the detector at any rate, and the untrimmed smear had matched them). Floors: measured minus
// 0.03.
TEST(EvalEventsCli, HeldOutKappaAtHalfTheRateStaysAboveItsFloor) {
    if (!have_data()) GTEST_SKIP() << "no shared data at " << kData << " or no fovea binary";
    const auto j = run_cv_json({"--decimate", "2"}, "cv_half_rate");
    ASSERT_FALSE(j.is_discarded());
    const Floor floors[] = {
        {"lund2013", "dots", "fixation", 0.654},    {"lund2013", "dots", "pursuit", 0.684},
        {"lund2013", "video", "fixation", 0.518},   {"lund2013", "video", "pursuit", 0.525},
        {"lund2013", "img", "fixation", 0.789},     {"lund2013", "dots", "saccade", 0.787},
        {"gazecom", "all", "fixation", 0.674},      {"gazecom", "all", "pursuit", 0.574},
        {"gazecom", "all", "saccade", 0.763},       {"hooge2018", "adult", "fixation", 0.633},
        {"hooge2018", "infant", "fixation", 0.860},
    };
    expect_held_out_above(j, floors, "at half the rate");
}

// A quarter of the rate (--decimate 4: Lund at 125 Hz, the VR trackers' rate, GazeCom at 62.5,
// Hooge at 75), held out. A one-sample velocity window is a central difference over 16-32 ms
// there, and saccades came out a sample wide at each end; with the bounds moved in by the
// window's excess (trim_window_excess, stop 42): Lund saccade img .741 -> .805, video .721 ->
// .808, dots .672 -> .703, GazeCom .584 -> .689 and fixation .420 -> .473; Lund img fixation
// .695 -> .682. Then (stop 43) the thresholds without the saccades' neighbours and pursuit
// without one-interval jumps: GazeCom fixation .473 -> .586, pursuit .171 -> .327, Lund img
// fixation .682 -> .705, Hooge adult .675 -> .694. Floors: measured minus 0.03.
TEST(EvalEventsCli, HeldOutKappaAtAQuarterOfTheRateStaysAboveItsFloor) {
    if (!have_data()) GTEST_SKIP() << "no shared data at " << kData << " or no fovea binary";
    const auto j = run_cv_json({"--decimate", "4"}, "cv_quarter_rate");
    ASSERT_FALSE(j.is_discarded());
    const Floor floors[] = {
        {"lund2013", "img", "saccade", 0.804},      {"lund2013", "video", "saccade", 0.807},
        {"lund2013", "dots", "saccade", 0.700},     {"lund2013", "img", "fixation", 0.705},
        {"lund2013", "dots", "fixation", 0.678},    {"lund2013", "video", "fixation", 0.516},
        {"gazecom", "all", "saccade", 0.683},       {"gazecom", "all", "fixation", 0.586},
        {"gazecom", "all", "pursuit", 0.327},       {"hooge2018", "adult", "fixation", 0.694},
        {"hooge2018", "infant", "fixation", 0.873},
    };
    expect_held_out_above(j, floors, "at a quarter of the rate");
}

// The same recordings through a slightly noisier tracker (--add-noise-deg 0.02: white noise,
// Lund's SMI is ~0.03 deg over 2 ms), held out. The pursuit floor was 85 x the noise: white
// noise raised it above Lund's pursuits and dots fixation / pursuit fell from .707 / .734 to
// .080 / .079 (video .537 / .539 -> .264 / .202). As a 3-SD bound on noise and drift, white
// noise barely moves a window's slope: .636 / .677 and .523 / .531. Floors: measured minus 0.03.
TEST(EvalEventsCli, HeldOutKappaThroughANoisierTrackerStaysAboveItsFloor) {
    if (!have_data()) GTEST_SKIP() << "no shared data at " << kData << " or no fovea binary";
    const auto j = run_cv_json({"--add-noise-deg", "0.02"}, "cv_noisier");
    ASSERT_FALSE(j.is_discarded());
    const Floor floors[] = {
        {"lund2013", "dots", "fixation", 0.636},   {"lund2013", "dots", "pursuit", 0.677},
        {"lund2013", "video", "fixation", 0.523},  {"lund2013", "video", "pursuit", 0.531},
        {"lund2013", "img", "fixation", 0.787},    {"lund2013", "img", "saccade", 0.873},
        {"gazecom", "all", "fixation", 0.706},     {"gazecom", "all", "pursuit", 0.575},
        {"hooge2018", "adult", "fixation", 0.635}, {"hooge2018", "infant", "fixation", 0.850},
    };
    expect_held_out_above(j, floors, "with 0.02 deg more noise");
}

// The same recordings at four times their rate (--upsample 4: Lund and EyeLink at 2000-4000 Hz,
// GazeCom at 1000, Hooge at 1200), with 0.02 deg of white noise on every sample as such a
// tracker would add between the original ones, held out. No labelled recording above 1000 Hz
// exists here: this pins the rate handling (windows in ms, the 2 ms noise reference, buffers)
// at the top of the 60-2000 Hz range. Measured (2026-12-06, stop 42) against native with the
// same noise: Lund dots fixation .646 (.636), video .538 (.523), img saccade .855 (.873); GazeCom
// fixation .634 (.706) and pursuit .494 (.575) lose most: its 250 Hz labels are 4 ms steps that
// the detector now resolves at 1 ms. Floors: measured minus 0.03.
TEST(EvalEventsCli, HeldOutKappaAtFourTimesTheRateStaysAboveItsFloor) {
    if (!have_data()) GTEST_SKIP() << "no shared data at " << kData << " or no fovea binary";
    const auto j = run_cv_json({"--upsample", "4", "--add-noise-deg", "0.02"}, "cv_four_rate");
    ASSERT_FALSE(j.is_discarded());
    const Floor floors[] = {
        {"lund2013", "dots", "fixation", 0.646},   {"lund2013", "dots", "pursuit", 0.686},
        {"lund2013", "video", "fixation", 0.538},  {"lund2013", "video", "pursuit", 0.541},
        {"lund2013", "img", "fixation", 0.779},    {"lund2013", "img", "saccade", 0.855},
        {"gazecom", "all", "fixation", 0.634},     {"gazecom", "all", "pursuit", 0.494},
        {"hooge2018", "adult", "fixation", 0.662}, {"hooge2018", "infant", "fixation", 0.855},
    };
    expect_held_out_above(j, floors, "at four times the rate");
}

// Online mode (what fovead runs), held out: the causal microsaccade stage (SDs from the past,
// 2026-12-06) raised U'n'Eye saccade .128 -> .517 (offline .600); floor minus 0.03 as above.
// Its largest falls elsewhere were Lund video saccade .881 -> .872 and GazeCom saccade .821 ->
// .814; those cells are floored offline only.
TEST(EvalEventsCli, OnlineHeldOutUneyeSaccadeStaysAboveItsFloor) {
    if (!have_data()) GTEST_SKIP() << "no shared data at " << kData << " or no fovea binary";
    const auto j = run_cv_json({"--mode", "online"}, "cv_online");
    ASSERT_FALSE(j.is_discarded());
    const auto& k = j["datasets"]["uneye"]["held_out"]["kappa"]["all"]["saccade"]["all"];
    ASSERT_TRUE(k.is_number());
    EXPECT_GE(k.get<double>(), 0.517 - 0.03);
}
