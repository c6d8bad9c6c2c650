// The Interaction Graph's carrying (SPEC 3.4-3.5, collaborative) on the demo
// actor's carry set: two carriers of one long box follow a circle with a
// small path error and keep the box (hand to hand within 5 % of its length,
// measured on the posed scene), the build does not depend on the thread
// count, reward weights must be finite, and a project without attacks is
// refused by the duel's graph with a clear message.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <string>

#include "fray/igraph/carry.h"
#include "fray/igraph/igraph.h"
#include "fray/sim/geometry.h"
#include "fray/sim/scene.h"
#include "sim/demo_world.h"

namespace fray::test {
namespace {

const DemoWorld& carryWorld() {
    static const std::unique_ptr<DemoWorld> world = buildDemoWorld("carry");
    return *world;
}

struct Carry {
    igraph::CarryGraph graph;
    std::vector<igraph::CarryPolicy> policies;
};

const Carry& carry() {
    static const std::unique_ptr<Carry> c = [] {
        auto out = std::make_unique<Carry>();
        igraph::CarryOptions o;
        o.maxSamples = 3000;  // a small graph (the CLI's default is 20,000): the test stays fast
        auto g = igraph::buildCarryGraph(carryWorld().library, o);
        if (!g) throw std::runtime_error(g.error().message);
        out->graph = std::move(*g);
        for (int k = 0; k < igraph::kCarryDirections; ++k) {
            auto p = igraph::computeCarryPolicy(out->graph, igraph::CarryWeights{}, k, 3);
            if (!p) throw std::runtime_error(p.error().message);
            out->policies.push_back(std::move(*p));
        }
        return out;
    }();
    return *c;
}

int jointIndex(const Skeleton& s, const std::string& name) {
    for (int j = 0; j < s.jointCount(); ++j)
        if (s.names[static_cast<std::size_t>(j)] == name) return j;
    return -1;
}

TEST(IgraphCarry, TwoCarriersFollowACircleAndKeepTheBox) {
    const auto& lib = carryWorld().library;
    const auto& c = carry();
    EXPECT_GT(c.graph.states.size(), 500u);
    EXPECT_GT(c.graph.edges.size(), 10 * c.graph.states.size());
    auto path = igraph::parseCarryPath("circle:3");
    ASSERT_TRUE(path) << path.error().message;
    igraph::CarryRunOptions o;
    o.duration = 60;
    auto run = igraph::runCarry(lib, c.graph, c.policies, *path, o);
    ASSERT_TRUE(run) << run.error().message;
    const sim::Scene& scene = run->scene;
    ASSERT_EQ(scene.characters.size(), 3u);
    EXPECT_EQ(scene.characters[2].body, "box");

    // Measured on the posed scene (what render and export show), every 1/30 s:
    // the grips (midpoints of each carrier's hands) stay a box length apart,
    // their middle stays on the circle, and it goes round it.
    sim::ScenePoser poser(scene, lib);
    const Skeleton& sk = poser.skeleton(0);
    const int lh = jointIndex(sk, "LeftHand"), rh = jointIndex(sk, "RightHand");
    ASSERT_GE(lh, 0);
    ASSERT_GE(rh, 0);
    const double L = c.graph.options.boxLength;
    std::vector<glm::vec3> wa, wb;
    double worst = 0, pathSum = 0, turned = 0, lastAngle = 0;
    const int n = static_cast<int>(o.duration * 30);
    for (int i = 0; i <= n; ++i) {
        const double t = i / 30.0;
        poser.worldPositions(0, t, wa);
        poser.worldPositions(1, t, wb);
        const glm::vec3 ga = 0.5f * (wa[static_cast<std::size_t>(lh)] + wa[static_cast<std::size_t>(rh)]);
        const glm::vec3 gb = 0.5f * (wb[static_cast<std::size_t>(lh)] + wb[static_cast<std::size_t>(rh)]);
        worst = std::max(worst, std::abs(static_cast<double>(glm::length(ga - gb)) - L) / L);
        const glm::vec2 mid(0.5f * (ga.x + gb.x), 0.5f * (ga.z + gb.z));
        pathSum += std::abs(static_cast<double>(glm::length(mid)) - 3.0);
        const double angle = std::atan2(static_cast<double>(mid.y), static_cast<double>(mid.x));
        if (i > 0) turned += sim::wrapAngle(angle - lastAngle);
        lastAngle = angle;
    }
    const double meanPathError = pathSum / (n + 1);
    EXPECT_LT(meanPathError, 0.5);
    EXPECT_LT(worst, 0.05) << "hand-to-hand distance left 5 % of the box length";
    // At 0.35 m/s a minute goes most of the way round a 3 m circle (18.8 m).
    EXPECT_GT(turned, std::numbers::pi) << "the pair did not go round the circle";
    // The run's own figures agree with the posed scene's.
    EXPECT_NEAR(run->stats.pathErrorMean, meanPathError, 0.1);
    EXPECT_LT(run->stats.gripErrorMax, 0.05);
    std::printf("carry: %zu states, %zu edges, built in %.2f s; path error mean %.3f m, hand distance within %.2f %%, turned %.2f rad, "
                "%lld decisions (%lld off the graph)\n",
                c.graph.states.size(), c.graph.edges.size(), c.graph.seconds, meanPathError, 100 * worst, turned,
                static_cast<long long>(run->stats.decisions), static_cast<long long>(run->stats.offGraph));
}

TEST(IgraphCarry, BuildDoesNotDependOnThreads) {
    igraph::CarryOptions o;
    o.maxSamples = 1000;
    auto a = igraph::buildCarryGraph(carryWorld().library, o);
    ASSERT_TRUE(a) << a.error().message;
    o.parallel = false;
    auto b = igraph::buildCarryGraph(carryWorld().library, o);
    ASSERT_TRUE(b) << b.error().message;
    ASSERT_EQ(a->states.size(), b->states.size());
    ASSERT_EQ(a->edges.size(), b->edges.size());
    for (std::size_t i = 0; i < a->states.size(); ++i) {
        ASSERT_EQ(a->states[i].r, b->states[i].r);
        ASSERT_EQ(a->states[i].thetaA, b->states[i].thetaA);
    }
    for (std::size_t e = 0; e < a->edges.size(); ++e) {
        ASSERT_EQ(a->edges[e].to, b->edges[e].to);
        ASSERT_EQ(a->edges[e].actionA, b->edges[e].actionA);
        ASSERT_EQ(a->edges[e].actionB, b->edges[e].actionB);
    }
}

TEST(IgraphCarry, RewardWeightsMustBeFinite) {
    igraph::CarryWeights w;
    EXPECT_TRUE(igraph::validate(w));
    w.wD = std::numeric_limits<double>::quiet_NaN();
    auto st = igraph::validate(w);
    ASSERT_FALSE(st);
    EXPECT_NE(st.error().message.find("w_d is not a finite number"), std::string::npos) << st.error().message;
    w = {};
    w.wV = std::numeric_limits<double>::infinity();
    EXPECT_FALSE(igraph::validate(w));
    w = {};
    EXPECT_FALSE(igraph::applyCarryEdit(w, "w_theta=nan"));
    EXPECT_FALSE(igraph::applyCarryEdit(w, "w_v=1e999"));
    EXPECT_FALSE(igraph::applyCarryEdit(w, "speed=fast"));
    EXPECT_FALSE(igraph::applyCarryEdit(w, "w_q=1"));
    EXPECT_EQ(w.wTheta, igraph::CarryWeights{}.wTheta) << "a refused edit changed the weights";
    EXPECT_TRUE(igraph::applyCarryEdit(w, "w_v=3"));
    EXPECT_EQ(w.wV, 3);
    // A policy is not computed with a weight that is not a number.
    igraph::CarryGraph empty;
    w.wTheta = std::numeric_limits<double>::quiet_NaN();
    auto p = igraph::computeCarryPolicy(empty, w, 0, 3);
    ASSERT_FALSE(p);
    EXPECT_NE(p.error().message.find("w_theta"), std::string::npos);
}

TEST(IgraphCarry, PathsAndBadInput) {
    EXPECT_FALSE(igraph::parseCarryPath("circle:nan"));
    EXPECT_FALSE(igraph::parseCarryPath("circle:"));
    EXPECT_FALSE(igraph::parseCarryPath("square:3"));
    auto p = igraph::carryPathFromJson(R"({"version": 1, "points": [[0, 0], [4, 0], [4, 4]]})", "p.json");
    ASSERT_TRUE(p) << p.error().message;
    EXPECT_NEAR(igraph::distanceToCarryPath(*p, {2.0f, 1.0f}), 1.0, 1e-6);
    auto bad = igraph::carryPathFromJson(R"({"version": 1, "points": [[0, 0], [4, "x"]]})", "p.json");
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().message.find("p.json: /points/1"), std::string::npos) << bad.error().message;
    EXPECT_FALSE(igraph::carryPathFromJson("{", "p.json"));
    // An open path: the pair stops at its end.
    const auto& c = carry();
    auto line = igraph::carryPathFromJson(R"({"version": 1, "points": [[0, 0], [3, 0]]})", "line.json");
    ASSERT_TRUE(line);
    igraph::CarryRunOptions o;
    o.duration = 20;
    auto run = igraph::runCarry(carryWorld().library, c.graph, c.policies, *line, o);
    ASSERT_TRUE(run) << run.error().message;
    EXPECT_LT(run->stats.pathErrorMean, 0.5);
    EXPECT_GT(run->stats.holds, 0) << "the pair should hold still at the path's end";
    const auto& keys = run->scene.characters[2].keys;
    ASSERT_FALSE(keys.empty());
}

TEST(IgraphCarry, ProjectsWithoutCarryOrAttackActionsAreRefused) {
    // The carry project has no attacks: the duel's graph refuses it.
    auto rules = igraph::Rules::make(carryWorld().library);
    ASSERT_FALSE(rules);
    EXPECT_NE(rules.error().message.find("no attack actions"), std::string::npos) << rules.error().message;
    // A prefix nothing has: no carry-end actions.
    igraph::CarryOptions o;
    o.prefix = "lift_piano_";
    auto g = igraph::buildCarryGraph(carryWorld().library, o);
    ASSERT_FALSE(g);
    EXPECT_NE(g.error().message.find("no carry-end actions"), std::string::npos) << g.error().message;
}

}  // namespace
}  // namespace fray::test
