// DetectorParams set by name (`fovea eval-events --detector KEY=VALUE`): every field reachable,
// bad assignments rejected with the key named and nothing changed.
#include <gtest/gtest.h>

#include "fovea/eval/detector_params.hpp"

namespace {

using fovea::eval::detector_param_names;
using fovea::eval::set_detector_param;
using fovea::gaze::DetectorParams;

TEST(DetectorParams, EveryFieldHasAName) {
    // All fields are doubles but one int, which pads to a double's slot: a field added to the
    // struct without a name here changes the size and fails this.
    EXPECT_EQ(sizeof(DetectorParams), detector_param_names().size() * sizeof(double));
}

TEST(DetectorParams, AnAssignmentSetsThatFieldOnly) {
    DetectorParams p;
    ASSERT_TRUE(set_detector_param(p, "min_peak_dps=20"));
    ASSERT_TRUE(set_detector_param(p, "min_saccade_s=6e-3"));
    ASSERT_TRUE(set_detector_param(p, "onset_extra_samples=2"));
    EXPECT_EQ(p.min_peak_dps, 20.0);
    EXPECT_EQ(p.min_saccade_s, 0.006);
    EXPECT_EQ(p.onset_extra_samples, 2);
    EXPECT_EQ(p.pursuit_dps, DetectorParams{}.pursuit_dps);
    for (const std::string& name : detector_param_names()) {
        DetectorParams q;
        EXPECT_TRUE(set_detector_param(q, name + "=3")) << name;
    }
}

TEST(DetectorParams, BadAssignmentsNameTheProblemAndChangeNothing) {
    DetectorParams p;
    const auto unknown = set_detector_param(p, "min_peak=20");
    ASSERT_FALSE(unknown);
    EXPECT_NE(unknown.error().message.find("min_peak"), std::string::npos);
    EXPECT_NE(unknown.error().message.find("min_peak_dps"), std::string::npos);  // the list
    for (const char* bad :
         {"min_peak_dps", "min_peak_dps=", "min_peak_dps=fast", "min_peak_dps=20x",
          "min_peak_dps=nan", "min_peak_dps=inf", "onset_extra_samples=2.5", "=3"}) {
        EXPECT_FALSE(set_detector_param(p, bad)) << bad;
    }
    EXPECT_EQ(p.min_peak_dps, DetectorParams{}.min_peak_dps);
    EXPECT_EQ(p.onset_extra_samples, DetectorParams{}.onset_extra_samples);
}

}  // namespace
