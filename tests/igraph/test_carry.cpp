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
#include <thread>

#include "fray/igraph/carry.h"
#include "fray/igraph/igraph.h"
#include "fray/sim/geometry.h"
#include "fray/sim/patches.h"
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

// ---- the carry graph file ------------------------------------------------------------

// The bytes with a CRC-32 recomputed over everything before it (a file
// damaged in a way the checksum does not catch, or of another rule).
std::string resealed(std::string bytes) {
    bytes.resize(bytes.size() - 4);
    const std::uint32_t crc = sim::patchFileChecksum(bytes);
    bytes.append(reinterpret_cast<const char*>(&crc), 4);
    return bytes;
}

::testing::AssertionResult refused(const Result<igraph::CarryGraph>& g, const std::string& expected) {
    if (g) return ::testing::AssertionFailure() << "accepted; expected '" << expected << "'";
    if (g.error().message.find(expected) == std::string::npos)
        return ::testing::AssertionFailure() << "'" << g.error().message << "' does not say '" << expected << "'";
    if (g.error().message.find("g.carry") == std::string::npos)
        return ::testing::AssertionFailure() << "'" << g.error().message << "' does not name the file";
    return ::testing::AssertionSuccess();
}

TEST(IgraphCarryFile, RoundTripsToTheSameGraphAndBytes) {
    const auto& lib = carryWorld().library;
    const auto& c = carry();
    auto bytes = igraph::carryGraphBytes(c.graph);
    ASSERT_TRUE(bytes) << bytes.error().message;
    EXPECT_EQ(bytes->substr(0, 8), "FRAYIGCA");
    auto g = igraph::readCarryGraph(*bytes, "g.carry", lib);
    ASSERT_TRUE(g) << g.error().message;
    ASSERT_EQ(g->states.size(), c.graph.states.size());
    ASSERT_EQ(g->edges.size(), c.graph.edges.size());
    EXPECT_EQ(g->firstEdge, c.graph.firstEdge);
    EXPECT_EQ(g->actions, c.graph.actions);
    EXPECT_EQ(g->hold, c.graph.hold);
    EXPECT_EQ(g->gripReach, c.graph.gripReach);
    EXPECT_EQ(g->options.maxSamples, c.graph.options.maxSamples);
    for (std::size_t i = 0; i < g->states.size(); ++i) {
        ASSERT_EQ(g->states[i].r, c.graph.states[i].r);
        ASSERT_EQ(g->states[i].thetaB, c.graph.states[i].thetaB);
    }
    for (std::size_t e = 0; e < g->edges.size(); ++e) {
        ASSERT_EQ(g->edges[e].to, c.graph.edges[e].to);
        ASSERT_EQ(g->edges[e].actionB, c.graph.edges[e].actionB);
        ASSERT_EQ(g->edges[e].boxZ, c.graph.edges[e].boxZ);
        ASSERT_EQ(g->edges[e].gripError, c.graph.edges[e].gripError);
    }
    auto again = igraph::carryGraphBytes(*g);
    ASSERT_TRUE(again);
    EXPECT_EQ(*again, *bytes) << "what loads saves the same bytes";
    // The loaded graph plays as the built one: the same policies, the same run.
    auto p = igraph::computeCarryPolicies(*g, igraph::CarryWeights{}, 3);
    ASSERT_TRUE(p) << p.error().message;
    for (int k = 0; k < igraph::kCarryDirections; ++k) EXPECT_EQ(p->policies[static_cast<std::size_t>(k)].best, c.policies[static_cast<std::size_t>(k)].best);
    auto path = igraph::parseCarryPath("circle:3");
    igraph::CarryRunOptions o;
    o.duration = 10;
    auto r1 = igraph::runCarry(lib, c.graph, c.policies, *path, o);
    auto r2 = igraph::runCarry(lib, *g, p->policies, *path, o);
    ASSERT_TRUE(r1 && r2);
    EXPECT_EQ(r1->stats.pathErrorMean, r2->stats.pathErrorMean);
    EXPECT_EQ(r1->stats.decisions, r2->stats.decisions);
}

TEST(IgraphCarryFile, DamagedForeignStaleAndNewerFilesAreRefused) {
    const auto& lib = carryWorld().library;
    auto good = igraph::carryGraphBytes(carry().graph);
    ASSERT_TRUE(good);
    const std::string& b = *good;
    // Damaged: a flipped byte, a truncated file, a short file.
    std::string flipped = b;
    flipped[flipped.size() / 2] = static_cast<char>(flipped[flipped.size() / 2] ^ 0x5a);
    EXPECT_TRUE(refused(igraph::readCarryGraph(flipped, "g.carry", lib), "truncated or corrupt"));
    EXPECT_TRUE(refused(igraph::readCarryGraph(b.substr(0, b.size() - 100), "g.carry", lib), "truncated or corrupt"));
    EXPECT_TRUE(refused(igraph::readCarryGraph(b.substr(0, 14), "g.carry", lib), "truncated"));
    // Foreign: a duel's graph file, something else.
    std::string duel = b;
    duel.replace(0, 8, "FRAYIGPH");
    EXPECT_TRUE(refused(igraph::readCarryGraph(duel, "g.carry", lib), "an interaction graph for a duel"));
    EXPECT_TRUE(refused(igraph::readCarryGraph("{\"version\": 1}", "g.carry", lib), "not a Fray carry graph file"));
    EXPECT_TRUE(refused(igraph::readCarryGraph("", "g.carry", lib), "not a Fray carry graph file"));
    // The duel's reader names a carry graph as such.
    auto asDuel = igraph::readGraphUnbound(b, "g.carry");
    ASSERT_FALSE(asDuel);
    EXPECT_NE(asDuel.error().message.find("g.carry: a carry graph"), std::string::npos) << asDuel.error().message;
    // Another file version; another rule; another library (stale).
    std::string newer = b;
    newer[8] = 9;
    auto v = igraph::readCarryGraph(resealed(newer), "g.carry", lib);
    EXPECT_TRUE(refused(v, "carry graph file version 9"));
    if (!v) {
        EXPECT_EQ(v.error().kind, ErrorKind::Unsupported);
    }
    std::string rule = b;
    rule[12] = 7;
    auto r = igraph::readCarryGraph(resealed(rule), "g.carry", lib);
    EXPECT_TRUE(refused(r, "made by carry graph rule 7"));
    if (!r) {
        EXPECT_EQ(r.error().kind, ErrorKind::Stale);
    }
    igraph::CarryGraph other = carry().graph;
    other.libraryKey ^= 1;
    auto st = igraph::readCarryGraph(*igraph::carryGraphBytes(other), "g.carry", lib);
    EXPECT_TRUE(refused(st, "made from other actions than the project has now"));
    if (!st) {
        EXPECT_EQ(st.error().kind, ErrorKind::Stale);
    }
    EXPECT_TRUE(igraph::readCarryGraphUnbound(*igraph::carryGraphBytes(other), "g.carry")) << "stats read any library's graph";
    // Damage the checksum does not catch: an edge to a state that does not exist, trailing data.
    other = carry().graph;
    other.edges[5].to = static_cast<std::int32_t>(other.states.size() + 3);
    EXPECT_TRUE(refused(igraph::readCarryGraph(*igraph::carryGraphBytes(other), "g.carry", lib), "corrupt at byte"));
    other = carry().graph;
    other.edges[7].actionA = 1;  // not a carry-end action
    EXPECT_TRUE(refused(igraph::readCarryGraph(*igraph::carryGraphBytes(other), "g.carry", lib), "corrupt at byte"));
    other = carry().graph;
    other.states[3].r = std::numeric_limits<double>::quiet_NaN();
    EXPECT_TRUE(refused(igraph::readCarryGraph(*igraph::carryGraphBytes(other), "g.carry", lib), "corrupt at byte"));
    std::string trailing = b.substr(0, b.size() - 4) + "xyz!" + b.substr(b.size() - 4);
    EXPECT_TRUE(refused(igraph::readCarryGraph(resealed(trailing), "g.carry", lib), "unexpected data after"));
    // Every truncation of the header is refused, never a crash.
    for (std::size_t n = 0; n < 200; n += 3) EXPECT_FALSE(igraph::readCarryGraphUnbound(resealed(b.substr(0, std::max<std::size_t>(n, 4))), "g.carry"));
}

// ---- the policies in the background ----------------------------------------------------

TEST(IgraphCarry, ChangedWeightRecomputesInTheBackgroundWhileTheOldPoliciesPlay) {
    const auto& lib = carryWorld().library;
    const auto graph = std::make_shared<const igraph::CarryGraph>(carry().graph);
    auto first = igraph::computeCarryPolicies(*graph, igraph::CarryWeights{}, 3);
    ASSERT_TRUE(first) << first.error().message;
    const auto old = std::make_shared<const igraph::CarryPolicySet>(std::move(*first));
    igraph::CarryPolicyService service(graph, old);
    EXPECT_EQ(service.current(), old);
    // A weight that is not a number is refused at once; the old set stays.
    igraph::CarryWeights bad;
    bad.wV = std::numeric_limits<double>::quiet_NaN();
    auto refusedRequest = service.request(bad, 3);
    ASSERT_FALSE(refusedRequest);
    EXPECT_NE(refusedRequest.error().message.find("w_v is not a finite number"), std::string::npos);
    EXPECT_EQ(service.current(), old);
    // The driver keeps playing the old set while a deep recompute runs.
    auto driver = igraph::CarryDriver::make(lib, graph, old, igraph::parseCarryPath("circle:3").value());
    ASSERT_TRUE(driver) << driver.error().message;
    igraph::CarryWeights slow;
    slow.wV = 20;
    ASSERT_TRUE(service.request(slow, 64));  // long enough to be cancelled below
    for (int i = 0; i < 30; ++i) {
        (*driver)->advance(1.0 / 30);
        if (service.current() != old) break;
        EXPECT_EQ((*driver)->policies(), old);
    }
    // A second request cancels the one in flight: what comes into force is the last asked for.
    igraph::CarryWeights w;
    w.wV = 12;
    ASSERT_TRUE(service.request(w, 3));
    ASSERT_TRUE(service.wait());
    EXPECT_FALSE(service.busy());
    const auto now = service.current();
    ASSERT_NE(now, old);
    EXPECT_EQ(now->weights.wV, 12);
    EXPECT_EQ(now->depth, 3);
    EXPECT_GT(now->seconds, 0);
    // The same policies as computed in the foreground, and they differ from the old ones.
    auto direct = igraph::computeCarryPolicies(*graph, w, 3);
    ASSERT_TRUE(direct);
    std::size_t changed = 0;
    for (int k = 0; k < igraph::kCarryDirections; ++k) {
        const auto kk = static_cast<std::size_t>(k);
        EXPECT_EQ(now->policies[kk].best, direct->policies[kk].best);
        for (std::size_t i = 0; i < graph->states.size(); ++i) changed += now->policies[kk].best[i] != old->policies[kk].best[i] ? 1 : 0;
    }
    EXPECT_GT(changed, 0u) << "w_v 8 -> 12 changed no choice";
    ASSERT_TRUE((*driver)->setPolicies(now));
    (*driver)->advance(2.0);
    EXPECT_EQ((*driver)->policies(), now);
    std::printf("carry policies recomputed in the background: %.3f s (%zu states, 8 directions, depth 3); %zu choices changed\n", now->seconds,
                graph->states.size(), changed);
}

// ---- the pair in real time -------------------------------------------------------------

TEST(IgraphCarry, DriverFollowsThePathAsRunCarryAndTurnsWhenSteered) {
    const auto& lib = carryWorld().library;
    const auto& c = carry();
    const auto graph = std::make_shared<const igraph::CarryGraph>(c.graph);
    auto set = std::make_shared<igraph::CarryPolicySet>();
    set->policies = c.policies;
    set->depth = 3;
    auto path = igraph::parseCarryPath("circle:3");
    igraph::CarryRunOptions o;
    o.duration = 30;
    auto run = igraph::runCarry(lib, c.graph, c.policies, *path, o);
    ASSERT_TRUE(run);
    auto d = igraph::CarryDriver::make(lib, graph, set, *path);
    ASSERT_TRUE(d) << d.error().message;
    for (int f = 0; f < 30 * 60; ++f) (*d)->advance(1.0 / 60);
    EXPECT_NEAR((*d)->time(), 30.0, 1e-6);
    // Frame by frame, the same decisions as the whole run at once.
    const auto& want = run->scene.characters[0].track;
    const auto& got = (*d)->scene().characters[0].track;
    ASSERT_GE(got.size(), want.size());
    for (std::size_t i = 0; i < want.size(); ++i) {
        ASSERT_EQ(got[i].action, want[i].action) << i;
        ASSERT_NEAR(got[i].start, want[i].start, 1e-9) << i;
        ASSERT_EQ((*d)->scene().characters[1].track[i].action, run->scene.characters[1].track[i].action) << i;
    }
    EXPECT_NEAR((*d)->stats().pathErrorMean, run->stats.pathErrorMean, 1e-3);
    EXPECT_LT((*d)->stats().gripErrorMax, 0.05);
    EXPECT_EQ((*d)->scene().characters[2].keys.size(), 30u * 30u + 1u);

    // Steered: 6 s towards +Z, then a turn to the left (+X) for 6 s: the box's way turns with it.
    auto s = igraph::CarryDriver::make(lib, graph, set, std::nullopt, {0, 0}, 0.0);
    ASSERT_TRUE(s) << s.error().message;
    auto& drv = **s;
    drv.advance(2.0);
    EXPECT_EQ(drv.now().direction, -1) << "not steered yet: holding";
    const glm::vec2 p0 = drv.now().boxMiddle;
    drv.steer(0.0, true);
    drv.advance(6.0);
    const glm::vec2 p1 = drv.now().boxMiddle;
    drv.steer(std::numbers::pi / 2, true);
    drv.advance(1.6);  // the actions playing end first
    const glm::vec2 p2 = drv.now().boxMiddle;
    drv.advance(6.0);
    const glm::vec2 p3 = drv.now().boxMiddle;
    const glm::vec2 first = p1 - p0, second = p3 - p2;
    EXPECT_GT(glm::length(first), 1.0f);
    EXPECT_GT(glm::length(second), 1.0f);
    EXPECT_NEAR(sim::angleOf(first), 0.0, 0.4) << first.x << ", " << first.y;
    EXPECT_NEAR(sim::angleOf(second), std::numbers::pi / 2, 0.4) << second.x << ", " << second.y;
    EXPECT_LT(drv.stats().gripErrorMax, 0.05);
    drv.steer(0.0, false);
    drv.advance(2.0);
    const glm::vec2 p4 = drv.now().boxMiddle;
    drv.advance(3.0);
    EXPECT_LT(glm::length(drv.now().boxMiddle - p4), 0.2f) << "stopped: the pair holds";
}

}  // namespace
}  // namespace fray::test
