// Transitions between actions: placement, blend, foot locking (two-bone IK),
// measured as foot skate and seam smoothness on pairs the motion graph allows.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>
#include <utility>

#include "fray/core/ik.h"
#include "fray/core/kinematics.h"
#include "fray/io/import.h"
#include "fray/prep/motion_graph.h"
#include "fray/prep/transition.h"
#include "prep/graph_fixture.h"
#include "test_util.h"

using namespace fray;
using namespace fray::prep;
using fray::test::demoGraph;
using fray::test::demoGraphInput;

namespace {

struct Pair {
    int a = 0, b = 0;  // action indices
};

bool consecutive(const ActionRef& a, const ActionRef& b) {
    return a.motion == b.motion && b.firstFrame == a.lastFrame + 1;
}

// One random B in Next(A) for every A, skipping pairs that were consecutive in
// their take (those need no transition).
const std::vector<Pair>& graphPairs() {
    static const std::vector<Pair> pairs = [] {
        const auto& in = demoGraphInput();
        const MotionGraph& g = demoGraph();
        std::mt19937 rng(11);
        std::vector<Pair> out;
        for (std::size_t a = 0; a < in.actions.size(); ++a) {
            std::vector<int> choices;
            for (int b : g.next[a])
                if (!consecutive(in.actions[a], in.actions[static_cast<std::size_t>(b)])) choices.push_back(b);
            if (choices.empty()) continue;
            out.push_back({static_cast<int>(a), choices[rng() % choices.size()]});
        }
        return out;
    }();
    return pairs;
}

Result<JoinedActions> join(const Pair& p, const TransitionOptions& options = {}) {
    const auto& in = demoGraphInput();
    const ActionRef& a = in.actions[static_cast<std::size_t>(p.a)];
    const ActionRef& b = in.actions[static_cast<std::size_t>(p.b)];
    const auto ma = static_cast<std::size_t>(a.motion), mb = static_cast<std::size_t>(b.motion);
    return joinActions(*in.motions[ma], in.joints[ma], a, in.contacts[ma], *in.motions[mb], in.joints[mb], b,
                       in.contacts[mb], options);
}

// Largest |p(f+1) - 2 p(f) + p(f-1)| over joints and f in (first, last) (m/frame^2):
// a velocity jump shows up here as its size.
double maxSecondDifference(const Motion& m, int first, int last) {
    first = std::max(first, 0);
    last = std::min(last, m.frameCount() - 1);
    if (last - first < 2) return 0.0;
    const auto w = worldPositions(m, first, last);
    const auto jc = static_cast<std::size_t>(m.jointCount());
    double out = 0.0;
    for (std::size_t f = 1; f + 1 < static_cast<std::size_t>(last - first + 1); ++f)
        for (std::size_t j = 0; j < jc; ++j)
            out = std::max(out, static_cast<double>(
                                    glm::length(w[(f + 1) * jc + j] - 2.0f * w[f * jc + j] + w[(f - 1) * jc + j])));
    return out;
}

double maxSpeed(const Motion& m, int first, int last) {
    first = std::max(first, 0);
    last = std::min(last, m.frameCount() - 1);
    const auto w = worldPositions(m, first, last);
    const auto jc = static_cast<std::size_t>(m.jointCount());
    double out = 0.0;
    for (std::size_t f = 1; f < static_cast<std::size_t>(last - first + 1); ++f)
        for (std::size_t j = 0; j < jc; ++j)
            out = std::max(out, static_cast<double>(glm::length(w[f * jc + j] - w[(f - 1) * jc + j])));
    return out;
}

double pelvisHeading(const Motion& m, const StandardJoints& j, int frame) {
    std::vector<glm::vec3> p(static_cast<std::size_t>(m.jointCount()));
    worldPositions(m, frame, p);
    return headingOf(p, j);
}

double angleBetween(double a, double b) {
    return std::abs(std::remainder(a - b, 2.0 * glm::pi<double>()));
}

}  // namespace

TEST(Transition, GraphTransitionsAddNoFootSkate) {
    const auto& pairs = graphPairs();
    ASSERT_GE(pairs.size(), 300u);
    const StandardJoints& joints = demoGraphInput().joints[0];
    double worst = 0.0, worstFree = 0.0, sum = 0.0, sumFree = 0.0;
    int samples = 0, unreached = 0, worseFree = 0;
    for (const Pair& p : pairs) {
        auto locked = join(p);
        ASSERT_TRUE(locked.ok()) << locked.error().message;
        TransitionOptions off;
        off.footLocking = false;
        auto free = join(p, off);
        ASSERT_TRUE(free.ok());
        // The blend region and everything a lock touched, seam step included.
        const int first = locked->seam - 1, last = std::max(locked->lastAdjusted, free->lastAdjusted) + 1;
        const SkateStats s = footSkate(locked->motion, joints, locked->contacts, first, last);
        const SkateStats sf = footSkate(free->motion, joints, free->contacts, first, last);
        EXPECT_LE(s.maxPerFrame, 0.005) << "actions " << p.a << " -> " << p.b;
        // Outside the region the motion is A's or B's own, planted feet included.
        EXPECT_LE(footSkate(locked->motion, joints, locked->contacts, 0, locked->motion.frameCount() - 1).maxPerFrame,
                  0.005);
        worst = std::max(worst, s.maxPerFrame);
        worstFree = std::max(worstFree, sf.maxPerFrame);
        sum += s.meanPerFrame;
        sumFree += sf.meanPerFrame;
        samples += s.frames;
        unreached += locked->ikReached ? 0 : 1;
        worseFree += sf.maxPerFrame > 0.005 ? 1 : 0;
    }
    const double n = static_cast<double>(pairs.size());
    std::printf("%zu graph transitions (not consecutive in their take), %d planted-foot samples in the blend regions:\n"
                "  foot locking on:  max %.2g mm/frame, mean %.2g mm/frame, %d with an unreachable lock\n"
                "  foot locking off: max %.2f mm/frame, mean %.3f mm/frame, %d transitions over 5 mm/frame\n",
                pairs.size(), samples, 1000.0 * worst, 1000.0 * sum / n, unreached, 1000.0 * worstFree,
                1000.0 * sumFree / n, worseFree);
    EXPECT_GT(samples, 1000);
    // Without locking the feet slide: the test above could fail.
    EXPECT_GT(worstFree, 0.005);
    EXPECT_GT(worseFree, static_cast<int>(pairs.size() / 10));
    EXPECT_LT(sum, 0.25 * sumFree);
}

TEST(Transition, SeamHasNoVelocityJump) {
    const auto& in = demoGraphInput();
    int naiveJumps = 0;
    double worstExcess = -1.0, worstNaive = -1.0, worstSpeedRatio = 0.0;
    for (const Pair& p : graphPairs()) {
        const ActionRef& ra = in.actions[static_cast<std::size_t>(p.a)];
        const ActionRef& rb = in.actions[static_cast<std::size_t>(p.b)];
        const Motion& ma = *in.motions[static_cast<std::size_t>(ra.motion)];
        const Motion& mb = *in.motions[static_cast<std::size_t>(rb.motion)];
        const double source = std::max(maxSecondDifference(ma, ra.firstFrame, ra.lastFrame),
                                       maxSecondDifference(mb, rb.firstFrame, rb.lastFrame));
        const double sourceSpeed = std::max(maxSpeed(ma, ra.firstFrame, ra.lastFrame),
                                            maxSpeed(mb, rb.firstFrame, rb.lastFrame));
        auto j = join(p);
        ASSERT_TRUE(j.ok());
        const int first = j->seam - 2, last = j->lastAdjusted + 2;
        const double joined = maxSecondDifference(j->motion, first, last);
        EXPECT_LE(joined, source + 0.01) << "actions " << p.a << " -> " << p.b;
        const double speed = maxSpeed(j->motion, first, last);
        EXPECT_LE(speed, 1.25 * sourceSpeed + 0.002) << "actions " << p.a << " -> " << p.b;
        worstExcess = std::max(worstExcess, joined - source);
        worstSpeedRatio = std::max(worstSpeedRatio, speed / sourceSpeed);

        // The same pair cut and appended with only the floor placement.
        auto ta = trim(ma, ra.firstFrame, ra.lastFrame);
        auto tb = trim(mb, rb.firstFrame, rb.lastFrame);
        auto naive = concatenate(*ta, *tb, true);
        ASSERT_TRUE(naive.ok());
        const double cut = maxSecondDifference(*naive, j->seam - 2, j->seam + j->blendFrames + 2);
        worstNaive = std::max(worstNaive, cut - source);
        naiveJumps += cut > source + 0.01 ? 1 : 0;
    }
    std::printf("seam: largest second difference above the sources' %.1f mm/frame^2 (blended) vs %.1f (cut and "
                "appended, %d of %zu over 10); largest joint speed %.2f x the sources'\n",
                1000.0 * worstExcess, 1000.0 * worstNaive, naiveJumps, graphPairs().size(), worstSpeedRatio);
    EXPECT_GT(naiveJumps, static_cast<int>(graphPairs().size() / 10));  // the check can fail
}

TEST(Transition, PlacementContinuesAOnTheFloor) {
    const auto& in = demoGraphInput();
    const StandardJoints& joints = in.joints[0];
    int turned = 0;
    for (const Pair& p : graphPairs()) {
        const ActionRef& ra = in.actions[static_cast<std::size_t>(p.a)];
        const ActionRef& rb = in.actions[static_cast<std::size_t>(p.b)];
        const Motion& ma = *in.motions[static_cast<std::size_t>(ra.motion)];
        const Motion& mb = *in.motions[static_cast<std::size_t>(rb.motion)];
        auto j = join(p);
        ASSERT_TRUE(j.ok());
        const int nA = ra.lastFrame - ra.firstFrame + 1, nB = rb.lastFrame - rb.firstFrame + 1;
        ASSERT_EQ(j->motion.frameCount(), nA + nB);
        ASSERT_EQ(j->seam, nA);
        ASSERT_EQ(j->contacts.frameCount(), nA + nB);
        // A is untouched.
        for (int f = 0; f < nA; f += 7) {
            const auto r = std::as_const(j->motion).rotations(f), rs = ma.rotations(ra.firstFrame + f);
            EXPECT_TRUE(std::equal(r.begin(), r.end(), rs.begin()));
            EXPECT_EQ(
                j->contacts.left[static_cast<std::size_t>(f)],
                in.contacts[static_cast<std::size_t>(ra.motion)]->left[static_cast<std::size_t>(ra.firstFrame + f)]);
        }
        // Heading continues across the seam although the sources face anywhere.
        const double before = pelvisHeading(j->motion, joints, j->seam - 1);
        const double after = pelvisHeading(j->motion, joints, j->seam);
        EXPECT_LT(angleBetween(before, after), 0.05) << "actions " << p.a << " -> " << p.b;
        turned += angleBetween(pelvisHeading(ma, joints, ra.lastFrame), pelvisHeading(mb, joints, rb.firstFrame)) > 0.5;
        // After the window B plays as captured, only turned and moved on the floor.
        const int f = j->lastAdjusted + 1;
        if (f < nA + nB) {
            const double turn = pelvisHeading(j->motion, joints, f) - pelvisHeading(mb, joints, rb.firstFrame + f - nA);
            const int g = nA + nB - 1;
            const double turnEnd = pelvisHeading(j->motion, joints, g) - pelvisHeading(mb, joints, rb.lastFrame);
            EXPECT_LT(angleBetween(turn, turnEnd), 1e-3);
            const auto r = std::as_const(j->motion).rotations(g), rs = mb.rotations(rb.lastFrame);
            for (std::size_t k = 1; k < r.size(); ++k)
                EXPECT_LT(std::abs(std::abs(glm::dot(r[k], rs[k])) - 1.0f), 1e-5f);
        }
    }
    EXPECT_GT(turned, 20) << "the pairs should include sources facing different ways";
}

TEST(Transition, ConsecutiveActionsComeBackUnchanged) {
    const auto& in = demoGraphInput();
    double worst = 0.0;
    for (std::size_t a = 0; a + 1 < in.actions.size(); a += 5) {
        const ActionRef& ra = in.actions[a];
        const ActionRef& rb = in.actions[a + 1];
        if (!consecutive(ra, rb)) continue;
        auto j = join({static_cast<int>(a), static_cast<int>(a + 1)});
        ASSERT_TRUE(j.ok());
        const Motion& m = *in.motions[static_cast<std::size_t>(ra.motion)];
        const auto joined = worldPositions(j->motion, 0, j->motion.frameCount() - 1);
        const auto source = worldPositions(m, ra.firstFrame, rb.lastFrame);
        ASSERT_EQ(joined.size(), source.size());
        for (std::size_t i = 0; i < joined.size(); ++i)
            worst = std::max(worst, static_cast<double>(glm::length(joined[i] - source[i])));
    }
    EXPECT_LT(worst, 1e-3) << "joining an action to its own successor should change nothing";
}

TEST(Transition, RejectsMismatchedInput) {
    const auto& in = demoGraphInput();
    const Motion& m = *in.motions[0];
    const StandardJoints& j = in.joints[0];
    const FootContacts& c = *in.contacts[0];
    const ActionRef a{0, 10, 80}, b{0, 200, 260};
    auto message = [](const Result<JoinedActions>& r) { return r.ok() ? std::string("(ok)") : r.error().message; };
    EXPECT_TRUE(joinActions(m, j, a, &c, m, j, b, &c).ok());

    Motion renamed = m;
    renamed.skeleton().names[3] = "Chest";
    EXPECT_NE(message(joinActions(m, j, a, &c, renamed, j, b, &c)).find("different skeletons"), std::string::npos);
    Motion slow = m;
    slow.setFps(30.0);
    EXPECT_NE(message(joinActions(m, j, a, &c, slow, j, b, &c)).find("frame rates differ"), std::string::npos);
    EXPECT_NE(message(joinActions(m, j, {0, 80, 10}, &c, m, j, b, &c)).find("action A"), std::string::npos);
    EXPECT_NE(message(joinActions(m, j, a, &c, m, j, {0, 0, m.frameCount()}, &c)).find("action B"),
              std::string::npos);
    FootContacts shortContacts = c;
    shortContacts.left.pop_back();
    EXPECT_NE(message(joinActions(m, j, a, &shortContacts, m, j, b, &c)).find("contacts of A"), std::string::npos);
    StandardJoints noKnee = j;
    noKnee.leftKnee = -1;
    EXPECT_NE(message(joinActions(m, noKnee, a, &c, m, noKnee, b, &c)).find("hip -> knee -> ankle"),
              std::string::npos);
    EXPECT_NE(message(joinActions(m, j, a, &c, m, noKnee, b, &c)).find("standard joints"), std::string::npos);
    TransitionOptions noLock;
    noLock.footLocking = false;
    EXPECT_TRUE(joinActions(m, noKnee, a, &c, m, noKnee, b, &c, noLock).ok());
}

TEST(Transition, EstimatesContactsWhenNoneAreGiven) {
    int agree = 0, total = 0;
    for (const auto& [name, t] : test::demoTakes()) {
        const FootContacts e = estimateContacts(t.take.motion, t.joints);
        ASSERT_EQ(e.frameCount(), t.take.motion.frameCount());
        for (std::size_t f = 0; f < e.left.size(); ++f) {
            agree += (e.left[f] != 0) == (t.truthContacts.left[f] != 0);
            agree += (e.right[f] != 0) == (t.truthContacts.right[f] != 0);
            total += 2;
        }
    }
    const double share = static_cast<double>(agree) / total;
    std::printf("estimated contacts agree with the demo truth on %.1f %% of foot-frames\n", 100.0 * share);
    EXPECT_GT(share, 0.85);

    const auto& in = demoGraphInput();
    const Pair p = graphPairs()[7];
    const ActionRef& ra = in.actions[static_cast<std::size_t>(p.a)];
    const ActionRef& rb = in.actions[static_cast<std::size_t>(p.b)];
    const Motion& ma = *in.motions[static_cast<std::size_t>(ra.motion)];
    const Motion& mb = *in.motions[static_cast<std::size_t>(rb.motion)];
    auto j = joinActions(ma, in.joints[0], ra, nullptr, mb, in.joints[0], rb, nullptr);
    ASSERT_TRUE(j.ok()) << j.error().message;
    const FootContacts eb = estimateContacts(mb, in.joints[0]);
    EXPECT_EQ(j->contacts.right[static_cast<std::size_t>(j->seam + 3)],
              eb.right[static_cast<std::size_t>(rb.firstFrame + 3)]);
}

TEST(FootSkate, MeasuresPlantedFeetThatSlide) {
    const auto& t = test::demoTakes().at("walking");
    const Motion& m = t.take.motion;
    const SkateStats clean = footSkate(m, t.joints, t.truthContacts, 0, m.frameCount() - 1);
    EXPECT_GT(clean.frames, 1000);
    EXPECT_LT(clean.maxPerFrame, 1e-5);
    // Everything drifts 3 mm per frame sideways: every planted foot skates by that.
    Motion drift = m;
    for (int f = 0; f < drift.frameCount(); ++f) drift.translations(f)[0].x += 0.003f * static_cast<float>(f);
    const SkateStats s = footSkate(drift, t.joints, t.truthContacts, 0, m.frameCount() - 1);
    EXPECT_EQ(s.frames, clean.frames);
    EXPECT_NEAR(s.maxPerFrame, 0.003, 1e-4);
    EXPECT_NEAR(s.meanPerFrame, 0.003, 1e-4);
    // Vertical motion is not skate.
    Motion bob = m;
    for (int f = 0; f < bob.frameCount(); ++f) bob.translations(f)[0].y += 0.01f * static_cast<float>(f % 2);
    EXPECT_LT(footSkate(bob, t.joints, t.truthContacts, 0, m.frameCount() - 1).maxPerFrame, 1e-4);
    // Only frames in range, and only where the previous frame was planted too.
    EXPECT_EQ(footSkate(m, t.joints, t.truthContacts, 50, 50).frames, 0);
}

TEST(TwoBoneIk, ReachesTargetsInTheKneePlane) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    const glm::vec3 hip(0.0f, 1.0f, 0.0f), knee(0.02f, 0.55f, 0.08f), ankle(0.0f, 0.1f, 0.0f);
    const float l1 = glm::length(knee - hip), l2 = glm::length(ankle - knee);
    for (int i = 0; i < 200; ++i) {
        const glm::vec3 dir = glm::normalize(glm::vec3(u(rng), -1.5f + 0.5f * u(rng), u(rng)));
        const float reach =
            (std::abs(l1 - l2) + 0.05f) + (l1 + l2 - std::abs(l1 - l2) - 0.06f) * (0.5f + 0.5f * u(rng));
        const glm::vec3 target = hip + reach * dir;
        const TwoBoneSolution s = solveTwoBone(hip, knee, ankle, target);
        const glm::vec3 newKnee = hip + s.upper * (knee - hip);
        const glm::vec3 newAnkle = newKnee + s.lower * (s.upper * (ankle - knee));
        EXPECT_TRUE(s.reached);
        EXPECT_LT(glm::length(newAnkle - target), 1e-4f);
        // The knee bends in the plane of hip, target and the old knee (the pole).
        const glm::vec3 normal = glm::normalize(glm::cross(target - hip, knee - hip));
        EXPECT_LT(std::abs(glm::dot(normal, newKnee - hip)), 1e-4f);
        EXPECT_GT(glm::dot(newKnee - hip, knee - hip - glm::dot(knee - hip, dir) * dir), 0.0f);
    }
    const glm::vec3 far = hip + glm::vec3(0.0f, -3.0f, 0.0f);
    const TwoBoneSolution s = solveTwoBone(hip, knee, ankle, far);
    EXPECT_FALSE(s.reached);
    const glm::vec3 newAnkle = hip + s.upper * (knee - hip) + s.lower * (s.upper * (ankle - knee));
    EXPECT_NEAR(glm::length(newAnkle - hip), l1 + l2, 1e-3f);
    EXPECT_GT(glm::dot(glm::normalize(newAnkle - hip), glm::vec3(0, -1, 0)), 0.9999f);
}

TEST(TwoBoneIk, MovesOnlyTheLegOnAPose) {
    const auto& t = test::demoTakes().at("walking");
    const Motion& m = t.take.motion;
    const int frame = 400;
    const auto jc = static_cast<std::size_t>(m.jointCount());
    std::vector<glm::vec3> pos(jc), after(jc);
    std::vector<glm::quat> rot(jc), rotAfter(jc);
    worldTransforms(m, frame, pos, rot);
    std::vector<glm::quat> local(m.rotations(frame).begin(), m.rotations(frame).end());
    const auto ankle = static_cast<std::size_t>(t.joints.leftFoot);
    const glm::vec3 target = pos[ankle] + glm::vec3(0.05f, 0.04f, -0.03f);
    const glm::quat footRot = glm::angleAxis(0.3f, glm::vec3(1, 0, 0)) * rot[ankle];
    EXPECT_TRUE(applyTwoBoneIk(m.skeleton(), local, pos, rot, t.joints.leftHip, t.joints.leftKnee,
                               t.joints.leftFoot, target, &footRot));
    forwardKinematics(m.skeleton(), m.translations(frame), local, after, rotAfter);
    EXPECT_LT(glm::length(after[ankle] - target), 1e-4f);
    EXPECT_GT(std::abs(glm::dot(rotAfter[ankle], footRot)), 1.0f - 1e-6f);
    for (int j : {t.joints.rightFoot, t.joints.head, t.joints.leftHand, t.joints.leftHip, t.joints.pelvis})
        EXPECT_LT(glm::length(after[static_cast<std::size_t>(j)] - pos[static_cast<std::size_t>(j)]), 1e-5f);
}

// Real captures (LAFAN1) cut into 1 s windows, contacts estimated: how much
// skate the transitions add over what the captures already have.
TEST(TransitionReal, LafanWindowsWithEstimatedContacts) {
    std::vector<Motion> motions;
    for (const char* file : {"lafan1/walk4_subject1.bvh", "lafan1/multipleActions1_subject1.bvh",
                             "lafan1/pushAndFall1_subject1.bvh"}) {
        if (!test::requireSharedMocap()) return;
        auto m = loadMotion(test::sharedMocap() / file);
        ASSERT_TRUE(m.ok()) << file << ": " << m.error().message;
        motions.push_back(std::move(*m));
    }
    std::vector<const Motion*> ptrs;
    std::vector<StandardJoints> joints;
    std::vector<FootContacts> contacts;
    std::vector<ActionRef> actions;
    for (std::size_t i = 0; i < motions.size(); ++i) {
        ptrs.push_back(&motions[i]);
        joints.push_back(guessStandardJoints(motions[i].skeleton()));
        contacts.push_back(estimateContacts(motions[i], joints.back()));
        const int window = static_cast<int>(std::lround(motions[i].fps()));
        for (int f = 0; f + window <= motions[i].frameCount(); f += window)
            actions.push_back({static_cast<int>(i), f, f + window - 1});
    }
    GraphOptions o;
    o.threshold = 0.3;
    auto g = buildMotionGraph(ptrs, joints, actions, o);
    ASSERT_TRUE(g.ok()) << g.error().message;
    std::mt19937 rng(5);
    double sum[2] = {0, 0}, worst[2] = {0, 0}, worstAdded = 0, own = 0;
    int pairs = 0;
    for (int trial = 0; trial < 200; ++trial) {
        const auto a = static_cast<std::size_t>(rng() % actions.size());
        if (g->next[a].empty()) continue;
        const auto b = static_cast<std::size_t>(g->next[a][rng() % g->next[a].size()]);
        if (consecutive(actions[a], actions[b])) continue;
        ++pairs;
        const auto ma = static_cast<std::size_t>(actions[a].motion), mb = static_cast<std::size_t>(actions[b].motion);
        for (int lock = 0; lock < 2; ++lock) {
            TransitionOptions to;
            to.footLocking = lock == 1;
            auto j = joinActions(motions[ma], joints[ma], actions[a], &contacts[ma], motions[mb], joints[mb],
                                 actions[b], &contacts[mb], to);
            ASSERT_TRUE(j.ok()) << j.error().message;
            const SkateStats s = footSkate(j->motion, joints[0], j->contacts, j->seam - 1, j->lastAdjusted + 1);
            sum[lock] += s.meanPerFrame;
            worst[lock] = std::max(worst[lock], s.maxPerFrame);
            if (lock == 1) {
                const SkateStats bs = footSkate(motions[mb], joints[mb], contacts[mb], actions[b].firstFrame,
                                                actions[b].firstFrame + j->lastAdjusted + 1 - j->seam);
                own = std::max(own, bs.maxPerFrame);
                worstAdded = std::max(worstAdded, s.maxPerFrame - bs.maxPerFrame);
            }
        }
    }
    ASSERT_GT(pairs, 40);
    std::printf("LAFAN1 1 s windows (%zu actions, %d nodes, largest SCC %.1f %%), %d transitions, estimated contacts:\n"
                "  locking on:  mean %.2f mm/frame, max %.1f (B's own capture over the same frames: max %.1f; "
                "largest excess over it %.1f)\n  locking off: mean %.2f mm/frame, max %.1f\n",
                actions.size(), g->stats.nodes, 100.0 * g->stats.sccShare, pairs, 1000.0 * sum[1] / pairs,
                1000.0 * worst[1], 1000.0 * own, 1000.0 * worstAdded, 1000.0 * sum[0] / pairs, 1000.0 * worst[0]);
    EXPECT_LT(sum[1], 0.5 * sum[0]);
    EXPECT_LT(worstAdded, 0.01);
}
