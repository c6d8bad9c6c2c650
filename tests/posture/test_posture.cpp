// Run-time posture synthesis (SPEC 5, issue 25): the physics poses of the
// README scenes meet the issue's thresholds where the kinematic ones do not,
// the solver is deterministic, rag dolls fall, and bad input stays finite.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <utility>

#include "fray/core/kinematics.h"
#include "fray/posture/posture.h"
#include "fray/sim/metrics.h"
#include "fray/sim/compose/domino.h"
#include "fray/sim/compose/luggage.h"
#include "posture/posture_fixture.h"

namespace {

using namespace fray;
using test::demoWorld;

const std::string kDemo = FRAY_SOURCE_DIR "/resources/demo/";

const sim::Scene& duel() {
    static const sim::Scene scene = test::plannedScene(kDemo + "duel.json");
    return scene;
}

// The demo duel as the exact search plans it ("root_beam": 0), the scene two
// tests below were written on: its fighters touch within the first 4 s, and
// its first unblocked blow on a defender who is not attacking is the one the
// parry test measures. Under the root beam of 16 the duel goes another way
// from 1.52 s (docs/BENCHMARKS.md "Duel speed pass 5"): no contact in the
// first 4 s, and at its first such blow the parry leaves the nearer hand
// 47.8 cm from the striking segment against 45.8 cm without it.
const sim::Scene& exactDuel() {
    static const sim::Scene scene = test::plannedScene(kDemo + "duel.json", 0);
    return scene;
}

const sim::Scene& oneVsMany() {
    static const sim::Scene scene = [] {
        static const auto patches = test::demoPatches({"attack-defence-attack-fall", "attack-fall", "attack-attack-fall"});
        return test::composedScene(kDemo + "one_vs_many.json", patches);
    }();
    return scene;
}

// The README football run (resources/demo/football.json) on the demo actor's
// football set, with the carrier's ball.
const sim::Scene& football() {
    static const sim::Scene scene = [] {
        const auto& lib = test::footballWorld().library;
        static const sim::PatchLibrary patches = [&] {
            sim::PatchLibrary out;
            for (const auto& p : sim::defaultPatterns()) {
                if (p.name != "run-tackle-avoid") continue;
                if (auto st = sim::generatePatches(lib, p, sim::PatternSet{}, out); !st) throw std::runtime_error(st.error().message);
            }
            sim::buildConnections(lib, out);
            return out;
        }();
        const std::string path = kDemo + "football.json";
        auto spec = sim::parseComposeSpec(test::readText(path), path, patches);
        if (!spec) throw std::runtime_error(spec.error().message);
        auto made = sim::compose(lib, patches, *spec);
        if (!made) throw std::runtime_error(made.error().message);
        return std::move(*made);
    }();
    return scene;
}

void expectSameBytes(const sim::Scene& scene);

bool allFinite(const sim::JointTracks& t) {
    for (const auto& c : t.joints) {
        for (const auto& p : c) {
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return false;
        }
    }
    return true;
}

struct Both {
    sim::PostureMetrics kinematic, physics;
    posture::Report report;
};

Both measure(const sim::Scene& scene, const posture::Options& options = {}, const sim::ActionLibrary& lib = demoWorld().library) {
    const auto captured = sim::kinematicTracks(scene, lib, options.fps);
    auto frames = posture::simulate(scene, lib, options);
    EXPECT_TRUE(frames) << frames.error().message;
    Both b;
    b.kinematic = sim::computePostureMetrics(scene, lib, captured, captured);
    b.physics = sim::computePostureMetrics(scene, lib, frames->world, captured);
    b.report = frames->report;
    EXPECT_TRUE(allFinite(frames->world));
    std::printf("kinematic\n%sphysics\n%s", sim::postureMetricsToText(b.kinematic).c_str(),
                sim::postureMetricsToText(b.physics).c_str());
    std::printf("report: %d non-finite, %d pins refused, %d released, %lld capped, %d resets, %d overlaps\n",
                b.report.nonFiniteTargets, b.report.refusedPins, b.report.releasedPins,
                static_cast<long long>(b.report.cappedForces), b.report.resets,
                b.report.initialOverlaps);
    for (const auto& n : b.report.notes) std::printf("  %s\n", n.c_str());
    if (const auto& w = b.physics.worstPenetration; w.a >= 0) {
        std::printf("worst penetration (physics): %.2f cm at %.2f s, %s's %s and %s's %s\n", b.physics.penetrationMaxCm, w.time,
                    scene.characters[static_cast<std::size_t>(w.a)].name.c_str(), sim::segmentName(w.segmentA),
                    scene.characters[static_cast<std::size_t>(w.b)].name.c_str(), sim::segmentName(w.segmentB));
    }
    return b;
}

// The issue's thresholds, each reported.
void expectThresholds(const sim::PostureMetrics& m, const char* scene) {
    EXPECT_LT(m.footSkateMaxCm, 1.0) << scene;
    EXPECT_LT(m.footSkateMeanCm, 0.2) << scene;
    EXPECT_LT(m.penetrationMaxCm, 2.0) << scene;
    EXPECT_GE(m.hitsOnSurfaceShare(), 0.95) << scene << ": " << m.hitsOnSurface << " of " << m.landed;
    EXPECT_LT(m.deviationMeanCm, 3.0) << scene;
}

void record(const char* prefix, const sim::PostureMetrics& m) {
    const std::string p = prefix;
    testing::Test::RecordProperty(p + "_skate_max_cm", std::to_string(m.footSkateMaxCm));
    testing::Test::RecordProperty(p + "_skate_mean_cm", std::to_string(m.footSkateMeanCm));
    testing::Test::RecordProperty(p + "_penetration_max_cm", std::to_string(m.penetrationMaxCm));
    testing::Test::RecordProperty(p + "_hits_on_surface", std::to_string(m.hitsOnSurface) + "/" + std::to_string(m.landed));
    testing::Test::RecordProperty(p + "_deviation_mean_cm", std::to_string(m.deviationMeanCm));
}

TEST(PostureGeometry, BoxDistanceAndPenetration) {
    sim::Obb a;
    a.half = {0.1f, 0.1f, 0.1f};
    sim::Obb b = a;
    b.centre = {0.3f, 0.0f, 0.0f};  // 10 cm apart
    glm::vec3 n;
    EXPECT_NEAR(sim::boxSignedDistance(a, b, &n), 0.1, 1e-5);
    EXPECT_NEAR(n.x, 1.0, 1e-5);
    EXPECT_EQ(sim::boxPenetration(a, b), 0.0);
    b.centre = {0.15f, 0.0f, 0.0f};  // 5 cm inside
    EXPECT_NEAR(sim::boxPenetration(a, b), 0.05, 1e-5);
    EXPECT_NEAR(sim::boxSignedDistance(a, b, &n), -0.05, 1e-5);
    EXPECT_NEAR(n.x, 1.0, 1e-5);
    // Corner to corner: the gap is the diagonal.
    b.centre = {0.3f, 0.3f, 0.0f};
    EXPECT_NEAR(sim::boxSignedDistance(a, b), std::sqrt(0.02), 1e-4);
}

TEST(PostureSolver, DuelMeetsTheIssueThresholds) {
    const auto both = measure(duel());
    record("kinematic", both.kinematic);
    record("physics", both.physics);
    ASSERT_GT(both.physics.landed, 0);
    expectThresholds(both.physics, "duel");
    // The kinematic playback is what the issue complains about: blows pass
    // through bodies.
    EXPECT_LT(both.kinematic.hitsOnSurfaceShare(), 0.95);
}

TEST(PostureSolver, OneVsManyMeetsTheIssueThresholds) {
    const auto both = measure(oneVsMany());
    record("kinematic", both.kinematic);
    record("physics", both.physics);
    expectThresholds(both.physics, "one-vs-many");
    EXPECT_GT(both.kinematic.footSkateMaxCm, 1.0);  // the issue's 17.5 cm slide
}

TEST(PostureSolver, SameBytesOnOneThreadOrMany) {
    // Three duels apart (three islands, in parallel) and the one-vs-many
    // fight (one island of nine), the first seconds of each.
    sim::Scene crowd = test::pairCrowd(duel(), 6, 6.0f);
    crowd.duration = 6.0;
    {
        const posture::Simulator probe(crowd, demoWorld().library, {});
        EXPECT_EQ(probe.islands(), 3);
    }
    sim::Scene fight = oneVsMany();
    fight.duration = 6.0;
    for (const sim::Scene* scene : {&crowd, &fight}) {
        expectSameBytes(*scene);
    }
}

void expectSameBytes(const sim::Scene& scene) {
    posture::Options serial;
    serial.parallel = false;
    const auto a = posture::simulate(scene, demoWorld().library);
    const auto b = posture::simulate(scene, demoWorld().library);
    const auto c = posture::simulate(scene, demoWorld().library, serial);
    ASSERT_TRUE(a && b && c);
    ASSERT_EQ(a->world.joints.size(), c->world.joints.size());
    for (std::size_t k = 0; k < a->world.joints.size(); ++k) {
        const auto& x = a->world.joints[k];
        ASSERT_EQ(x.size(), b->world.joints[k].size());
        ASSERT_EQ(x.size(), c->world.joints[k].size());
        EXPECT_EQ(0, std::memcmp(x.data(), b->world.joints[k].data(), x.size() * sizeof(glm::vec3))) << "character " << k;
        EXPECT_EQ(0, std::memcmp(x.data(), c->world.joints[k].data(), x.size() * sizeof(glm::vec3))) << "character " << k;
    }
}

TEST(PostureSolver, WithoutControlACharacterFallsAsARagDoll) {
    sim::Scene scene = duel();
    scene.duration = 3.0;
    posture::Options options;
    options.ragdoll = {1, 0};
    const auto frames = posture::simulate(scene, demoWorld().library, options);
    ASSERT_TRUE(frames);
    const auto& lib = demoWorld().library;
    const auto captured = sim::kinematicTracks(scene, lib, options.fps);
    const int pelvis = lib.motion(lib.actions()[static_cast<std::size_t>(scene.characters[0].track[0].action)].motion).joints.pelvis;
    const int last = frames->world.frames - 1;
    const float fallen = frames->world.at(0, last)[static_cast<std::size_t>(pelvis)].y;
    const float standing = frames->world.at(1, last)[static_cast<std::size_t>(pelvis)].y;
    EXPECT_LT(fallen, 0.35f) << "the rag doll lies on the floor";
    EXPECT_GT(fallen, -0.05f) << "the floor holds it";
    EXPECT_NEAR(standing, captured.at(1, last)[static_cast<std::size_t>(pelvis)].y, 0.05f) << "the controlled one stands";
    EXPECT_TRUE(allFinite(frames->world));
}

// End joints without a box or pin (the demo actor's finger and toe ends) are
// no bodies of their own: each sits on its parent's frame at its bone's
// offset, turned by its captured rotation relative to the parent.
TEST(PostureSolver, EndJointsRideOnTheirParents) {
    const auto& scene = duel();
    const auto& lib = demoWorld().library;
    posture::Simulator solver(scene, lib, {});
    sim::ScenePoser poser(scene, lib);
    Pose pose;
    int checked = 0;
    for (int f = 0; f <= 90; ++f) {
        solver.step();
        if (f % 30 != 0) continue;
        for (int c = 0; c < 2; ++c) {
            const auto& sk = poser.skeleton(c);
            const auto roles = lib.motion(lib.actions()[static_cast<std::size_t>(scene.characters[static_cast<std::size_t>(c)].track[0].action)].motion).joints;
            const auto pos = solver.positions(c);
            const auto rot = solver.rotations(c);
            poser.pose(c, f / 60.0, pose);
            for (int j = 0; j < sk.jointCount(); ++j) {
                const int p = sk.parents[static_cast<std::size_t>(j)];
                if (p < 0 || !sk.children(j).empty() || j == roles.head || j == roles.leftHand || j == roles.rightHand ||
                    j == roles.leftFoot || j == roles.rightFoot) {
                    continue;
                }
                const auto u = static_cast<std::size_t>(j), up = static_cast<std::size_t>(p);
                const glm::vec3 expected = pos[up] + rot[up] * sk.offsets[u];
                EXPECT_LT(glm::length(pos[u] - expected), 1e-4f) << sk.names[u] << " at frame " << f;
                const glm::quat relative = glm::conjugate(rot[up]) * rot[u];
                const glm::quat diff = glm::conjugate(pose.rotations[u]) * relative;
                const float turn = 2.0f * glm::length(glm::vec3(diff.x, diff.y, diff.z));  // radians, for small turns
                EXPECT_LT(turn, 1e-3f) << sk.names[u] << " at frame " << f << ": not its captured rotation on its parent";
                ++checked;
            }
        }
    }
    EXPECT_EQ(checked, 4 * 2 * 4) << "two finger ends and two toe ends per character, at four frames";
}

TEST(PostureSolver, BadInputStaysFiniteAndIsReported) {
    const auto& lib = demoWorld().library;
    sim::Scene scene = duel();
    scene.duration = 4.0;
    // Both boxers start on the same spot, one inside the other.
    const glm::vec2 shift = scene.characters[0].track[0].root.pos - scene.characters[1].track[0].root.pos;
    for (auto& inst : scene.characters[1].track) inst.root.pos += shift;
    // A NaN pose from the second action of the first character on.
    ASSERT_GT(scene.characters[0].track.size(), 2u);
    scene.characters[0].track[1].root.pos.x = std::numeric_limits<float>::quiet_NaN();
    // A foot pin where the foot is not supported.
    const sim::ScenePoser poser(scene, lib);
    double airborne = -1;
    int foot = 0;
    for (double t = 0; t < scene.duration && airborne < 0; t += 1.0 / 60) {
        const auto c = poser.contacts(1, t);
        if (!c[0]) airborne = t, foot = 0;
        else if (!c[1]) airborne = t, foot = 1;
    }
    ASSERT_GE(airborne, 0) << "a frame with a foot in the air";
    posture::Options options;
    options.pins.push_back({1, foot, airborne, airborne + 0.1});
    options.pins.push_back({7, 0, 0, 1});  // no such character
    const auto frames = posture::simulate(scene, lib, options);
    ASSERT_TRUE(frames) << frames.error().message;
    EXPECT_TRUE(allFinite(frames->world));
    const auto& r = frames->report;
    EXPECT_GT(r.nonFiniteTargets, 0);
    EXPECT_GE(r.initialOverlaps, 1);
    EXPECT_GE(r.refusedPins, 2);
    std::string all;
    for (const auto& n : r.notes) all += n + "\n";
    EXPECT_NE(all.find("non-finite pose"), std::string::npos) << all;
    EXPECT_NE(all.find("inside each other"), std::string::npos) << all;
    EXPECT_NE(all.find("not supported"), std::string::npos) << all;
    EXPECT_NE(all.find("no such person"), std::string::npos) << all;
}

// The solver is a real option (docs/POSTURE.md "Speed"): the direct solver,
// ODE's QuickStep and the hybrid of the two (the default) all give finite
// poses, and different ones; the hybrid solves the duel's fighters directly
// while they are apart and by QuickStep while they touch.
TEST(PostureSolver, SolverIsAnOption) {
    sim::Scene two = exactDuel();
    two.duration = 4.0;
    EXPECT_EQ(posture::Options{}.solver, posture::Solver::Hybrid);
    std::vector<posture::Frames> runs;
    for (const auto solver : {posture::Solver::Direct, posture::Solver::Iterative, posture::Solver::Hybrid}) {
        posture::Options options;
        options.solver = solver;
        auto r = posture::simulate(two, demoWorld().library, options);
        ASSERT_TRUE(r);
        for (const auto& p : r->world.joints[0]) ASSERT_TRUE(std::isfinite(p.x + p.y + p.z));
        const auto& rep = r->report;
        if (solver == posture::Solver::Direct) {
            EXPECT_EQ(rep.iterativeSteps, 0);
        }
        if (solver == posture::Solver::Iterative) {
            EXPECT_EQ(rep.directSteps, 0);
        }
        if (solver == posture::Solver::Hybrid) {
            EXPECT_GT(rep.directSteps, 0);
            EXPECT_GT(rep.iterativeSteps, 0);
        }
        EXPECT_GT(rep.directSteps + rep.iterativeSteps, 0);
        runs.push_back(std::move(*r));
    }
    // Three solvers, three results: the hybrid is neither of the others (the
    // fighters touch in this duel, so both solvers take part in its steps).
    const auto& x = runs[0].world.joints[0];
    for (std::size_t a = 0; a < runs.size(); ++a) {
        ASSERT_EQ(x.size(), runs[a].world.joints[0].size());
        for (std::size_t b = a + 1; b < runs.size(); ++b) {
            EXPECT_NE(0, std::memcmp(runs[a].world.joints[0].data(), runs[b].world.joints[0].data(), x.size() * sizeof(glm::vec3)))
                << a << " " << b;
        }
    }
}

// Calm pairs (Options::calmPairs, on by default): a character with no contact
// with another character takes two substeps as one direct step. On the duel's
// first 4 s both fighters do so in most steps, the poses stay within a
// millimetre of those made with every substep on average (0.07 cm; the
// largest difference, 12 cm at 3.95 s, is the victim's reaction to the first
// blow: a contact amplifies any difference), and QuickStep, or a control
// frequency where a step of 2h would be unstable, takes no calm steps.
TEST(PostureSolver, CalmPairsTakeTwoSubstepsAsOne) {
    sim::Scene two = duel();
    two.duration = 4.0;
    EXPECT_TRUE(posture::Options{}.calmPairs);
    posture::Options on, off;
    off.calmPairs = false;
    const auto a = posture::simulate(two, demoWorld().library, on);
    const auto b = posture::simulate(two, demoWorld().library, off);
    ASSERT_TRUE(a && b);
    EXPECT_GT(a->report.calmSteps, 0);
    EXPECT_EQ(b->report.calmSteps, 0);
    EXPECT_LE(2 * a->report.calmSteps, a->report.directSteps);
    // Most character-steps of these 4 s are calm (pairs of them, counted twice as direct steps).
    EXPECT_GT(2 * a->report.calmSteps, (a->report.directSteps + a->report.iterativeSteps) / 2);
    double sum = 0, worst = 0;
    std::size_t count = 0, worstAt = 0;
    for (std::size_t c = 0; c < 2; ++c) {
        const auto& x = a->world.joints[c];
        const auto& y = b->world.joints[c];
        ASSERT_EQ(x.size(), y.size());
        for (std::size_t k = 0; k < x.size(); ++k) {
            ASSERT_TRUE(std::isfinite(x[k].x + x[k].y + x[k].z));
            const double d = glm::length(glm::dvec3(x[k] - y[k]));
            if (d > worst) worst = d, worstAt = k;
            sum += d, ++count;
        }
    }
    const double mean = sum / static_cast<double>(count);
    const auto joints = static_cast<std::size_t>(a->world.jointCount[0]);
    std::printf("calm pairs against every substep: mean %.3f cm, max %.3f cm (frame %zu); %lld calm of %lld direct steps\n",
                100 * mean, 100 * worst, worstAt / joints, static_cast<long long>(a->report.calmSteps),
                static_cast<long long>(a->report.directSteps));
    EXPECT_GT(mean, 0.0);     // a different integration ...
    EXPECT_LT(mean, 0.005);   // ... of the same motion: under 5 mm on average (0.07 cm)
    posture::Options quick;
    quick.solver = posture::Solver::Iterative;
    const auto q = posture::simulate(two, demoWorld().library, quick);
    ASSERT_TRUE(q);
    EXPECT_EQ(q->report.calmSteps, 0);
    posture::Options stiff;
    stiff.frequency = 30;  // stable at h = 1/240 s, not at 2h
    const auto r = posture::simulate(two, demoWorld().library, stiff);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->report.calmSteps, 0);
}

TEST(PostureSolver, OptionErrorsNameTheField) {
    posture::Options bad;
    bad.frequency = 200;  // unstable at 240 Hz
    const auto r = posture::simulate(duel(), demoWorld().library, bad);
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("frequency"), std::string::npos) << r.error().message;
    posture::Options fps;
    fps.fps = std::numeric_limits<double>::quiet_NaN();
    const auto r2 = posture::simulate(duel(), demoWorld().library, fps);
    ASSERT_FALSE(r2);
    EXPECT_NE(r2.error().message.find("fps"), std::string::npos);
    posture::Options solver;
    solver.solver = static_cast<posture::Solver>(7);
    const auto r3 = posture::simulate(duel(), demoWorld().library, solver);
    ASSERT_FALSE(r3);
    EXPECT_NE(r3.error().message.find("solver"), std::string::npos);
    EXPECT_EQ(posture::parseMode("physics"), posture::Mode::Physics);
    EXPECT_EQ(posture::parseMode("kinematic"), posture::Mode::Kinematic);
    EXPECT_FALSE(posture::parseMode("ragdoll"));
}

}  // namespace

namespace {

// The chase (a planned scene) and the luggage chain (composed): feet and
// pose meet the issue's thresholds, and the porters' bodies stay out of each
// other (< 2 cm). The chase's swinging foot sank 6.75 cm into a neighbour's
// pinned shin at 21.57 s until a touching body's whole limb yielded
// (docs/POSTURE.md); this in-memory chase was left 2.07 cm deep there and
// was asserted below 2.5 cm; since pins move at most 0.5 cm a frame and
// contacts see the real gap (third pass), 0.83 cm: the issue's 2 cm.
TEST(PostureSolver, ChaseAndLuggageKeepFeetAndPose) {
    const auto chase = measure(test::plannedScene(kDemo + "chase.json"));
    record("chase_physics", chase.physics);
    EXPECT_LT(chase.physics.footSkateMaxCm, 1.0);
    EXPECT_LT(chase.physics.footSkateMeanCm, 0.2);
    EXPECT_LT(chase.physics.deviationMeanCm, 3.0);
    EXPECT_LT(chase.physics.penetrationMaxCm, 2.0);

    static const auto patches = test::demoPatches({"carry-walk-hand-receive-turn-carry", "carry-hand-receive-carry"});
    sim::ComposeSpec spec = sim::ComposeSpec::of(sim::LuggageSpec{.porters = 4, .handoffs = 9});
    spec.seed = 1;
    spec.duration = 300;
    auto scene = sim::compose(demoWorld().library, patches, spec);
    ASSERT_TRUE(scene) << scene.error().message;
    const auto luggage = measure(*scene);
    record("luggage_physics", luggage.physics);
    EXPECT_GT(luggage.kinematic.footSkateMaxCm, 1.0);
    EXPECT_LT(luggage.physics.footSkateMaxCm, 1.0);
    EXPECT_LT(luggage.physics.footSkateMeanCm, 0.2);
    EXPECT_LT(luggage.physics.deviationMeanCm, 3.0);
    EXPECT_LT(luggage.physics.penetrationMaxCm, 2.0);
}

// The README's domino crowd and rat crowd (resources/demo/domino.json,
// rat.json), composed in memory: the issue's thresholds with physics.
// The domino crowd starts with bodies inside each other (the solver
// separates them before the first frame); its falls and the rat crowd's
// bumps are body blows (docs/POSTURE.md).
TEST(PostureSolver, DominoCrowdMeetsTheIssueThresholds) {
    static const auto patches = test::demoPatches({"fall-fall"});
    auto spec = sim::parseComposeSpec(test::readText(kDemo + "domino.json"), "domino.json", patches);
    ASSERT_TRUE(spec) << spec.error().message;
    // resources/demo/domino_floor.png (200 x 120 pixels of 0.1 m from (-10, -6)):
    // a disc of 40 pixels round pixel (50.5, 60.5) and the rectangle of pixels
    // x 110-189, y 40-79 painted (the CLI reads the PNG; the core does not).
    auto* domino = spec->part<sim::DominoSpec>();
    ASSERT_NE(domino, nullptr);
    domino->floor.width = 200;
    domino->floor.height = 120;
    domino->floor.metresPerPixel = 0.1;
    domino->floor.origin = {-10.0f, -6.0f};
    domino->floor.painted.assign(200 * 120, 0);
    for (int y = 0; y < 120; ++y) {
        for (int x = 0; x < 200; ++x) {
            const double dx = x + 0.5 - 50.5, dy = y + 0.5 - 60.5;
            const bool disc = dx * dx + dy * dy < 1600.0;
            const bool rect = x >= 110 && x <= 189 && y >= 40 && y <= 79;
            domino->floor.painted[static_cast<std::size_t>(y * 200 + x)] = disc || rect ? 1 : 0;
        }
    }
    auto composed = sim::compose(demoWorld().library, patches, *spec);
    ASSERT_TRUE(composed) << composed.error().message;
    const sim::Scene scene = std::move(*composed);
    const auto both = measure(scene);
    record("kinematic", both.kinematic);
    record("physics", both.physics);
    ASSERT_GT(both.physics.landed, 10);
    // Every threshold of the issue. Before, two were missed and chaotic (skate
    // 0.98-1.49 cm, 34-35 of 36 hits on the surface, with the build): a victim's
    // planted foot pressed by the faller broke its pin, and blows stopped 1-2 cm
    // short where grown collision boxes met edge to edge (docs/POSTURE.md,
    // "Domino crowd, third pass"). Now 0.61 cm and 36 of 36 here.
    expectThresholds(both.physics, "domino");
    EXPECT_GE(both.report.initialOverlaps, 1);  // separated before the first frame
    EXPECT_GT(both.kinematic.penetrationMaxCm, 2.0);
}

TEST(PostureSolver, RatCrowdMeetsTheIssueThresholds) {
    const auto scene = test::composedScene(kDemo + "rat.json", sim::PatchLibrary{});
    const auto both = measure(scene);
    record("kinematic", both.kinematic);
    record("physics", both.physics);
    ASSERT_GT(both.physics.landed, 0);
    expectThresholds(both.physics, "rat");
    EXPECT_GT(both.kinematic.penetrationMaxCm, 2.0);
}

}  // namespace

namespace {

// Hard constraints on the luggage (issue 25): while a porter holds the bag
// (its captured hands' midpoint within 3 cm of the bag's centre, so not while
// the bag passes between two porters), each hand stays where it took hold of
// it, in the bag's frame, as the bag moves; the captured hands drift on it,
// and the physics hands without the pins more.
TEST(PostureSolver, HandsStayOnTheLuggage) {
    const auto& lib = demoWorld().library;
    static const auto patches = test::demoPatches({"carry-walk-hand-receive-turn-carry", "carry-hand-receive-carry"});
    sim::ComposeSpec spec = sim::ComposeSpec::of(sim::LuggageSpec{.porters = 4, .handoffs = 9});
    spec.seed = 1;
    spec.duration = 300;
    auto composed = sim::compose(lib, patches, spec);
    ASSERT_TRUE(composed) << composed.error().message;
    sim::Scene scene = std::move(*composed);
    scene.duration = std::min(scene.duration, 40.0);
    int bag = -1;
    for (std::size_t i = 0; i < scene.characters.size(); ++i) {
        if (scene.characters[i].body == "bag") bag = static_cast<int>(i);
    }
    ASSERT_GE(bag, 0);
    posture::Options on, off;
    on.handPins = true;
    const auto pinned = posture::simulate(scene, lib, on);
    const auto free = posture::simulate(scene, lib, off);
    ASSERT_TRUE(pinned && free);
    const auto captured = sim::kinematicTracks(scene, lib, 60);
    const auto& sc = scene.characters[static_cast<std::size_t>(bag)];
    auto local = [&](double t, const glm::vec3& p) {  // p in the bag's frame
        const sim::RootXf at = sim::creatureAt(sc, t);
        const glm::vec2 f = sim::headingVector(at.heading);
        const glm::vec3 d = p - glm::vec3(at.pos.x, sim::creatureHeightAt(sc, t), at.pos.y);
        const glm::vec3 along(f.x, 0, f.y), side = glm::cross(glm::vec3(0, 1, 0), along);
        return glm::vec3(glm::dot(d, side), d.y, glm::dot(d, along));
    };
    // The largest drift of a holder's hand on the bag over a hold (cm), and the frames held.
    auto drift = [&](const sim::JointTracks& shown, int& held) {
        double worst = 0;
        held = 0;
        for (int c = 0; c < bag; ++c) {
            const auto& j = lib.motion(lib.action(scene.characters[static_cast<std::size_t>(c)].track[0].action).motion).joints;
            std::array<glm::vec3, 2> grip{};
            int since = 0;  // frames into the hold (the solver takes hold at a frame's start: the grip is read one frame in)
            for (int f = 1; f < shown.frames; ++f) {
                const double t = f / 60.0;
                const auto k = captured.at(c, f);
                const glm::vec3 mid = 0.5f * (k[static_cast<std::size_t>(j.leftHand)] + k[static_cast<std::size_t>(j.rightHand)]);
                const bool now = scene.present(c, t) && glm::length(local(t, mid) - glm::vec3(0, 0, 0.5f * sim::kBagLength)) < 0.03f;
                since = now ? since + 1 : 0;
                const auto p = shown.at(c, f);
                const std::array<glm::vec3, 2> hands{local(t, p[static_cast<std::size_t>(j.leftHand)]), local(t, p[static_cast<std::size_t>(j.rightHand)])};
                if (since == 2) grip = hands;
                if (since > 2) {
                    ++held;
                    for (int h = 0; h < 2; ++h) {
                        const double d = 100.0 * static_cast<double>(glm::length(hands[static_cast<std::size_t>(h)] - grip[static_cast<std::size_t>(h)]));
                        worst = std::max(worst, d);
                    }
                }
            }
        }
        return worst;
    };
    int heldPinned = 0, heldFree = 0, heldCaptured = 0;
    const double a = drift(pinned->world, heldPinned), b = drift(free->world, heldFree), k = drift(captured, heldCaptured);
    std::printf("hands on the bag: drift over a hold %.2f cm pinned, %.2f cm without the pins, %.2f cm captured; %d hand frames held\n",
                a, b, k, heldPinned);
    std::printf("pins refused %d, released %d\n", pinned->report.refusedPins, pinned->report.releasedPins);
    for (const auto& n : pinned->report.notes) std::printf("  %s\n", n.c_str());
    RecordProperty("hand_drift_pinned_cm", std::to_string(a));
    RecordProperty("hand_drift_free_cm", std::to_string(b));
    EXPECT_GT(heldPinned, 600) << "porters hold the bag for most of the scene";
    // Pinned, a hand slips a little where the pins of both feet and both
    // hands close a loop through the body (2.9 cm at most here, docs/POSTURE.md).
    EXPECT_LT(a, 4.0);
    EXPECT_GT(b, 3.0 * a);
    EXPECT_GT(k, 3.0 * a) << "the captured hands drift on the bag more than the pinned ones";
    EXPECT_TRUE(allFinite(pinned->world));
}

}  // namespace

// posture::ScenePoses, what render, export and fray-play read: the solver's
// frames at their times, linear in between, clamped outside the scene; the
// local poses rebuild the same joints; kinematic mode is the scene poser's;
// cancel stops it.
TEST(PostureScenePoses, FramesAtAnyTimeLocalPosesAndCancel) {
    const auto& lib = demoWorld().library;
    sim::Scene scene = duel();
    scene.duration = 3.0;
    const auto frames = posture::simulate(scene, lib);
    ASSERT_TRUE(frames) << frames.error().message;
    auto poses = posture::ScenePoses::make(posture::Mode::Physics, scene, lib);
    ASSERT_TRUE(poses) << poses.error().message;
    EXPECT_EQ(poses->mode(), posture::Mode::Physics);
    std::vector<glm::vec3> pos, fkPos;
    std::vector<glm::quat> rot, fkRot;
    const int last = frames->world.frames - 1;
    for (int c = 0; c < 2; ++c) {
        for (int f : {0, 10, 90, last}) {
            poses->world(c, f / 60.0, pos, rot);
            const auto want = frames->world.at(c, f);
            ASSERT_EQ(pos.size(), want.size());
            for (std::size_t j = 0; j < pos.size(); ++j) EXPECT_EQ(pos[j], want[j]) << "character " << c << " frame " << f;
        }
        // Half way between frames 10 and 11.
        poses->world(c, 10.5 / 60.0, pos, rot);
        for (std::size_t j = 0; j < pos.size(); ++j) {
            const glm::vec3 mid = 0.5f * (frames->world.at(c, 10)[j] + frames->world.at(c, 11)[j]);
            EXPECT_LT(glm::length(pos[j] - mid), 1e-5f);
        }
        // Outside the scene: its ends.
        poses->world(c, -5.0, pos, rot);
        EXPECT_EQ(pos[0], frames->world.at(c, 0)[0]);
        poses->world(c, 99.0, pos, rot);
        EXPECT_EQ(pos[0], frames->world.at(c, last)[0]);
        poses->world(c, std::numeric_limits<double>::quiet_NaN(), pos, rot);
        EXPECT_TRUE(std::isfinite(pos[0].x));
        // The local pose rebuilds the joints (segment lengths kept by the
        // ball joints to well under a centimetre).
        Pose local;
        poses->pose(c, 1.5, local);
        poses->world(c, 1.5, pos, rot);
        const auto& sk = poses->skeleton(c);
        fkPos.resize(pos.size());
        fkRot.resize(pos.size());
        forwardKinematics(sk, local.translations, local.rotations, fkPos, fkRot);
        for (std::size_t j = 0; j < pos.size(); ++j) EXPECT_LT(glm::length(fkPos[j] - pos[j]), 0.01f) << sk.names[j];
    }
    // Kinematic: the scene poser's poses.
    auto kin = posture::ScenePoses::make(posture::Mode::Kinematic, scene, lib);
    ASSERT_TRUE(kin);
    const sim::ScenePoser poser(scene, lib);
    Pose a, b;
    kin->pose(1, 2.25, a);
    poser.pose(1, 2.25, b);
    EXPECT_EQ(a.translations, b.translations);
    EXPECT_EQ(a.rotations, b.rotations);
    // Cancelled through progress.
    const auto stopped = posture::ScenePoses::make(posture::Mode::Physics, scene, lib, {},
                                                   [](double f, std::string_view) { return f < 0.3; });
    ASSERT_FALSE(stopped);
    EXPECT_TRUE(stopped.error().isCancelled());
}

// Parry (SPEC 5): before an unblocked blow on a defender who is not attacking,
// the defender's forearm nearer to the striking segment moves towards it.
TEST(PostureSolver, ParryMovesTheFreeForearmTowardsTheBlow) {
    const auto& lib = demoWorld().library;
    sim::Scene scene = exactDuel();
    const sim::HitEvent* hit = nullptr;
    for (const auto& h : scene.hits) {
        const int inst = scene.instanceAt(h.defender, h.time);
        if (h.blocked || inst < 0) continue;
        const auto& track = scene.characters[static_cast<std::size_t>(h.defender)].track;
        if (lib.action(track[static_cast<std::size_t>(inst)].action).is(sim::kAttack)) continue;
        hit = &h;
        break;
    }
    ASSERT_NE(hit, nullptr) << "an unblocked blow on a defender who is not attacking";
    scene.duration = std::min(scene.duration, hit->time + 0.3);
    posture::Options on, off;
    off.parry = false;
    const auto withParry = posture::simulate(scene, lib, on);
    const auto without = posture::simulate(scene, lib, off);
    ASSERT_TRUE(withParry && without);
    // The striking segment where the capture has it 0.1 s before the blow.
    const int frame = static_cast<int>(std::lround((hit->time - 0.1) * 60.0));
    const auto& sj = lib.motion(lib.action(scene.characters[static_cast<std::size_t>(hit->attacker)].track[0].action).motion).joints;
    const auto& dj = lib.motion(lib.action(scene.characters[static_cast<std::size_t>(hit->defender)].track[0].action).motion).joints;
    const auto strike = sim::segmentBoxes(without->world.at(hit->attacker, frame), sj)[static_cast<std::size_t>(hit->effector)].centre;
    auto nearest = [&](const posture::Frames& f) {
        const auto p = f.world.at(hit->defender, frame);
        return std::min(glm::length(strike - p[static_cast<std::size_t>(dj.leftHand)]),
                        glm::length(strike - p[static_cast<std::size_t>(dj.rightHand)]));
    };
    const float a = nearest(*withParry), b = nearest(*without);
    std::printf("hit at %.2f s: nearest hand to the striking segment %.1f cm with parry, %.1f cm without\n", hit->time,
                100.0 * static_cast<double>(a), 100.0 * static_cast<double>(b));
    EXPECT_LT(a, b - 0.02f);
    EXPECT_TRUE(allFinite(withParry->world));
}

namespace {

// Where the carrying hand holds the ball shown at t (ScenePoses), and that hand.
std::pair<glm::vec3, glm::vec3> gripAndHand(const posture::ScenePoses& poses, const sim::Scene& scene, int ball, double t) {
    const auto& lib = test::footballWorld().library;
    const auto& b = scene.characters[static_cast<std::size_t>(ball)];
    const auto& joints = lib.motion(lib.actions()[static_cast<std::size_t>(scene.characters[static_cast<std::size_t>(b.holder)].track.front().action)].motion).joints;
    std::vector<glm::vec3> p;
    std::vector<glm::quat> r;
    poses.world(ball, t, p, r);
    EXPECT_EQ(p.size(), 1u);
    const glm::vec3 grip = p[0] + r[0] * glm::vec3(0, 0, 0.5f * sim::kBallLength + sim::kBallTuck);
    poses.world(b.holder, t, p, r);
    return {grip, p[static_cast<std::size_t>(b.hand == 0 ? joints.leftHand : joints.rightHand)]};
}

// Issue 25 item 2: a football carrier's arm holds the ball. The composed run
// has a ball in the carrier's right hand; its grip stays within 5 cm of the
// hand on average and 10 cm at worst (a hand is about 10 cm long: a ball
// farther than that is out of the hand) in both postures, against the ball
// shown and, with physics, against the ball as keyed (the soft constraint
// holds the physics hand there); at times between frames too; and the
// issue's thresholds still hold on the football run with physics.
TEST(PostureSolver, FootballCarrierHoldsTheBall) {
    const auto& scene = football();
    const auto& lib = test::footballWorld().library;
    int ball = -1;
    for (std::size_t i = 0; i < scene.characters.size(); ++i) {
        if (scene.characters[i].body == "ball") ball = static_cast<int>(i);
    }
    ASSERT_GE(ball, 0);
    const auto& b = scene.characters[static_cast<std::size_t>(ball)];
    ASSERT_EQ(b.holder, 0);
    EXPECT_EQ(scene.characters[0].name, "carrier");
    EXPECT_EQ(b.hand, 1);
    const auto both = measure(scene, {}, lib);
    record("kinematic", both.kinematic);
    record("physics", both.physics);
    expectThresholds(both.physics, "football");
    for (const auto* m : {&both.kinematic, &both.physics}) {
        ASSERT_EQ(m->balls.size(), 1u);
        const auto& h = m->balls[0];
        EXPECT_EQ(h.holder, "carrier");
        EXPECT_GT(h.frames, 600);  // the whole run at 60 fps
        EXPECT_LT(h.keyedMeanCm, 5.0);
        EXPECT_LT(h.keyedMaxCm, 10.0);
        testing::Test::RecordProperty(m == &both.kinematic ? "kinematic_ball_max_cm" : "physics_ball_keyed_max_cm",
                                      std::to_string(h.keyedMaxCm));
    }
    // The ball shown between frames: at the hand of the pose shown, in either mode.
    for (const auto mode : {posture::Mode::Kinematic, posture::Mode::Physics}) {
        auto poses = posture::ScenePoses::make(mode, scene, lib);
        ASSERT_TRUE(poses) << poses.error().message;
        for (const double t : {0.51, 3.333, 7.77, 12.345}) {
            const auto [grip, hand] = gripAndHand(*poses, scene, ball, t);
            EXPECT_LT(glm::length(grip - hand), 0.02f) << posture::modeName(mode) << " at " << t << " s";
        }
    }
    // The ball's keys survive the scene file: it stores the hold, and the
    // reader places the ball from the carrier as the composer did.
    const std::string text = sim::sceneToJson(scene, lib);
    EXPECT_TRUE(b.held());
    EXPECT_NE(text.find("\"version\": 3"), std::string::npos);
    EXPECT_NE(text.find("\"held\": ["), std::string::npos);
    auto back = sim::sceneFromJson(text, "f.frayscene", lib);
    ASSERT_TRUE(back) << back.error().message;
    const auto& kb = back->characters[static_cast<std::size_t>(ball)];
    EXPECT_GT(kb.keys.size(), 300u);  // 1/30 s over the run
    EXPECT_EQ(kb.keys, b.keys);
    EXPECT_EQ(kb.holder, b.holder);
    EXPECT_EQ(kb.hand, b.hand);
    EXPECT_EQ(kb.heldFrom, b.heldFrom);
    EXPECT_EQ(kb.heldTo, b.heldTo);
    EXPECT_EQ(sim::sceneToJson(*back, lib), text);
    // A file of before version 3 stores every key: it loads as stored, and a
    // ball held with keys before and after its hold keeps those.
    {
        sim::Scene old = scene;
        auto& ob = old.characters[static_cast<std::size_t>(ball)];
        ob.heldTo = -1;
        const std::string oldText = sim::sceneToJson(old, lib);
        EXPECT_NE(oldText.find("\"version\": 1"), std::string::npos);
        EXPECT_GT(oldText.size(), text.size() + 100 * ob.keys.size());
        auto loaded = sim::sceneFromJson(oldText, "old.frayscene", lib);
        ASSERT_TRUE(loaded) << loaded.error().message;
        EXPECT_EQ(loaded->characters[static_cast<std::size_t>(ball)].keys, b.keys);
        EXPECT_FALSE(loaded->characters[static_cast<std::size_t>(ball)].held());
        // Held over part of the run: the keys outside the hold stay, those
        // in it are the carrier's again (their times from the hold's start:
        // the same up to rounding).
        sim::Scene partly = scene;
        auto& pb = partly.characters[static_cast<std::size_t>(ball)];
        pb.heldFrom = pb.keys[10].time, pb.heldTo = pb.keys[pb.keys.size() - 11].time;
        sim::placeHeldBalls(partly, lib);
        ASSERT_EQ(pb.keys.size(), b.keys.size());
        for (std::size_t k = 0; k < b.keys.size(); ++k) {
            const auto &x = pb.keys[k], &y = b.keys[k];
            if (k < 10 || k > b.keys.size() - 11) {
                EXPECT_EQ(x, y) << k;
            }
            EXPECT_NEAR(x.time, y.time, 1e-12) << k;
            EXPECT_LT(glm::length(x.at.pos - y.at.pos) + std::abs(x.height - y.height) + std::abs(x.pitch - y.pitch), 1e-5f) << k;
            EXPECT_NEAR(x.at.heading, y.at.heading, 1e-5) << k;
        }
        const std::string partText = sim::sceneToJson(partly, lib);
        auto again = sim::sceneFromJson(partText, "p.frayscene", lib);
        ASSERT_TRUE(again) << again.error().message;
        EXPECT_EQ(again->characters[static_cast<std::size_t>(ball)].keys, pb.keys);
        EXPECT_EQ(sim::sceneToJson(*again, lib), partText);
    }
    // Bad holds are named: a hold in an older version, a key inside the
    // hold, a holder that cannot hold, a hold out of range.
    auto refused = [&](const std::string& from, const std::string& to, const std::string& message) {
        std::string t = text;
        const auto at = t.find(from);
        ASSERT_NE(at, std::string::npos) << from;
        t.replace(at, from.size(), to);
        auto r = sim::sceneFromJson(t, "f.frayscene", lib);
        ASSERT_FALSE(r) << to;
        EXPECT_NE(r.error().message.find("f.frayscene: /characters/" + std::to_string(ball) + message), std::string::npos) << r.error().message;
    };
    refused("\"version\": 3", "\"version\": 2", "/held: held bodies need scene version 3");
    const std::size_t heldAt = text.find("\"held\": [");
    const std::string held = text.substr(heldAt, text.find(']', heldAt) + 1 - heldAt);
    refused(held, "\"keys\": [[1.0, 0, 0, 0]], " + held, "/keys/0/0: a key inside the hold");
    refused("\"holder\": 0", "\"holder\": " + std::to_string(ball), "/holder: character " + std::to_string(ball) + " cannot hold it");
    refused(held, "\"held\": [-1, 2]", "/held/0: must be in [0, 3600] s");
    refused(held, "\"held\": [1e9, 1e9]", "/held/0: must be in [0, 3600] s");
    refused(held, "\"held\": [3, 2]", "/held/1: must be in [from, 3600] s");
    refused(held, "\"held\": [3000, 4000]", "/held/1: must be in [from, 3600] s");
    refused(held, "\"held\": [0, 1, 2]", "/held: must be [from, to]");
    // Holds that would make more than sim::kMaxHeldKeys keys (an hour's hold
    // is 108,001 keys) are refused before any is made.
    {
        sim::Scene many = scene;
        many.duration = 3600;
        auto hour = many.characters[static_cast<std::size_t>(ball)];
        hour.heldTo = 3600;
        hour.keys.clear();
        many.characters.resize(static_cast<std::size_t>(ball));
        for (int k = 0; k < 40; ++k) many.characters.push_back(hour);
        const std::int64_t fit = sim::kMaxHeldKeys / sim::heldKeyCount(0, 3600);
        auto r = sim::sceneFromJson(sim::sceneToJson(many, lib), "m.frayscene", lib);
        ASSERT_FALSE(r);
        EXPECT_NE(r.error().message.find("m.frayscene: /characters/" + std::to_string(ball + fit) +
                                         "/held: the held bodies would make more than 4000000 keys"),
                  std::string::npos)
            << r.error().message;
    }
    // A bad holder or hand is named.
    std::string bad = text;
    bad.replace(bad.find("\"holder\": 0"), 11, "\"holder\": 99");
    auto broken = sim::sceneFromJson(bad, "f.frayscene", lib);
    ASSERT_FALSE(broken);
    EXPECT_NE(broken.error().message.find("f.frayscene: /characters/" + std::to_string(ball) + "/holder: must be a character index"),
              std::string::npos)
        << broken.error().message;
    bad = text;
    bad.replace(bad.find("\"hand\": \"right\""), 15, "\"hand\": \"both\"");
    broken = sim::sceneFromJson(bad, "f.frayscene", lib);
    ASSERT_FALSE(broken);
    EXPECT_NE(broken.error().message.find("/hand: must be"), std::string::npos) << broken.error().message;
}

// A carrier whose hand is pinned to its ball (--hand-pins) is never calm
// (calm pairs step a character alone by 2h, its pins moved once): alone
// with its ball it takes no calm step with the pin, and does without it.
TEST(PostureSolver, BallPinnedHandIsNeverCalm) {
    const auto& full = football();
    sim::Scene scene = full;
    scene.characters.clear(), scene.hits.clear(), scene.catches.clear();
    scene.characters.push_back(full.characters[0]);
    for (const auto& c : full.characters) {
        if (c.body == "ball" && c.holder == 0) scene.characters.push_back(c);
    }
    ASSERT_EQ(scene.characters.size(), 2u);
    scene.characters[1].holder = 0;
    scene.duration = 3.0;
    const auto& lib = test::footballWorld().library;
    posture::Options soft, pinned;
    pinned.handPins = true;
    auto free = posture::simulate(scene, lib, soft);
    auto held = posture::simulate(scene, lib, pinned);
    ASSERT_TRUE(free && held);
    EXPECT_GT(free->report.calmSteps, 100);
    EXPECT_EQ(held->report.calmSteps, 0);
}

// With --hand-pins the carrying hand is also pinned to the ball: it holds it
// within half a centimetre (much closer than the soft constraint alone), and the thresholds still hold.
TEST(PostureSolver, FootballBallWithHandPins) {
    posture::Options pinned;
    pinned.handPins = true;
    const auto both = measure(football(), pinned, test::footballWorld().library);
    expectThresholds(both.physics, "football, hand pins");
    ASSERT_EQ(both.physics.balls.size(), 1u);
    // Held within half a centimetre (0.07 / 0.12 cm measured; 1.35 / 2.65 cm
    // while a pinned carrier was stepped as calm).
    EXPECT_LT(both.physics.balls[0].keyedMeanCm, 0.5);
    EXPECT_LT(both.physics.balls[0].keyedMaxCm, 1.0);
}

}  // namespace
