// Kappa, sample F1, event F1 (IoU >= 0.5 matching), the vocabulary folding and the coders'
// agreement, on hand-made label sequences.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "fovea/eval/scoring.hpp"

namespace fovea::eval {
namespace {

using gaze::Event;
constexpr Event F = Event::kFixation, S = Event::kSaccade, P = Event::kPso, U = Event::kUnknown,
                R = Event::kPursuit, B = Event::kBlink;

TEST(Agreement, KappaAndF1MatchHandComputedExample) {
    Agreement a;
    // 20 both, 5 only a, 10 only b, 65 neither: po = .85, pe = .25*.30 + .75*.70 = .6
    for (int i = 0; i < 20; ++i) a.add(true, true);
    for (int i = 0; i < 5; ++i) a.add(true, false);
    for (int i = 0; i < 10; ++i) a.add(false, true);
    for (int i = 0; i < 65; ++i) a.add(false, false);
    EXPECT_NEAR(a.kappa(), (0.85 - 0.6) / 0.4, 1e-12);
    EXPECT_NEAR(a.f1(), 40.0 / 55.0, 1e-12);
    EXPECT_TRUE(std::isnan(Agreement{}.kappa()));
    EXPECT_TRUE(std::isnan(Agreement{}.f1()));
}

TEST(EventF1, HitNeedsIntersectionOverUnionOfAtLeastHalf) {
    // Labelled saccade [2, 6); detected [4, 8): IoU 2/6 < .5, a miss. Detected [3, 7): 3/5, a hit.
    const std::vector<Event> lab = {F, F, S, S, S, S, F, F, F, F};
    EventCounts miss, hit, exact;
    count_events(std::vector<Event>{F, F, F, F, S, S, S, S, F, F}, lab, S, miss);
    count_events(std::vector<Event>{F, F, F, S, S, S, S, F, F, F}, lab, S, hit);
    EXPECT_EQ(miss.hits, 0);
    EXPECT_EQ(hit.hits, 1);
    EXPECT_EQ(hit.detected, 1);
    EXPECT_EQ(hit.labelled, 1);
    // Exactly one half counts: [2, 6) against [2, 4) + ... IoU 2/4.
    count_events(std::vector<Event>{F, F, S, S, F, F, F, F, F, F}, lab, S, exact);
    EXPECT_EQ(exact.hits, 1);
    EXPECT_NEAR(hit.f1(), 1.0, 1e-12);
}

TEST(EventF1, AFragmentedEventCountsEveryFragment) {
    // Saccade-like spikes split one long fixation in three: IoU .4, .15, .35, no hit.
    const std::vector<Event> lab(20, F);
    std::vector<Event> det(20, F);
    det[8] = det[12] = S;
    EventCounts c;
    count_events(det, lab, F, c);
    EXPECT_EQ(c.detected, 3);
    EXPECT_EQ(c.labelled, 1);
    EXPECT_EQ(c.hits, 0);
    std::vector<Event> det2(20, F);
    det2[15] = S;
    EventCounts c2;
    count_events(det2, lab, F, c2);
    EXPECT_EQ(c2.hits, 1);  // [0,15) IoU .75 matches, [16,20) does not
    EXPECT_NEAR(c2.f1(), 2.0 / 3.0, 1e-12);
}

TEST(FoldToScheme, EventsOutsideTheCodersVocabularyFoldOntoTheirs) {
    Dataset d;
    d.scheme = {F, S};
    const auto out = fold_to_scheme(std::vector<Event>{F, S, P, R, B, U}, d);
    EXPECT_EQ(out, (std::vector<Event>{F, S, S, F, U, U}));
    d.scheme = {F, S, P, R, B};
    EXPECT_EQ(fold_to_scheme(std::vector<Event>{P, R, B}, d), (std::vector<Event>{P, R, B}));
    d.scheme = {F, S};
    d.pso_without_label = F;  // EyeLink's parser: the wobble starts the fixation
    EXPECT_EQ(fold_to_scheme(std::vector<Event>{S, P, F}, d), (std::vector<Event>{S, F, F}));
    d.scheme = {F};
    EXPECT_EQ(coder_labels(std::vector<Event>{F, S, P}, d), (std::vector<Event>{F, U, U}));
}

TEST(Score, PoolsRecordingsPerStimulusAndStacksCoders) {
    Dataset d;
    d.scheme = {F, S};
    for (int k = 0; k < 2; ++k) {
        Recording r;
        r.name = "r" + std::to_string(k);
        r.stimulus = "img";
        r.samples.resize(10);
        r.coders["A"] = {F, F, F, S, S, F, F, F, F, F};
        r.coders["B"] = {F, F, F, F, S, S, F, F, F, F};
        d.recordings.push_back(r);
    }
    const std::vector<Event> det = {F, F, F, S, S, F, F, F, F, F};
    const DatasetScore s = score(d, {det, det});
    EXPECT_EQ(s.samples, 20u);
    const auto& sac = s.cells.at("img").at("saccade");
    EXPECT_NEAR(sac.at("A").kappa(), 1.0, 1e-12);
    EXPECT_NEAR(sac.at("A").f1_event(), 1.0, 1e-12);
    EXPECT_EQ(sac.at(kAllCoders).samples.both, 6);    // 2 x (2 with A + 1 with B)
    EXPECT_NEAR(sac.at("B").f1_event(), 0.0, 1e-12);  // IoU 1/3
    const CoderTable humans = coder_agreement(d);
    EXPECT_EQ(humans.at("img").at("saccade").kappa.pairs, 1);
    EXPECT_NEAR(humans.at("img").at("saccade").kappa.mean, sac.at("B").kappa(), 1e-12);
}

}  // namespace
}  // namespace fovea::eval
