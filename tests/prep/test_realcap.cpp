// Data preparation against hand labels of shared real captures
// (tests/data/real_labels/README.md says how the labels were made).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "fray/prep/actions.h"
#include "fray/prep/annotations.h"
#include "fray/prep/contacts.h"
#include "fray/prep/learning.h"
#include "fray/prep/warnings.h"
#include "fray/prep/segmentation.h"
#include "realcap_fixture.h"

using namespace fray;
using namespace fray::prep;
using fray::test::LabelledAction;

namespace {

const char* const kFallTake = "lafan1/fallAndGetUp3_subject1.bvh";

int tolerance(double fps) { return static_cast<int>(std::lround(0.1 * fps)); }

SegmentationResult segmentTake(const test::RealTake& t, const SegmentationParams& params = {}) {
    return segment(t.signals, heuristicContacts(t.signals), params);
}

// Boundary F1 over every labelled take, segmented with `params` (0 when a take is missing).
double score(const SegmentationParams& params) {
    BoundaryScore total;
    for (const auto& [take, labels] : test::readActionLabels("actions.csv")) {
        const auto* t = test::realTake(take);
        if (!t) return 0.0;
        const auto truth = test::trueCuts(labels, t->signals.frameCount, t->signals.fps);
        total += scoreBoundaries(segmentTake(*t, params).cuts, truth, tolerance(t->signals.fps));
    }
    return total.f1();
}

bool isAttack(const std::string& w) { return w == "punch" || w == "kick"; }

}  // namespace

// Boundary F1 within 0.1 s on the fully labelled karate takes.
TEST(RealCaptures, SegmentationBoundaryF1) {
    if (!test::requireSharedMocap()) return;
    BoundaryScore total;
    for (const auto& [take, labels] : test::readActionLabels("actions.csv")) {
        const auto* t = test::realTake(take);
        ASSERT_TRUE(t);
        const auto r = segmentTake(*t);
        const auto truth = test::trueCuts(labels, t->signals.frameCount, t->signals.fps);
        const auto s = scoreBoundaries(r.cuts, truth, tolerance(t->signals.fps));
        std::printf("[ real ] %-34s P %.3f R %.3f F1 %.3f (cuts %d, true %d)\n", take.c_str(), s.precision(),
                    s.recall(), s.f1(), s.predicted, s.actual);
        std::printf("         cuts:");
        for (int c : r.cuts) std::printf(" %d", c);
        std::printf("\n         true:");
        for (int c : truth) std::printf(" %d", c);
        std::printf("\n");
        total += s;
    }
    std::printf("[ real ] all labelled takes: P %.3f R %.3f F1 %.3f\n", total.precision(), total.recall(), total.f1());
    // The target is 0.85; we reach 0.867 (docs/DATA_PREP.md).
    EXPECT_GE(total.f1(), 0.86);
}

// The onset cap (a basin cut lands where the profile has risen a small share
// of the threshold, not a share of the next peak) must help on the labelled
// takes: real attacks peak at tens of times the threshold.
TEST(RealCaptures, OnsetCapHelps) {
    if (!test::requireSharedMocap()) return;
    const double ours = score({});
    SegmentationParams noCap;
    noCap.onsetCapFraction = 1e9;
    std::printf("[ real ] F1 %.3f; without the onset cap %.3f\n", ours, score(noCap));
    EXPECT_LT(score(noCap), ours - 0.05);
}

// Idles start where no effector moves faster than the take's own jitter at
// rest (SegmentationParams::stillNoiseFactor): it must help on the labelled
// takes, where the profile of a performer settling reaches the rest level late.
TEST(RealCaptures, IdleStartFromStillEffectorsHelps) {
    if (!test::requireSharedMocap()) return;
    SegmentationParams off;
    off.stillNoiseFactor = 0.0;
    const double ours = score({}), without = score(off);
    std::printf("[ real ] F1 %.3f; idles after the recovery beat only %.3f\n", ours, without);
    EXPECT_GT(ours, without + 0.04);
}

// Three refinements for a real performer's jitter must each help on the
// labelled takes: a basin needs an effector moving faster than movingFactor x
// the take's still level (a sway of the trunk or a hand settling inside a rest
// is no action), its cut must come before that movement reaches pauseFraction
// of its top speed (no mid-stroke cuts in a slow movement), and quiet
// double-support phases shorter than half the smoothing window (the threshold
// crossing flickering inside a block) give no cut.
TEST(RealCaptures, SwaysAndSupportFlickersAreNoCuts) {
    if (!test::requireSharedMocap()) return;
    SegmentationParams everyBasin;
    everyBasin.movingFactor = 0.0;
    SegmentationParams everyPhase;
    everyPhase.minPhaseSeconds = 0.0;
    SegmentationParams midStroke;
    midStroke.pauseFraction = 1e9;
    const double ours = score({}), basins = score(everyBasin), phases = score(everyPhase), strokes = score(midStroke);
    std::printf("[ real ] F1 %.3f; every basin split %.3f; every quiet phase cut %.3f; mid-stroke basin cuts %.3f\n",
                ours, basins, phases, strokes);
    EXPECT_GT(ours, basins + 0.05);
    EXPECT_GT(ours, phases + 0.01);
    EXPECT_GT(ours, strokes + 0.01);
}

// A fall and its get-up are one action each, or one together: at most one
// cut inside an episode (0.25 s from its ends).
TEST(RealCaptures, FallsAreNeverSlivers) {
    if (!test::requireSharedMocap()) return;
    const auto labels = test::readActionLabels("falls.csv").at(kFallTake);
    const auto* t = test::realTake(kFallTake);
    ASSERT_TRUE(t);
    const auto r = segmentTake(*t);
    const int margin = static_cast<int>(std::lround(0.25 * t->signals.fps));
    int episodes = 0, whole = 0, edges = 0, edgesFound = 0;
    for (std::size_t i = 0; i + 1 < labels.size(); i += 2) {
        const int first = labels[i].first, last = labels[i + 1].last;
        int inside = 0;
        for (int c : r.cuts) inside += c > first + margin && c < last + 1 - margin ? 1 : 0;
        ++episodes;
        whole += inside <= 1 ? 1 : 0;
        for (int edge : {first, last + 1}) {
            ++edges;
            for (int c : r.cuts) {
                if (std::abs(c - edge) <= margin) {
                    ++edgesFound;
                    break;
                }
            }
        }
        if (inside > 1) std::printf("[ real ] fall %d-%d: %d cuts inside\n", first, last, inside);
    }
    std::printf("[ real ] falls: %d of %d episodes are one or two actions; %d of %d episode ends have a cut "
                "within 0.25 s; %zu cuts in the take\n",
                whole, episodes, edgesFound, edges, r.cuts.size());
    EXPECT_EQ(whole, episodes);
}

// Attack proposals on the labelled actions (and the rests between them) of the
// karate takes, and on the automatic actions of the falls take (which has no
// attack): a proposal is right when the action is a labelled attack of that kind.
TEST(RealCaptures, AttackProposalsPrecisionRecall) {
    if (!test::requireSharedMocap()) return;
    int proposed = 0, right = 0, attacks = 0, found = 0;
    for (const auto& [take, labels] : test::readActionLabels("actions.csv")) {
        const auto* t = test::realTake(take);
        ASSERT_TRUE(t);
        std::vector<LabelledAction> spans;
        int at = 0;
        for (const auto& l : labels) {
            if (l.first > at) spans.push_back({at, l.first - 1, "idle"});
            spans.push_back(l);
            at = l.last + 1;
        }
        if (at < t->signals.frameCount) spans.push_back({at, t->signals.frameCount - 1, "idle"});
        for (const auto& s : spans) {
            const Proposal p = proposeAnnotations(t->motion, t->joints, t->signals, s.first, s.last);
            bool hit = false;
            for (const auto& w : p.annotations) {
                if (!isAttack(w)) continue;
                ++proposed;
                if (w == s.label) right += 1, hit = true;
                else std::printf("[ real ] %s %d-%d (%s): proposed %s\n", take.c_str(), s.first, s.last, s.label.c_str(), w.c_str());
            }
            if (isAttack(s.label)) {
                ++attacks;
                found += hit ? 1 : 0;
                if (!hit) std::printf("[ real ] %s %d-%d (%s): no proposal\n", take.c_str(), s.first, s.last, s.label.c_str());
            }
        }
    }
    const auto* t = test::realTake(kFallTake);
    ASSERT_TRUE(t);
    const auto r = segmentTake(*t);
    MotionActions doc = MotionActions::whole(t->signals.frameCount);
    doc = recut(doc, r.cuts);
    proposeAll(doc, t->motion, t->joints, t->signals);
    int fallsProposals = 0;
    for (const auto& a : doc.actions) {
        for (const auto& w : a.proposed) fallsProposals += isAttack(w) ? 1 : 0;
    }
    proposed += fallsProposals;
    const double precision = proposed ? double(right) / proposed : 1.0;
    const double recall = attacks ? double(found) / attacks : 1.0;
    std::printf("[ real ] attack proposals: precision %.3f (%d of %d; %d on the falls take), recall %.3f (%d of %d)\n",
                precision, right, proposed, fallsProposals, recall, found, attacks);
    // Target 0.9 each; precision reaches 0.92 (one low block reads as a punch).
    EXPECT_GE(precision, 0.9);
    EXPECT_GE(recall, 0.9);
}

// Contacts: an SVM trained on one take of the performer (11 s of labels)
// classifies another take of the same performer.
TEST(RealCaptures, ContactsFromTwentySecondsOfTheSamePerformer) {
    if (!test::requireSharedMocap()) return;
    std::ifstream in(test::realLabelsDir() / "contacts.csv");
    std::stringstream text;
    text << in.rdbuf();
    const auto rows = parseLabelsCsv(text.str(), "contacts.csv");
    ASSERT_TRUE(rows.ok()) << rows.error().message;
    auto labelsOf = [&](const std::string& motion) {
        std::vector<ContactLabel> out;
        for (const auto& r : *rows) {
            if (r.motion == motion) out.push_back(r.label);
        }
        return out;
    };
    const auto* train = test::realTake("cmu135_karate/frontkick001.bvh");
    const auto* check = test::realTake("cmu135_karate/oiduki001.bvh");
    ASSERT_TRUE(train && check);
    const auto trainLabels = expandLabels(labelsOf("frontkick001"), train->signals.frameCount);
    const auto checkLabels = expandLabels(labelsOf("oiduki001"), check->signals.frameCount);
    ASSERT_TRUE(trainLabels.ok() && checkLabels.ok());
    SvmTrainOptions options;
    options.maxSamples = 1200;  // 11 s at 120 fps: every other frame, both feet
    const auto svm = ContactSvm::train(collectSamples(train->signals, *trainLabels), options);
    ASSERT_TRUE(svm.ok()) << svm.error().message;
    auto accuracy = [&](const FootContacts& c) {
        int total = 0, same = 0;
        for (std::size_t f = 0; f < checkLabels->left.size(); ++f) {
            for (const Foot foot : {Foot::Left, Foot::Right}) {
                const int l = foot == Foot::Left ? checkLabels->left[f] : checkLabels->right[f];
                if (l < 0) continue;
                ++total;
                same += (c.foot(foot)[f] != 0) == (l > 0) ? 1 : 0;
            }
        }
        return total ? double(same) / total : 0.0;
    };
    const double svmAccuracy = accuracy(svm->classify(check->signals));
    const double heuristicAccuracy = accuracy(heuristicContacts(check->signals));
    std::printf("[ real ] contacts on oiduki001: SVM (trained on frontkick001, %.1f s) %.4f, heuristic %.4f\n",
                train->signals.frameCount / train->signals.fps, svmAccuracy, heuristicAccuracy);
    EXPECT_GE(svmAccuracy, 0.95);
}

// Learning from the user: the first 10 actions of the low-block take are
// corrected (their cuts set to the labels and each action named); the
// segmentation refit on them must score better on the rest of that take.
TEST(RealCaptures, RefitFromTenCorrectedActionsImprovesTheRest) {
    if (!test::requireSharedMocap()) return;
    const auto all = test::readActionLabels("actions.csv");
    const std::string corrected = "cmu135_karate/gedanbarai.bvh";
    const auto* t = test::realTake(corrected);
    ASSERT_TRUE(t);
    const FootContacts contacts = heuristicContacts(t->signals);
    const auto truth = test::trueCuts(all.at(corrected), t->signals.frameCount, t->signals.fps);
    ASSERT_GE(truth.size(), 11u);
    // The document after the user's corrections: the automatic cuts, with the
    // first 10 actions replaced by the true ones and named.
    MotionActions doc = recut(MotionActions::whole(t->signals.frameCount), segmentTake(*t).cuts);
    const int boundary = truth[9];  // first frame of the 11th true action
    std::vector<int> userCuts(truth.begin(), truth.begin() + 10);
    MotionActions user = recut(MotionActions::whole(t->signals.frameCount), userCuts);
    for (int a = 0; a < user.actionCount(); ++a) {
        if (user.lastFrame(a) < boundary) user.actions[static_cast<std::size_t>(a)].name = "a" + std::to_string(a);
    }
    user.cuts = mergeWithConfirmed(user, doc.cuts);
    user = recut(user, user.cuts);
    const auto examples = confirmedExamples(user, t->signals, contacts);
    ASSERT_EQ(examples.size(), 1u);
    EXPECT_EQ(examples[0].first, 0);
    EXPECT_EQ(examples[0].last, boundary - 1);
    const RefitReport refit = refitSegmentation(examples);
    std::printf("[ real ] refit on %d corrected cuts (%d parameter sets): F1 on them %.3f -> %.3f; threshold factor "
                "%.2f, basin prominence %.2f, onset cap %.2f, still noise factor %.1f, min phase %.2f s\n",
                refit.trueCuts, refit.tried, refit.before.f1(), refit.after.f1(), refit.params.thresholdFactor,
                refit.params.basinProminence, refit.params.onsetCapFraction, refit.params.stillNoiseFactor,
                refit.params.minPhaseSeconds);
    auto restScore = [&](const SegmentationParams& params) {
        std::vector<int> predicted, actual;
        for (int c : segment(t->signals, contacts, params).cuts) {
            if (c > boundary + tolerance(t->signals.fps)) predicted.push_back(c);
        }
        for (int c : truth) {
            if (c > boundary) actual.push_back(c);
        }
        return scoreBoundaries(predicted, actual, tolerance(t->signals.fps));
    };
    auto otherScore = [&](const SegmentationParams& params) {
        BoundaryScore total;
        for (const auto& [take, labels] : all) {
            if (take == corrected) continue;
            const auto* o = test::realTake(take);
            if (!o) continue;
            total += scoreBoundaries(segmentTake(*o, params).cuts,
                                     test::trueCuts(labels, o->signals.frameCount, o->signals.fps),
                                     tolerance(o->signals.fps));
        }
        return total;
    };
    const BoundaryScore restBefore = restScore({}), restAfter = restScore(refit.params);
    const BoundaryScore otherBefore = otherScore({}), otherAfter = otherScore(refit.params);
    std::printf("[ real ] rest of the take: F1 %.3f -> %.3f (%d true cuts); other takes: F1 %.3f -> %.3f\n",
                restBefore.f1(), restAfter.f1(), restAfter.actual, otherBefore.f1(), otherAfter.f1());
    EXPECT_GT(refit.after.f1(), refit.before.f1());
    EXPECT_GT(restAfter.f1(), restBefore.f1());
    // Other takes hold other moves (punches, kicks): the blocks' parameters are
    // printed for them, not asserted (they score 0.79 vs 0.94).
}

// Confirmed stretches keep the user's cuts; the automatic ones fill the rest.
TEST(Learning, MergeKeepsConfirmedCutsAndExamplesSpanConfirmedRuns) {
    MotionActions doc = recut(MotionActions::whole(100), {20, 40, 60});
    doc.actions[1].name = "jab";
    doc.actions[2].annotations = {"block"};
    EXPECT_EQ(mergeWithConfirmed(doc, {10, 30, 50, 55, 70, 90}), (std::vector<int>{10, 20, 40, 60, 70, 90}));
    MotionSignals signals;
    FootContacts contacts;
    const auto examples = confirmedExamples(doc, signals, contacts);
    ASSERT_EQ(examples.size(), 1u);
    EXPECT_EQ(examples[0].first, 20);
    EXPECT_EQ(examples[0].last, 59);
    EXPECT_EQ(examples[0].cuts, (std::vector<int>{20, 40, 60}));
    EXPECT_TRUE(confirmedExamples(MotionActions::whole(100), signals, contacts).empty());
    const RefitReport none = refitSegmentation({});
    EXPECT_EQ(none.tried, 0);
    EXPECT_EQ(none.params.thresholdFactor, SegmentationParams{}.thresholdFactor);
}

TEST(Warnings, ReactionsUnknownAnnotationsAndProposalsOnly) {
    Project p = makeProject("w");
    EXPECT_TRUE(projectWarnings(p).empty());
    ProjectMotion m;
    m.id = "jabs";
    m.actions = recut(MotionActions::whole(100), {50});
    m.actions.actions[0].proposed = {"punch"};
    m.actions.actions[1].proposed = {"falling"};
    p.motions.push_back(m);
    auto codes = [](const std::vector<PrepWarning>& ws) {
        std::vector<std::string> out;
        for (const auto& w : ws) out.push_back(w.code);
        return out;
    };
    auto w = projectWarnings(p);
    EXPECT_EQ(codes(w), (std::vector<std::string>{"no-reactions", "proposals-only"}));
    EXPECT_NE(w[0].message.find("falling?/pushed? proposal"), std::string::npos) << w[0].message;
    EXPECT_NE(w[1].message.find("punch? x1"), std::string::npos) << w[1].message;
    p.motions[0].actions.actions[0].annotations = {"punch"};
    p.motions[0].actions.actions[0].proposed.clear();
    p.combos.set({"@block", "@punch", 1.0});
    w = projectWarnings(p, {{"dodge", "duel.json: /a/actions"}});
    EXPECT_EQ(codes(w), (std::vector<std::string>{"no-reactions", "unknown-annotation", "unknown-annotation"}));
    EXPECT_NE(w[1].message.find("\"dodge\" is used by duel.json: /a/actions"), std::string::npos) << w[1].message;
    EXPECT_NE(w[2].message.find("\"block\" is used by combination record (@block, @punch)"), std::string::npos)
        << w[2].message;
    p.motions[0].actions.actions[1].annotations = {"falling"};
    p.motions[0].actions.actions.push_back({});
    p.motions[0].actions.cuts.push_back(80);
    p.motions[0].actions.actions[2].annotations = {"block"};
    EXPECT_EQ(codes(projectWarnings(p, {{"dodge", "duel.json"}})), (std::vector<std::string>{"unknown-annotation"}));
}
