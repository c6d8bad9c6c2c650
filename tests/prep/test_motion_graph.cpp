// Action-level motion graph (SPEC 1.5): pose distance properties, clustering,
// Next(), strongly connected components, input checks, cancellation, and a
// graph of real captures cut naively into 1 s windows.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <numeric>
#include <queue>
#include <set>

#include "fray/core/kinematics.h"
#include "fray/io/import.h"
#include "fray/prep/motion_graph.h"
#include "prep/graph_fixture.h"
#include "test_util.h"

using namespace fray;
using namespace fray::prep;
using fray::test::demoGraph;
using fray::test::demoGraphInput;

namespace {

const test::DemoTake& shadowbox() { return fray::test::demoTakes().at("shadowbox_energetic"); }

// The whole motion turned about Y and moved on the floor.
Motion movedOnFloor(const Motion& m, float yaw, glm::vec3 shift) {
    Motion out = m;
    const glm::quat turn = glm::angleAxis(yaw, glm::vec3(0, 1, 0));
    for (int f = 0; f < out.frameCount(); ++f) {
        out.translations(f)[0] = turn * out.translations(f)[0] + shift;
        out.rotations(f)[0] = turn * out.rotations(f)[0];
    }
    return out;
}

GraphWeights only(double GraphWeights::*term) {
    GraphWeights w{0, 0, 0, 0, 0, 0};
    w.*term = 1.0;
    return w;
}

}  // namespace

TEST(PoseDistance, ZeroForTheSamePoseAndSymmetric) {
    const auto& t = shadowbox();
    const GraphWeights w = GraphWeights::fighting();
    for (int f : {10, 500, 2000, 4000}) {
        const PoseFeature a = poseFeature(t.take.motion, t.joints, f);
        const PoseFeature b = poseFeature(t.take.motion, t.joints, f + 37);
        EXPECT_NEAR(poseDistance(a, a, w), 0.0, 1e-6);
        EXPECT_GT(poseDistance(a, b, w), 0.01) << "frame " << f;
        EXPECT_DOUBLE_EQ(poseDistance(a, b, w), poseDistance(b, a, w));
    }
}

TEST(PoseDistance, InvariantToFloorTranslationAndTurn) {
    const auto& t = shadowbox();
    const Motion moved = movedOnFloor(t.take.motion, 2.3f, glm::vec3(4.0f, 0.0f, -7.5f));
    const GraphWeights w = GraphWeights::fighting();
    for (int f : {0, 333, 1234, 5000, t.take.motion.frameCount() - 1}) {
        const double d = poseDistance(poseFeature(t.take.motion, t.joints, f), poseFeature(moved, t.joints, f), w);
        EXPECT_LT(d, 2e-4) << "frame " << f;
    }
    // Lifting the whole body is a different pose (pelvis height).
    Motion lifted = movedOnFloor(t.take.motion, 0.0f, glm::vec3(0.0f, 0.2f, 0.0f));
    EXPECT_GT(poseDistance(poseFeature(t.take.motion, t.joints, 100), poseFeature(lifted, t.joints, 100),
                           only(&GraphWeights::height)),
              0.1);
}

TEST(PoseDistance, UsesRotationAnglesSoEulerWrapDoesNotMatter) {
    const auto& t = shadowbox();
    const PoseFeature base = poseFeature(t.take.motion, t.joints, 100);
    // +179 and -179 degrees about Y are 2 degrees apart, whatever Euler angles say.
    PoseFeature a = base, b = base;
    const std::size_t j = 3;
    const float deg = glm::pi<float>() / 180.0f;
    a.rotations[j] = a.rotations[j] * glm::angleAxis(179.0f * deg, glm::vec3(0, 1, 0));
    b.rotations[j] = b.rotations[j] * glm::angleAxis(-179.0f * deg, glm::vec3(0, 1, 0));
    const double n = static_cast<double>(base.rotations.size());
    EXPECT_NEAR(poseDistance(a, b, only(&GraphWeights::upper)), 2.0 * static_cast<double>(deg) / n, 1e-4);
    // q and -q are the same rotation.
    PoseFeature c = base;
    for (auto& q : c.rotations) q = -q;
    EXPECT_NEAR(poseDistance(base, c, GraphWeights::fighting()), 0.0, 1e-6);
}

TEST(PoseDistance, DerivativesDoNotDependOnTheFrameRate) {
    const auto& t = shadowbox();
    auto fast = resample(t.take.motion, 120.0);
    ASSERT_TRUE(fast.ok()) << fast.error().message;
    double worst = 0.0, typical = 0.0;
    for (int f = 200; f < 6000; f += 450) {
        const PoseFeature a = poseFeature(t.take.motion, t.joints, f);
        worst = std::max(worst, poseDistance(a, poseFeature(*fast, t.joints, 2 * f), GraphWeights::fighting()));
        typical += poseDistance(a, poseFeature(t.take.motion, t.joints, f + 6), GraphWeights::fighting());
    }
    typical /= 13.0;
    std::printf("60 vs 120 fps: largest D %.4f; D to 0.1 s later %.4f\n", worst, typical);
    EXPECT_LT(worst, 0.2 * typical);
}

TEST(PoseDistance, Presets) {
    EXPECT_EQ(GraphWeights::preset("fighting"), GraphWeights::fighting());
    EXPECT_EQ(GraphWeights::preset("locomotion"), GraphWeights::locomotion());
    EXPECT_FALSE(GraphWeights::preset("dance").has_value());
    const GraphWeights f = GraphWeights::fighting(), l = GraphWeights::locomotion();
    EXPECT_EQ(f.upper, f.leg);
    EXPECT_EQ(f.upperVel, f.heightVel);
    EXPECT_LT(l.upper, 0.5 * l.leg);
    EXPECT_LT(l.upperVel, 0.5 * l.legVel);
}

TEST(MotionGraph, DemoLibraryIsMostlyOneStronglyConnectedComponent) {
    const auto& in = demoGraphInput();
    const MotionGraph& g = demoGraph();
    const GraphStats& s = g.stats;
    std::printf("demo graph: %zu actions, %d nodes, mean out-degree %.1f, max %d, largest SCC %d actions (%.1f %%), "
                "%d dead ends, largest pose-centre distance %.3f, %d rounds\n",
                in.actions.size(), s.nodes, s.meanOutDegree, s.maxOutDegree, s.largestSccActions, 100.0 * s.sccShare,
                s.deadEnds, g.maxClusterDistance, g.kmeansRounds);
    EXPECT_EQ(s.edges, static_cast<int>(in.actions.size()));
    EXPECT_GE(s.nodes, 15) << "a graph of a handful of nodes would connect anything to anything";
    EXPECT_GE(s.sccShare, 0.90);
    EXPECT_LT(g.maxClusterDistance, GraphOptions{}.threshold);
    EXPECT_EQ(g.nodeCount, s.nodes);
    EXPECT_EQ(static_cast<int>(g.centres.size()), s.nodes);
    EXPECT_DOUBLE_EQ(s.meanOutDegree, static_cast<double>(s.edges) / s.nodes);
    EXPECT_EQ(std::accumulate(g.inLargestScc.begin(), g.inLargestScc.end(), 0), s.largestSccActions);
    EXPECT_DOUBLE_EQ(s.sccShare, static_cast<double>(s.largestSccActions) / s.edges);
}

// The threshold from the data (docs/MOTION_GRAPH.md): 1.5 x the 90th
// percentile of the transition gaps. The demo's poses are dense, so its
// graph keeps the default; an end's own continuation is never its gap.
TEST(MotionGraph, ThresholdFromTheDataKeepsTheDemoDefault) {
    const std::vector<double> gaps = {0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0};
    EXPECT_DOUBLE_EQ(thresholdFromGaps(gaps), 1.5 * 0.9);  // the 90th percentile of 10: the 9th, with the margin
    EXPECT_DOUBLE_EQ(thresholdFromGaps(std::vector<double>(gaps.begin(), gaps.begin() + 2)), 1.5 * 0.2);
    EXPECT_DOUBLE_EQ(thresholdFromGaps(std::vector<double>{}), 0.0);
    const auto& in = demoGraphInput();
    auto demo = transitionGaps(in.motions, in.joints, in.actions, GraphWeights::fighting());
    ASSERT_TRUE(demo) << demo.error().message;
    ASSERT_EQ(demo->size(), in.actions.size());
    EXPECT_TRUE(std::is_sorted(demo->begin(), demo->end()));
    std::printf("demo transition gaps: median %.3f, 90th percentile %.3f -> threshold from the data %.3f\n",
                (*demo)[demo->size() / 2], (*demo)[demo->size() * 9 / 10], thresholdFromGaps(*demo));
    EXPECT_LT(thresholdFromGaps(*demo), GraphOptions{}.threshold);
    // Capped: an even stride over the ends, about the same statistic.
    auto sampled = transitionGaps(in.motions, in.joints, in.actions, GraphWeights::fighting(), 100);
    ASSERT_TRUE(sampled);
    const std::size_t step = (in.actions.size() + 99) / 100;
    EXPECT_EQ(sampled->size(), (in.actions.size() + step - 1) / step);
    EXPECT_NEAR(thresholdFromGaps(*sampled), thresholdFromGaps(*demo), 0.25 * thresholdFromGaps(*demo));
    // Two actions of one take: the first one's end is a frame from the
    // second one's start, which is its continuation and not a gap.
    const Motion* m = in.motions[0];
    const std::vector<ActionRef> two = {{0, 0, 40}, {0, 41, 80}};
    auto own = transitionGaps(std::span(&m, 1), std::span(in.joints.data(), 1), two, GraphWeights::fighting());
    ASSERT_TRUE(own);
    ASSERT_EQ(own->size(), 2u);
    const PoseFeature end0 = poseFeature(*m, in.joints[0], 40), start0 = poseFeature(*m, in.joints[0], 0);
    const PoseFeature end1 = poseFeature(*m, in.joints[0], 80), start1 = poseFeature(*m, in.joints[0], 41);
    const double d00 = poseDistance(end0, start0, GraphWeights::fighting());
    const double d10 = poseDistance(end1, start0, GraphWeights::fighting()), d11 = poseDistance(end1, start1, GraphWeights::fighting());
    std::vector<double> expected = {d00, std::min(d10, d11)};
    std::sort(expected.begin(), expected.end());
    EXPECT_NEAR((*own)[0], expected[0], 1e-4);
    EXPECT_NEAR((*own)[1], expected[1], 1e-4);
    auto bad = transitionGaps(std::span(&m, 1), std::span(in.joints.data(), 1), std::vector<ActionRef>{{0, 0, 1 << 30}},
                              GraphWeights::fighting());
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().message.find("not a range inside motion 0"), std::string::npos) << bad.error().message;
}

TEST(MotionGraph, DeterministicForASeed) {
    const auto& in = demoGraphInput();
    GraphOptions o;
    o.seed = 7;
    auto a = buildMotionGraph(in.motions, in.joints, in.actions, o);
    auto b = buildMotionGraph(in.motions, in.joints, in.actions, o);
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_EQ(a->nodeCount, b->nodeCount);
    EXPECT_EQ(a->startNode, b->startNode);
    EXPECT_EQ(a->endNode, b->endNode);
    EXPECT_EQ(a->next, b->next);
    EXPECT_EQ(a->maxClusterDistance, b->maxClusterDistance);
    // Other seeds give other, equally valid clusterings.
    for (std::uint64_t seed : {2u, 3u, 4u}) {
        o.seed = seed;
        auto c = buildMotionGraph(in.motions, in.joints, in.actions, o);
        ASSERT_TRUE(c.ok());
        EXPECT_LT(c->maxClusterDistance, o.threshold);
        EXPECT_GE(c->stats.sccShare, 0.9) << "seed " << seed;
    }
}

TEST(MotionGraph, MoreNodesWhenTheThresholdShrinks) {
    const auto& in = demoGraphInput();
    int previous = 0;
    for (double threshold : {0.6, 0.3, 0.15, 0.08}) {
        GraphOptions o;
        o.threshold = threshold;
        auto g = buildMotionGraph(in.motions, in.joints, in.actions, o);
        ASSERT_TRUE(g.ok()) << g.error().message;
        std::printf("threshold %.2f: %d nodes, largest SCC %.1f %%\n", threshold, g->stats.nodes,
                    100.0 * g->stats.sccShare);
        EXPECT_LT(g->maxClusterDistance, threshold);
        EXPECT_GT(g->stats.nodes, previous) << "threshold " << threshold;
        previous = g->stats.nodes;
    }
}

TEST(MotionGraph, MaxNodesCapsK) {
    const auto& in = demoGraphInput();
    GraphOptions o;
    o.threshold = 0.01;
    o.maxNodes = 12;
    auto g = buildMotionGraph(in.motions, in.joints, in.actions, o);
    ASSERT_TRUE(g.ok()) << g.error().message;
    EXPECT_LE(g->nodeCount, 12);
    EXPECT_GT(g->maxClusterDistance, o.threshold);  // reported honestly
}

TEST(MotionGraph, NodesNextAndComponentsAgreeWithBruteForce) {
    const auto& in = demoGraphInput();
    const MotionGraph& g = demoGraph();
    const std::size_t n = in.actions.size();
    ASSERT_EQ(g.startNode.size(), n);
    ASSERT_EQ(g.next.size(), n);
    const double threshold = GraphOptions{}.threshold;
    for (std::size_t a = 0; a < n; ++a) {
        // Each pose lies within the threshold of its node's centre.
        const ActionRef& r = in.actions[a];
        const Motion& m = *in.motions[static_cast<std::size_t>(r.motion)];
        const StandardJoints& j = in.joints[static_cast<std::size_t>(r.motion)];
        EXPECT_LT(poseDistance(poseFeature(m, j, r.firstFrame),
                               g.centres[static_cast<std::size_t>(g.startNode[a])], GraphWeights::fighting()),
                  threshold + 1e-4);
        EXPECT_LT(poseDistance(poseFeature(m, j, r.lastFrame), g.centres[static_cast<std::size_t>(g.endNode[a])],
                               GraphWeights::fighting()),
                  threshold + 1e-4);
        // Next: the actions starting at its end node, and its continuation in the capture.
        std::vector<int> expected;
        for (std::size_t b = 0; b < n; ++b) {
            const ActionRef& rb = in.actions[b];
            if (g.startNode[b] == g.endNode[a] || (rb.motion == r.motion && rb.firstFrame == r.lastFrame + 1))
                expected.push_back(static_cast<int>(b));
        }
        EXPECT_EQ(g.next[a], expected) << "action " << a;
        EXPECT_EQ(g.next[a].empty(), expected.empty());
    }
    EXPECT_EQ(g.stats.deadEnds,
              std::count_if(g.next.begin(), g.next.end(), [](const auto& next) { return next.empty(); }));

    // Components by mutual reachability over the action graph (BFS from
    // every action; an action reaches itself only along a cycle).
    std::vector<std::vector<std::uint8_t>> reach(n, std::vector<std::uint8_t>(n, 0));
    for (std::size_t s = 0; s < n; ++s) {
        std::queue<int> q;
        for (int b : g.next[s])
            if (!reach[s][static_cast<std::size_t>(b)]) reach[s][static_cast<std::size_t>(b)] = 1, q.push(b);
        while (!q.empty()) {
            const int u = q.front();
            q.pop();
            for (int v : g.next[static_cast<std::size_t>(u)])
                if (!reach[s][static_cast<std::size_t>(v)]) reach[s][static_cast<std::size_t>(v)] = 1, q.push(v);
        }
    }
    int best = 0;
    std::vector<std::uint8_t> bestMembers;
    for (std::size_t rep = 0; rep < n; ++rep) {
        if (!reach[rep][rep]) continue;
        std::vector<std::uint8_t> inside(n, 0);
        int count = 0;
        for (std::size_t a = 0; a < n; ++a)
            if (reach[rep][a] && reach[a][rep]) inside[a] = 1, ++count;
        if (count > best) best = count, bestMembers = inside;
    }
    EXPECT_EQ(g.stats.largestSccActions, best);
    EXPECT_EQ(g.inLargestScc, bestMembers);
}

// The capture's own continuation is always a transition: without it,
// clustering put the two sides of some cuts (a frame apart) in different
// nodes, and every running turn of the demo was a dead end.
TEST(MotionGraph, CaptureContinuationsAreAlwaysEdges) {
    const auto& in = demoGraphInput();
    const MotionGraph& g = demoGraph();
    const std::vector<int> succ = naturalSuccessors(in.actions);
    int continued = 0;
    for (std::size_t a = 0; a < succ.size(); ++a) {
        if (succ[a] < 0) continue;
        ++continued;
        EXPECT_TRUE(std::binary_search(g.next[a].begin(), g.next[a].end(), succ[a])) << "action " << a;
        EXPECT_EQ(in.actions[static_cast<std::size_t>(succ[a])].firstFrame, in.actions[a].lastFrame + 1);
    }
    // Every action but the last of each take continues.
    std::set<int> takes;
    for (const ActionRef& r : in.actions) takes.insert(r.motion);
    EXPECT_EQ(continued, static_cast<int>(in.actions.size() - takes.size()));
    // Clustering alone left some out (the check can fail), and adding them
    // grows the largest strongly connected set.
    MotionGraph nodesOnly;
    nodesOnly.nodeCount = g.nodeCount;
    connectNodes(nodesOnly, g.startNode, g.endNode);
    EXPECT_GT(g.naturalEdges, 0);
    EXPECT_GT(g.stats.largestSccActions, nodesOnly.stats.largestSccActions);
    EXPECT_LE(g.stats.deadEnds, nodesOnly.stats.deadEnds);
    RecordProperty("natural_edges", g.naturalEdges);
    RecordProperty("scc_nodes_only", nodesOnly.stats.largestSccActions);
    RecordProperty("scc", g.stats.largestSccActions);
    std::printf("capture continuations added: %d; largest SCC %d -> %d of %zu actions, dead ends %d -> %d\n",
                g.naturalEdges, nodesOnly.stats.largestSccActions, g.stats.largestSccActions, in.actions.size(),
                nodesOnly.stats.deadEnds, g.stats.deadEnds);
}

// The project cache stores only the node of each action's ends; reconnecting
// them must give back the same graph.
TEST(MotionGraph, ReconnectingCachedNodesGivesTheSameGraph) {
    const prep::MotionGraph& g = demoGraph();
    prep::MotionGraph r;
    r.nodeCount = g.nodeCount;
    prep::connectNodes(r, g.startNode, g.endNode, prep::naturalSuccessors(demoGraphInput().actions));
    EXPECT_EQ(r.next, g.next);
    EXPECT_EQ(r.inLargestScc, g.inLargestScc);
    EXPECT_EQ(r.stats.largestSccActions, g.stats.largestSccActions);
    EXPECT_EQ(r.stats.deadEnds, g.stats.deadEnds);
    EXPECT_EQ(r.stats.maxOutDegree, g.stats.maxOutDegree);
    prep::MotionGraph empty;
    prep::connectNodes(empty, {}, {});
    EXPECT_EQ(empty.stats.edges, 0);
}

TEST(MotionGraph, RejectsBadInputWithReasons) {
    const auto& in = demoGraphInput();
    const GraphOptions o;
    auto message = [](const Result<MotionGraph>& r) { return r.ok() ? std::string("(ok)") : r.error().message; };

    // A motion with another skeleton.
    Motion renamed = *in.motions[1];
    renamed.skeleton().names[5] = "Skull";
    std::vector<const Motion*> motions = in.motions;
    motions[1] = &renamed;
    auto r = buildMotionGraph(motions, in.joints, in.actions, o);
    EXPECT_NE(message(r).find("motion 1: skeleton differs"), std::string::npos) << message(r);

    std::vector<ActionRef> bad = in.actions;
    bad[3].lastFrame = in.motions[static_cast<std::size_t>(bad[3].motion)]->frameCount();
    r = buildMotionGraph(in.motions, in.joints, bad, o);
    EXPECT_NE(message(r).find("action 3: frames"), std::string::npos) << message(r);
    bad = in.actions;
    bad[4].firstFrame = bad[4].lastFrame + 1;
    EXPECT_NE(message(buildMotionGraph(in.motions, in.joints, bad, o)).find("action 4"), std::string::npos);
    bad = in.actions;
    bad[5].firstFrame = -1;
    EXPECT_NE(message(buildMotionGraph(in.motions, in.joints, bad, o)).find("action 5"), std::string::npos);
    bad = in.actions;
    bad[6].motion = 99;
    EXPECT_NE(message(buildMotionGraph(in.motions, in.joints, bad, o)).find("refers to motion 99"),
              std::string::npos);

    std::vector<StandardJoints> joints = in.joints;
    joints[2].leftFoot = -1;
    EXPECT_NE(message(buildMotionGraph(in.motions, joints, in.actions, o)).find("leftFoot"), std::string::npos);
    joints.pop_back();
    EXPECT_NE(message(buildMotionGraph(in.motions, joints, in.actions, o)).find("joint sets"), std::string::npos);
    EXPECT_FALSE(buildMotionGraph(in.motions, in.joints, {}, o).ok());
    EXPECT_FALSE(buildMotionGraph({}, {}, in.actions, o).ok());
    GraphOptions zero;
    zero.threshold = 0.0;
    EXPECT_NE(message(buildMotionGraph(in.motions, in.joints, in.actions, zero)).find("threshold"),
              std::string::npos);
}

TEST(MotionGraph, ReportsProgressAndCancels) {
    const auto& in = demoGraphInput();
    std::vector<double> fractions;
    auto ok = buildMotionGraph(in.motions, in.joints, in.actions, GraphOptions{}, [&](double f, std::string_view) {
        fractions.push_back(f);
        return true;
    });
    ASSERT_TRUE(ok.ok());
    ASSERT_GE(fractions.size(), 3u);
    EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));
    EXPECT_EQ(fractions.front(), 0.0);
    EXPECT_EQ(fractions.back(), 1.0);

    for (std::size_t stop = 0; stop < fractions.size(); ++stop) {
        std::size_t calls = 0;
        auto r = buildMotionGraph(in.motions, in.joints, in.actions, GraphOptions{},
                                  [&](double, std::string_view) { return calls++ < stop; });
        ASSERT_FALSE(r.ok()) << "stop at call " << stop;
        EXPECT_TRUE(r.error().isCancelled()) << r.error().message;
        EXPECT_EQ(calls, stop + 1);
    }
}

// Real captures, cut naively into 1 s windows (no segmentation yet): the
// windows start and end mid-movement, so this is a hard case for the graph.
TEST(MotionGraphReal, KarateOneSecondWindows) {
    std::vector<Motion> motions;
    std::vector<std::string> names;
    for (const auto& path : test::sharedBvhFiles()) {
        if (path.parent_path().filename() != "cmu135_karate") continue;
        auto m = loadMotion(path);
        ASSERT_TRUE(m.ok()) << path << ": " << m.error().message;
        motions.push_back(std::move(*m));
        names.push_back(path.stem().string());
    }
    ASSERT_GE(motions.size(), 4u);
    std::vector<const Motion*> ptrs;
    std::vector<StandardJoints> joints;
    std::vector<ActionRef> actions;
    for (std::size_t i = 0; i < motions.size(); ++i) {
        ptrs.push_back(&motions[i]);
        joints.push_back(guessStandardJoints(motions[i].skeleton()));
        const int window = static_cast<int>(std::lround(motions[i].fps()));
        for (int f = 0; f + window <= motions[i].frameCount(); f += window)
            actions.push_back({static_cast<int>(i), f, f + window - 1});
    }
    for (double threshold : {GraphOptions{}.threshold, 0.5}) {
        GraphOptions o;
        o.weights = GraphWeights::fighting();
        o.threshold = threshold;
        const auto start = std::chrono::steady_clock::now();
        auto g = buildMotionGraph(ptrs, joints, actions, o);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        ASSERT_TRUE(g.ok()) << g.error().message;
        std::printf("cmu135_karate, %zu takes, %zu 1 s windows, threshold %.2f: %d nodes, largest SCC %d actions "
                    "(%.1f %%), %d dead ends, largest pose-centre distance %.3f, %.2f s\n",
                    motions.size(), actions.size(), threshold, g->stats.nodes, g->stats.largestSccActions,
                    100.0 * g->stats.sccShare, g->stats.deadEnds, g->maxClusterDistance, seconds);
        EXPECT_LT(g->maxClusterDistance, threshold);
        EXPECT_GT(g->stats.nodes, 1);
        EXPECT_LT(g->stats.nodes, static_cast<int>(2 * actions.size()));
    }
}
