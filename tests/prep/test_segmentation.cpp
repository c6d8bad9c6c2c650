// Segmentation against the demo actor's ground truth (SPEC 1.2).
#include <gtest/gtest.h>

#include <cstdio>

#include "fray/prep/contacts.h"
#include "fray/prep/segmentation.h"
#include "prep_fixture.h"

using namespace fray::prep;

namespace {

std::vector<int> truthCuts(const fray::demo::GroundTruth& truth) {
    std::vector<int> cuts;
    for (std::size_t i = 1; i < truth.actions.size(); ++i) cuts.push_back(truth.actions[i].firstFrame);
    return cuts;
}

BoundaryScore scoreAll(const SegmentationParams& params, bool print) {
    BoundaryScore total;
    for (const auto& [name, t] : fray::test::demoTakes()) {
        const auto r = segment(t.signals, t.truthContacts, params);
        const auto s = scoreBoundaries(r.cuts, truthCuts(t.take.truth), 6);
        if (print) {
            std::printf("%-22s P %.3f R %.3f F1 %.3f (cuts %d, true %d)\n", name.c_str(), s.precision(), s.recall(),
                        s.f1(), s.predicted, s.actual);
        }
        total += s;
    }
    if (print) std::printf("all demo takes: P %.3f R %.3f F1 %.3f\n", total.precision(), total.recall(), total.f1());
    return total;
}

}  // namespace

// The target: boundary F1 >= 0.9 (+-6 frames at 60 fps) on the demo
// truth.
TEST(Segmentation, DemoBoundaryF1WithTrueContacts) {
    const BoundaryScore s = scoreAll({}, true);
    EXPECT_GE(s.f1(), 0.90);
    EXPECT_GE(s.precision(), 0.90);
    EXPECT_GE(s.recall(), 0.88);
}

// Each refinement over the thesis' centre-of-double-support rule must earn
// its place: switching it off must score worse.
TEST(Segmentation, RefinementsBeatThePlainThesisRule) {
    const double ours = scoreAll({}, false).f1();
    struct Without {
        const char* refinement;
        void (*off)(SegmentationParams&);
        double margin;  // how much worse the segmentation must be without it
    };
    const Without refinements[] = {
        {"quietest frame, rests and idles (the thesis' centre rule instead)",
         [](SegmentationParams& p) {
             p.placement = SegmentationParams::Placement::Centre;
             p.restFraction = 0.0;
             p.idleSeconds = 1e9;
         },
         0.05},
        {"recurrence filter", [](SegmentationParams& p) { p.recurrenceDistance = 0.0; }, 0.0},
        {"flight-phase cuts", [](SegmentationParams& p) { p.cutFlightPhases = false; }, 0.0},
        {"basin cuts", [](SegmentationParams& p) { p.basinProminence = 0.0; }, 0.02},
        {"no basin cut at an attack's apex", [](SegmentationParams& p) { p.attackApexSeconds = 0.0; }, 0.0},
        {"no basin cuts on the ground", [](SegmentationParams& p) { p.groundedFraction = 0.0; }, 0.0},
        {"recovery beat before an idle", [](SegmentationParams& p) { p.recoverySeconds = 0.0; }, 0.0},
    };
    for (const Without& w : refinements) {
        SegmentationParams params;
        w.off(params);
        EXPECT_LT(scoreAll(params, false).f1(), ours - w.margin) << "without: " << w.refinement;
    }
}

TEST(Segmentation, NeverCutsInsideHighAccelerationOrTooClose) {
    for (const auto& [name, t] : fray::test::demoTakes()) {
        SegmentationParams params;
        const auto r = segment(t.signals, t.truthContacts, params);
        ASSERT_EQ(r.highAccel.size(), t.signals.acceleration.size());
        const int minAction = static_cast<int>(std::lround(params.minActionSeconds * t.signals.fps));
        int prev = 0;
        for (int c : r.cuts) {
            EXPECT_GE(c - prev, minAction) << name << " cut " << c;
            prev = c;
            // The cut lands at most onsetDelay after a quiet frame.
            const int quietFrame = c - static_cast<int>(std::lround(params.onsetDelaySeconds * t.signals.fps));
            EXPECT_TRUE(!r.highAccel[static_cast<std::size_t>(c)] || !r.highAccel[static_cast<std::size_t>(quietFrame)])
                << name << " cut " << c;
        }
        EXPECT_GE(t.signals.frameCount - prev, minAction) << name;
    }
}

TEST(Segmentation, DeterministicAndThresholdOverride) {
    const auto& t = fray::test::demoTakes().at("shadowbox_energetic");
    const auto a = segment(t.signals, t.truthContacts);
    const auto b = segment(t.signals, t.truthContacts);
    EXPECT_EQ(a.cuts, b.cuts);
    SegmentationParams high;
    high.highAccelThreshold = a.threshold * 100.0;  // nothing is an attack any more
    const auto c = segment(t.signals, t.truthContacts, high);
    EXPECT_DOUBLE_EQ(c.threshold, a.threshold * 100.0);
    EXPECT_EQ(std::count(c.highAccel.begin(), c.highAccel.end(), 1), 0);
}

TEST(Segmentation, ShortOrStillMotionGivesNoCuts) {
    MotionSignals s;
    s.fps = 60;
    s.frameCount = 2;
    s.acceleration = {0, 0};
    FootContacts c{{1, 1}, {1, 1}};
    EXPECT_TRUE(segment(s, c).cuts.empty());
    s.frameCount = 600;
    s.acceleration.assign(600, 0.0f);
    c.left.assign(600, 1);
    c.right.assign(600, 1);
    EXPECT_TRUE(segment(s, c).cuts.empty());  // one long idle, nothing to cut
}

TEST(Segmentation, BoundaryScoreMatchesOneToOne) {
    const auto s = scoreBoundaries({10, 12, 50}, {11, 40}, 6);
    EXPECT_EQ(s.truePositives, 1);
    EXPECT_EQ(s.predicted, 3);
    EXPECT_EQ(s.actual, 2);
    EXPECT_NEAR(s.f1(), 2.0 / 5.0, 1e-12);
}

// The pipeline as a user runs it: contacts from the heuristic (no labels) and
// from the SVM trained on 20 s of labels, then segmentation.
TEST(Segmentation, DemoBoundaryF1WithComputedContacts) {
    const auto& takes = fray::test::demoTakes();
    const ContactSvm& svm = fray::test::demoSvm();  // 4 x 5 s of labels
    BoundaryScore heuristic, learned;
    for (const auto& [name, t] : takes) {
        const auto truth = truthCuts(t.take.truth);
        heuristic += scoreBoundaries(segment(t.signals, heuristicContacts(t.signals)).cuts, truth, 6);
        learned += scoreBoundaries(segment(t.signals, svm.classify(t.signals)).cuts, truth, 6);
    }
    std::printf("heuristic contacts: P %.3f R %.3f F1 %.3f\nsvm contacts:       P %.3f R %.3f F1 %.3f\n",
                heuristic.precision(), heuristic.recall(), heuristic.f1(), learned.precision(), learned.recall(),
                learned.f1());
    EXPECT_GE(learned.f1(), 0.90);
    EXPECT_GE(heuristic.f1(), 0.88);
}

