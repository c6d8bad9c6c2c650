// Temporal tree expansion (SPEC 2): geometry, the action library, the
// planner's rules, the scene file and the metrics, on the demo project.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

#include <tbb/task_arena.h>

#include "fray/sim/geometry.h"
#include "fray/sim/metrics.h"
#include "fray/sim/scene.h"
#include "sim_fixture.h"

namespace fray::sim {
namespace {

using test::demoWorld;
using test::duelSpec;
using test::parseSpec;
using test::runSpec;

TEST(SimGeometry, RootXfComposeAndInverse) {
    const RootXf a{{1.0f, 2.0f}, 0.7};
    const RootXf b{{-0.5f, 0.25f}, -2.0};
    const RootXf ab = a * b;
    const RootXf back = a.inverse() * ab;
    EXPECT_NEAR(back.pos.x, b.pos.x, 1e-5);
    EXPECT_NEAR(back.pos.y, b.pos.y, 1e-5);
    EXPECT_NEAR(wrapAngle(back.heading - b.heading), 0.0, 1e-9);
    // Heading h faces headingVector(h): (0, 1) in the local frame.
    const glm::vec2 f = RootXf{{0, 0}, 0.5}.apply(glm::vec2(0, 1)) ;
    EXPECT_NEAR(f.x, std::sin(0.5), 1e-6);
    EXPECT_NEAR(f.y, std::cos(0.5), 1e-6);
    EXPECT_NEAR(angleOf(headingVector(2.5)), 2.5, 1e-6);
}

TEST(SimGeometry, ObbSeparatingAxes) {
    Obb a;
    a.half = {0.5f, 0.5f, 0.5f};
    Obb b = a;
    b.centre = {0.99f, 0, 0};
    EXPECT_TRUE(overlaps(a, b));
    b.centre = {1.01f, 0, 0};
    EXPECT_FALSE(overlaps(a, b));
    // Rotated 45 degrees about Y: its corner reaches sqrt(2)/2 from its centre.
    const float c = std::cos(std::numbers::pi_v<float> / 4), s = std::sin(std::numbers::pi_v<float> / 4);
    b.axes = glm::mat3(glm::vec3(c, 0, -s), glm::vec3(0, 1, 0), glm::vec3(s, 0, c));
    b.centre = {1.15f, 0, 0};
    EXPECT_TRUE(overlaps(a, b));
    b.centre = {1.25f, 0, 0};
    EXPECT_FALSE(overlaps(a, b));
    // Two thin crossed sticks apart in depth only separate along an edge-edge axis.
    Obb x = segmentBox({-1, 0, 0}, {1, 0, 0}, 0.05f, 0.05f, 0.0f, {0, 1, 0});
    Obb z = segmentBox({0, 0.2f, -1}, {0, 0.0f, 1}, 0.05f, 0.05f, 0.0f, {0, 1, 0});
    EXPECT_TRUE(overlaps(x, z));
    z = segmentBox({0, 0.3f, -1}, {0, 0.3f, 1}, 0.05f, 0.05f, 0.0f, {0, 1, 0});
    EXPECT_FALSE(overlaps(x, z));
}

// The separating-axis test as it was written first (every product of the
// axes, then a's faces, b's faces and the edges in order), for comparing.
static bool overlapsInFifteenSteps(const Obb& a, const Obb& b) {
    const glm::vec3 d = b.centre - a.centre;
    float R[3][3], absR[3][3];
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            R[i][j] = glm::dot(a.axes[i], b.axes[j]);
            absR[i][j] = std::fabs(R[i][j]) + 1e-6f;
        }
    }
    const float t[3] = {glm::dot(d, a.axes[0]), glm::dot(d, a.axes[1]), glm::dot(d, a.axes[2])};
    const float ah[3] = {a.half.x, a.half.y, a.half.z}, bh[3] = {b.half.x, b.half.y, b.half.z};
    for (int i = 0; i < 3; ++i) {
        if (std::fabs(t[i]) > ah[i] + bh[0] * absR[i][0] + bh[1] * absR[i][1] + bh[2] * absR[i][2]) return false;
    }
    for (int j = 0; j < 3; ++j) {
        const float ra = ah[0] * absR[0][j] + ah[1] * absR[1][j] + ah[2] * absR[2][j];
        if (std::fabs(t[0] * R[0][j] + t[1] * R[1][j] + t[2] * R[2][j]) > ra + bh[j]) return false;
    }
    for (int i = 0; i < 3; ++i) {
        const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
        for (int j = 0; j < 3; ++j) {
            const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
            const float ra = ah[i1] * absR[i2][j] + ah[i2] * absR[i1][j];
            const float rb = bh[j1] * absR[i][j2] + bh[j2] * absR[i][j1];
            if (std::fabs(t[i2] * R[i1][j] - t[i1] * R[i2][j]) > ra + rb) return false;
        }
    }
    return true;
}

// The planner's penetration test asks for a box's axes only when a test
// needs them, a's depth axis first: the same answer as the fifteen steps in
// their first order, for boxes placed on the floor as the planner places
// them (segment boxes like the core body's, near enough that the bounding
// spheres meet).
TEST(SimGeometry, LazyAxesAnswerAsTheFifteenSteps) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    auto point = [&](float spread) { return glm::vec3(spread * u(rng), 1.0f + 0.5f * u(rng), spread * u(rng)); };
    int overlapping = 0, apart = 0;
    for (int n = 0; n < 20000; ++n) {
        const glm::vec3 p0 = point(0.3f), p1 = p0 + 0.4f * glm::vec3(u(rng), u(rng), u(rng));
        const Obb local = segmentBox(p0, p1, 0.05f + 0.1f * std::fabs(u(rng)), 0.05f + 0.1f * std::fabs(u(rng)), 0.02f,
                                     glm::vec3(u(rng), 0, u(rng)));
        const glm::vec3 q0 = point(0.3f), q1 = q0 + 0.4f * glm::vec3(u(rng), u(rng), u(rng));
        const Obb b = segmentBox(q0, q1, 0.05f + 0.1f * std::fabs(u(rng)), 0.05f + 0.1f * std::fabs(u(rng)), 0.02f,
                                 glm::vec3(u(rng), 0, u(rng)));
        const RootXf xf{{0.2f * u(rng), 0.2f * u(rng)}, 3.0 * static_cast<double>(u(rng))};
        const FloorRotation rotate(xf.heading);
        const Obb placed = local.placed(xf, rotate);
        const bool expected = overlapsInFifteenSteps(placed, b);
        EXPECT_EQ(overlapsBeyondSpheres(placed, b), expected) << n;
        std::array<glm::vec3, 3> axes;
        unsigned asked = 0;
        const bool lazy = overlapsBeyondSpheresWith(
            local.placedCentre(xf, rotate),
            [&](int i) -> const glm::vec3& {
                const auto k = static_cast<std::size_t>(i);
                if (!(asked >> k & 1u)) axes[k] = rotate(local.axes[i]), asked |= 1u << k;
                return axes[k];
            },
            local.half, b);
        EXPECT_EQ(lazy, expected) << n;
        (expected ? overlapping : apart) += 1;
    }
    // Both answers are common.
    EXPECT_GT(overlapping, 1000);
    EXPECT_GT(apart, 1000);
}

TEST(SimLibrary, ActionsTracksAndAttacks) {
    const auto& w = demoWorld();
    const auto& lib = w.library;
    ASSERT_EQ(lib.size(), static_cast<int>(sim::projectActionRefs(w.project).size()));
    int attacks = 0, variants = 0;
    for (int i = 0; i < lib.size(); ++i) {
        const auto& a = lib.actions()[static_cast<std::size_t>(i)];
        EXPECT_GT(a.duration, 0.0);
        EXPECT_EQ(a.sampleCount, static_cast<int>(std::floor(a.duration * kSampleRate)) + 1);
        // The first sample is the action's own placement.
        const RootXf r0 = lib.rootAt(i, 0.0);
        EXPECT_NEAR(glm::length(r0.pos), 0.0f, 1e-4f) << a.label();
        EXPECT_NEAR(r0.heading, 0.0, 1e-4) << a.label();
        EXPECT_LT(glm::length(a.end.pos), 4.0f) << a.label();
        if (a.is(kAttack)) {
            ++attacks;
            EXPECT_GE(a.effector, 0) << a.label();
            EXPECT_LT(a.activeBegin, a.activeEnd) << a.label();
            EXPECT_GT(a.peakSpeed, 2.0) << a.label();
        }
        variants = std::max(variants, lib.variantClass()[static_cast<std::size_t>(i)] + 1);
    }
    EXPECT_GT(attacks, 100);
    EXPECT_LT(variants, lib.size() / 2);  // the demo repeats every action kind many times
    EXPECT_FALSE(lib.reactions().empty());
    // A jab's fist travels forward (+Z in its own frame) during its active window.
    const auto jabs = lib.select("jab");
    ASSERT_FALSE(jabs.empty());
    const auto& jab = lib.actions()[static_cast<std::size_t>(jabs.front())];
    const Obb fist = lib.boxesAt(jabs.front(), jab.activeEnd - 1)[jab.effector];
    EXPECT_GT(fist.centre.z, 0.3f);
}

TEST(SimSpec, BadInputNamesTheField) {
    auto expectError = [](const std::string& json, const std::string& fragment) {
        auto r = parseSpec(json);
        ASSERT_FALSE(r.ok()) << json;
        EXPECT_NE(r.error().message.find(fragment), std::string::npos) << r.error().message;
        EXPECT_EQ(r.error().message.rfind("spec.json:", 0), 0u) << r.error().message;
    };
    expectError(R"({"duration": 5, "characters": [{"name": "a", "actions": ["@kik"]}]})",
                "/characters/0/actions/0: unknown annotation 'kik'");
    expectError(R"({"duration": 5, "characters": [{"name": "a", "actions": ["@pushed"]}]})",
                "/characters/0/actions: character 'a' has no usable action");
    expectError(R"({"duration": -2, "characters": [{"name": "a"}]})", "/duration: must be a positive");
    expectError(R"({"duration": 5, "characters": [{"name": "a", "preset": "brawler"}]})", "unknown preset 'brawler'");
    expectError(R"({"duration": 5, "characters": [{"name": "a", "dept": 3}]})", "/characters/0/dept: unknown field");
    expectError(R"({"duration": 5, "characters": [{"name": "a", "weights": {"w_tehta": 1}}]})",
                "/characters/0/weights/w_tehta: unknown weight");
    expectError(R"({"duration": 5, "characters": [{"name": "a", "motions": ["nope"]}]})", "no motion 'nope'");
    expectError(R"({"duration": 5, "characters": [{"name": "a", "opponent": "b"}]})", "no character is named 'b'");
    expectError(R"({"duration": 5, "characters": [{"name": "a", "depth": 0}]})", "/characters/0/depth");
    expectError("{not json", "spec.json:1:3: not valid JSON");  // line and column (issue 21)
    expectError(R"({"duration": 5, "characters": [{"name": "a", "path": [{"x": 1}]}]})", "/characters/0/path/0/z: missing");
    expectError(R"({"duration": 5, "arena": {"radius": 0.5}, "characters": [{"name": "a"}]})", "/arena/radius: must be at least 1 m");
    expectError(R"({"duration": 5, "arena": {"radius": 5, "r": 2}, "characters": [{"name": "a"}]})", "/arena/r: unknown field");
    expectError(R"({"duration": 5, "arena": {"x": 0}, "characters": [{"name": "a"}]})", "/arena/radius: missing");
    expectError(R"({"duration": 5, "arena": 4, "characters": [{"name": "a"}]})", "/arena: must be {x, z, radius}");
    expectError(R"({"duration": 5, "arena": {"x": 10, "radius": 3}, "characters": [{"name": "a"}]})",
                "/characters/0/start: 'a' starts 10.00 m from the arena's centre, outside its radius of 3.00 m");
    expectError(R"({"duration": 5, "leaf_budget": 10, "characters": [{"name": "a"}]})", "/leaf_budget: must be an integer from 1000");
    expectError(R"({"duration": 5, "leaf_budget": 2.5e3, "characters": [{"name": "a"}]})", "/leaf_budget: must be an integer");
    auto budget = parseSpec(R"({"duration": 5, "leaf_budget": 400000, "characters": [{"name": "a"}]})");
    ASSERT_TRUE(budget) << budget.error().message;
    EXPECT_EQ(budget->options.leafBudget, 400000);
    expectError(R"({"duration": 5, "root_beam": -1, "characters": [{"name": "a"}]})", "/root_beam: must be an integer from 0 to 100000");
    expectError(R"({"duration": 5, "root_beam": 2.5, "characters": [{"name": "a"}]})", "/root_beam: must be an integer");
    auto beam = parseSpec(R"({"duration": 5, "root_beam": 0, "characters": [{"name": "a"}]})");
    ASSERT_TRUE(beam) << beam.error().message;
    EXPECT_EQ(beam->options.rootBeam, 0);
    auto byDefault = parseSpec(R"({"duration": 5, "characters": [{"name": "a"}]})");
    ASSERT_TRUE(byDefault) << byDefault.error().message;
    EXPECT_EQ(byDefault->options.rootBeam, 8);
}

// The stage: with an arena, a chase on the running take turns back at its
// edge (a running turn overshoots it by up to about 2.5 m), where the same
// chase without one runs far beyond it.
TEST(SimPlanner, ArenaKeepsAChaseOnStage) {
    auto chase = [](const std::string& arena) {
        return R"({"version": 1, "duration": 20, "seed": 3, )" + arena + R"("characters": [
          {"name": "runaway", "side": 1, "preset": "runaway", "depth": 2, "motions": ["running_around"],
           "start": {"x": 2, "z": 0, "heading_deg": 90}},
          {"name": "chaser", "side": 0, "preset": "chaser", "depth": 2, "motions": ["running_around"],
           "start": {"x": 0, "z": 0, "heading_deg": 90}}]})";
    };
    auto farthest = [](const Scene& scene) {
        const auto& lib = demoWorld().library;
        double out = 0;
        for (const auto& c : scene.characters)
            for (const auto& a : c.track) {
                if (a.forced) continue;
                const RootXf end = a.root * lib.actions()[static_cast<std::size_t>(a.action)].end;
                out = std::max(out, static_cast<double>(glm::length(end.pos - glm::vec2(1.0f, 0.0f))));
            }
        return out;
    };
    auto open = runSpec(chase(""));
    ASSERT_TRUE(open.ok()) << open.error().message;
    auto staged = runSpec(chase(R"("arena": {"x": 1, "z": 0, "radius": 6}, )"));
    ASSERT_TRUE(staged.ok()) << staged.error().message;
    RecordProperty("open_farthest_m", std::to_string(farthest(*open)));
    RecordProperty("arena_farthest_m", std::to_string(farthest(*staged)));
    EXPECT_GT(farthest(*open), 10.0);
    EXPECT_LE(farthest(*staged), 9.0);
    for (const auto& c : staged->characters) EXPECT_EQ(c.fallbacks, 0) << c.name;
    // The scene file keeps the stage for viewers; a broken one is refused.
    const auto& lib = demoWorld().library;
    const std::string text = sceneToJson(*staged, lib);
    auto back = sceneFromJson(text, "s.frayscene", lib);
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(back->arena.radius, 6.0);
    EXPECT_EQ(back->arena.centre, glm::vec2(1.0f, 0.0f));
    EXPECT_EQ(sceneToJson(*back, lib), text);
    std::string broken = text;
    broken.replace(broken.find("\"radius\": 6.0"), 13, "\"radius\": -1");
    auto bad = sceneFromJson(broken, "s.frayscene", lib);
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("s.frayscene: /arena"), std::string::npos) << bad.error().message;
    EXPECT_FALSE(open->arena.bounded());
    EXPECT_EQ(sceneToJson(*open, lib).find("\"arena\""), std::string::npos);
}

// The search's shortcuts (lazy child order, bounded frontier nodes replayed
// when met again) change no decision and no count: with node reuse off the
// same scene, statistics included, serial and parallel.
TEST(SimPlanner, NodeReuseChangesNothing) {
    const auto& lib = demoWorld().library;
    auto parsed = parseSpec(duelSpec(4, 2, 3, 12.0));
    ASSERT_TRUE(parsed.ok()) << parsed.error().message;
    auto reused = simulate(lib, demoWorld().project.combos, *parsed);
    ASSERT_TRUE(reused.ok()) << reused.error().message;
    EXPECT_GT(reused->stats.leaves, 5000);
    parsed->options.reuseNodes = false;
    parsed->options.parallel = false;
    auto fresh = simulate(lib, demoWorld().project.combos, *parsed);
    ASSERT_TRUE(fresh.ok());
    EXPECT_EQ(sceneToJson(*reused, lib), sceneToJson(*fresh, lib));
}

TEST(SimPlanner, DeterministicAndParallelIndependent) {
    const std::string spec = duelSpec(3, 3, 7, 6.0);
    auto a = runSpec(spec);
    auto b = runSpec(spec);
    ASSERT_TRUE(a.ok()) << a.error().message;
    ASSERT_TRUE(b.ok());
    const auto& lib = demoWorld().library;
    EXPECT_EQ(sceneToJson(*a, lib), sceneToJson(*b, lib));
    auto parsed = parseSpec(spec);
    ASSERT_TRUE(parsed.ok());
    parsed->options.parallel = false;
    auto serial = simulate(lib, demoWorld().project.combos, *parsed);
    ASSERT_TRUE(serial.ok());
    EXPECT_EQ(sceneToJson(*a, lib), sceneToJson(*serial, lib));
    // Another seed gives another scene.
    auto c = runSpec(duelSpec(3, 3, 8, 6.0));
    ASSERT_TRUE(c.ok());
    EXPECT_NE(sceneToJson(*a, lib), sceneToJson(*c, lib));
}

// The search statistics the scene stores (nodes, leaves, cutoffs) and the
// choices are the same whatever the number of threads the root children
// share (each thread keeps its own memo of frontier nodes, replayed with
// the counts of a fresh run).
TEST(SimPlanner, SameBytesWhateverTheThreadCount) {
    const auto& lib = demoWorld().library;
    auto parsed = parseSpec(duelSpec(4, 2, 5, 8.0));
    ASSERT_TRUE(parsed.ok()) << parsed.error().message;
    for (int beam : {8, 0}) {  // the default root beam and the exact search
        parsed->options.rootBeam = beam;
        std::string first;
        for (int threads : {1, 2, 3, 4}) {
            tbb::task_arena arena(threads);
            Result<Scene> scene = makeError("not run");
            arena.execute([&] { scene = simulate(lib, demoWorld().project.combos, *parsed); });
            ASSERT_TRUE(scene.ok()) << scene.error().message;
            EXPECT_GT(scene->stats.leaves, 1000);
            const std::string text = sceneToJson(*scene, lib);
            if (first.empty()) first = text;
            EXPECT_EQ(text, first) << threads << " threads, root beam " << beam;
        }
    }
}

// The root beam (SimOptions::rootBeam, the spec's "root_beam"): the deepest
// pass searches only the root children the pass before ranked best. A beam
// wider than any root's children is the exact search byte for byte, search
// statistics included; "root_beam": 0 is that exact search; the default
// beam of 8 searches fewer leaves (the same whatever the thread count:
// SameBytesWhateverTheThreadCount runs both settings).
TEST(SimPlanner, RootBeamNarrowsTheLastPassAndZeroIsExact) {
    const auto& lib = demoWorld().library;
    std::string text = duelSpec(4, 2, 3, 8.0);
    auto beamed = parseSpec(text);
    ASSERT_TRUE(beamed.ok()) << beamed.error().message;
    ASSERT_EQ(beamed->options.rootBeam, 8);
    text.insert(1, R"("root_beam": 0, )");
    auto exactSpec = parseSpec(text);
    ASSERT_TRUE(exactSpec.ok()) << exactSpec.error().message;
    ASSERT_EQ(exactSpec->options.rootBeam, 0);
    auto exact = simulate(lib, demoWorld().project.combos, *exactSpec);
    ASSERT_TRUE(exact.ok()) << exact.error().message;
    auto wide = *exactSpec;
    wide.options.rootBeam = 100000;
    auto wideScene = simulate(lib, demoWorld().project.combos, wide);
    ASSERT_TRUE(wideScene.ok()) << wideScene.error().message;
    EXPECT_EQ(sceneToJson(*wideScene, lib), sceneToJson(*exact, lib));
    auto beam = simulate(lib, demoWorld().project.combos, *beamed);
    ASSERT_TRUE(beam.ok()) << beam.error().message;
    EXPECT_GT(beam->stats.leaves, 1000);
    // 11,051 against 26,457 measured (16 kept: 16,320; the demo duel's
    // 20 s: 210,076 against 622,868, 16 kept: 265,986).
    EXPECT_LT(beam->stats.leaves, exact->stats.leaves);
    for (const Scene* scene : {&*exact, &*beam}) {
        EXPECT_EQ(scene->stats.shallower, 0);
        EXPECT_GT(scene->stats.decisions, 10);
    }
}

TEST(SimPlanner, TimelineIsContinuous) {
    auto scene = runSpec(duelSpec(3, 2, 3, 10.0));
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    const auto& lib = demoWorld().library;
    for (const auto& c : scene->characters) {
        ASSERT_FALSE(c.track.empty());
        for (std::size_t i = 1; i < c.track.size(); ++i) {
            const auto& prev = c.track[i - 1];
            const auto& cur = c.track[i];
            EXPECT_NEAR(cur.start, prev.end, 1e-9) << c.name << " action " << i;
            // Each action starts where the previous one left the character.
            const RootXf was = prev.placementAt(lib, prev.offset + (prev.end - prev.start));
            const RootXf now = cur.placementAt(lib, cur.offset);
            EXPECT_LT(glm::length(was.pos - now.pos), 0.08f) << c.name << " action " << i;
        }
        EXPECT_GE(c.track.back().end, scene->duration);
    }
    for (const auto& h : scene->hits) {
        EXPECT_GT(h.speed, 0.0);
        EXPECT_NE(h.attacker, h.defender);
    }
}

TEST(SimPlanner, HitsForceReactions) {
    // Over a few seeded matches some blows land; every unblocked hit puts its
    // victim into a forced reaction starting at that moment.
    int hits = 0;
    for (std::uint64_t seed = 1; seed <= 4 && hits == 0; ++seed) {
        auto scene = runSpec(duelSpec(2, 2, seed, 20.0));
        ASSERT_TRUE(scene.ok()) << scene.error().message;
        for (const auto& h : scene->hits) {
            if (h.blocked) continue;
            ++hits;
            const auto& track = scene->characters[static_cast<std::size_t>(h.defender)].track;
            const bool reacted = std::any_of(track.begin(), track.end(), [&](const ActionInstance& i) {
                return i.forced && std::fabs(i.start - h.time) < 1e-9 &&
                       demoWorld().library.actions()[static_cast<std::size_t>(i.action)].is(kReactive);
            });
            EXPECT_TRUE(reacted) << "hit at " << h.time;
        }
    }
    EXPECT_GT(hits, 0);
}

TEST(SimPlanner, PruningIsCounted) {
    auto on = runSpec(duelSpec(3, 3, 2, 8.0));
    ASSERT_TRUE(on.ok());
    EXPECT_GT(on->stats.choices, 0);
    EXPECT_GT(on->stats.prunedShare(), 0.25);
    auto parsed = parseSpec(duelSpec(3, 3, 2, 8.0));
    ASSERT_TRUE(parsed.ok());
    parsed->options.pruning = false;
    auto off = simulate(demoWorld().library, demoWorld().project.combos, *parsed);
    ASSERT_TRUE(off.ok());
    EXPECT_EQ(off->stats.pruned, 0);
    EXPECT_GT(off->stats.leaves, on->stats.leaves);
}

TEST(SimPlanner, NoLegalActionFallsBackToIdle) {
    // Carrying actions never follow a guard: Next() within the set is empty,
    // the planner takes an action of the set anyway, says so, and goes on.
    auto scene = runSpec(R"({"duration": 6, "seed": 1, "characters": [
        {"name": "a", "side": 0, "actions": ["@carry"], "motions": ["carrying", "shadowbox_energetic"],
         "start_action": "guard_idle", "start": {"x": 0, "z": 0}},
        {"name": "b", "side": 1, "start": {"x": 3, "z": 0, "heading_deg": 180}, "motions": ["walking"]}]})");
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    const auto& a = scene->characters[0];
    EXPECT_GT(a.fallbacks, 0);
    EXPECT_EQ(scene->stats.fallbacks, a.fallbacks + scene->characters[1].fallbacks);
    ASSERT_GT(a.track.size(), 1u);
    EXPECT_TRUE(a.track[1].fallback);  // the first choice after the guard
    EXPECT_TRUE(demoWorld().library.actions()[static_cast<std::size_t>(a.track[1].action)].has("carry"));
    const auto m = computeMetrics(*scene, demoWorld().library);
    EXPECT_EQ(m.characters[0].fallbacks, a.fallbacks);
}

TEST(SimScene, JsonRoundTripAndErrors) {
    auto scene = runSpec(duelSpec(2, 2, 5, 6.0));
    ASSERT_TRUE(scene.ok());
    const auto& lib = demoWorld().library;
    scene->project = "demo.frayproj";
    const std::string text = sceneToJson(*scene, lib);
    auto back = sceneFromJson(text, "s.frayscene", lib);
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(sceneToJson(*back, lib), text);
    auto path = sceneProjectPath(text, "s.frayscene");
    ASSERT_TRUE(path.ok());
    EXPECT_EQ(*path, "demo.frayproj");

    auto broken = text;
    broken.replace(broken.find("\"version\": 1"), 12, "\"version\": 9");
    auto r = sceneFromJson(broken, "s.frayscene", lib);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("s.frayscene: /version: version 9 is not supported"), std::string::npos);
    broken = text;
    const auto first = broken.find("\"first\": ");
    broken.replace(first, 9, "\"first\": 9");  // an action that is not in the project
    r = sceneFromJson(broken, "s.frayscene", lib);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("is not in the project any more"), std::string::npos) << r.error().message;
    EXPECT_FALSE(sceneFromJson("[]", "s.frayscene", lib).ok());
}

TEST(SimScene, PoserPlacesAndBlends) {
    auto scene = runSpec(duelSpec(2, 2, 4, 6.0));
    ASSERT_TRUE(scene.ok());
    const auto& lib = demoWorld().library;
    const ScenePoser poser(*scene, lib);
    const auto& joints = lib.motion(0).joints;
    std::vector<glm::vec3> world, before;
    for (int c = 0; c < 2; ++c) {
        const auto& track = scene->characters[static_cast<std::size_t>(c)].track;
        for (std::size_t i = 1; i < track.size(); ++i) {
            const double t = track[i].start;
            // The pelvis is where the planner placed it, and does not jump at the seam.
            poser.worldPositions(c, t + 0.2, world);
            const glm::vec3 p = world[static_cast<std::size_t>(joints.pelvis)];
            const RootXf planned = track[i].placementAt(lib, track[i].offset + 0.2);
            if (t + 0.2 < track[i].end) {
                EXPECT_LT(glm::length(glm::vec2(p.x, p.z) - planned.pos), 0.02f) << "character " << c << " action " << i;
            }
            poser.worldPositions(c, t - 1e-3, before);
            poser.worldPositions(c, t, world);
            EXPECT_LT(glm::length(world[static_cast<std::size_t>(joints.pelvis)] - before[static_cast<std::size_t>(joints.pelvis)]),
                      0.08f)
                << "character " << c << " seam " << i;
        }
    }
}

TEST(SimMetrics, PenetrationAndDistanceCanFail) {
    // Two idle characters on the same spot penetrate all the time; apart, never.
    const std::string close = R"({"duration": 3, "seed": 1, "characters": [
        {"name": "a", "side": 0, "actions": ["guard_idle"], "start": {"x": 0, "z": 0}},
        {"name": "b", "side": 1, "actions": ["guard_idle"], "start": {"x": 0.1, "z": 0}}]})";
    auto together = runSpec(close);
    ASSERT_TRUE(together.ok()) << together.error().message;
    const auto& lib = demoWorld().library;
    const auto m = computeMetrics(*together, lib);
    EXPECT_GT(m.penetrationFrames, 60);
    EXPECT_GT(m.characters[0].penetrationFrames, 60);
    ASSERT_TRUE(m.characters[0].meanOpponentDistance.has_value());
    EXPECT_LT(*m.characters[0].meanOpponentDistance, 0.5);
    std::string apart = close;
    apart.replace(apart.find("\"x\": 0.1"), 8, "\"x\": 3.0");
    auto far = runSpec(apart);
    ASSERT_TRUE(far.ok());
    const auto m2 = computeMetrics(*far, lib);
    EXPECT_EQ(m2.penetrationFrames, 0);
    EXPECT_GT(*m2.characters[0].meanOpponentDistance, 2.5);
    EXPECT_LT(m2.characters[0].footSkateMean, 0.5);  // cm per frame, idle feet stay planted
}

TEST(SimPresets, BuiltinsEditableAndStored) {
    const auto& builtins = builtinPresets();
    auto find = [&](const std::vector<Preset>& list, const std::string& name) {
        return std::find_if(list.begin(), list.end(), [&](const Preset& p) { return p.name == name; });
    };
    for (const char* name : {"general-boxer", "infighter", "outboxer", "chaser", "runaway", "chaser-path"}) {
        EXPECT_NE(find(builtins, name), builtins.end()) << name;
    }
    EXPECT_LT(find(builtins, "infighter")->weights.rD, find(builtins, "general-boxer")->weights.rD);
    EXPECT_LT(find(builtins, "general-boxer")->weights.rD, find(builtins, "outboxer")->weights.rD);
    EXPECT_EQ(find(builtins, "general-boxer-path")->weights.wPath, 10.0);

    prep::Project p = prep::makeProject("t");
    Preset mine = *find(builtins, "infighter");
    ASSERT_TRUE(applyWeightEdit(mine.weights, "r_d=0.4").ok());
    EXPECT_FALSE(applyWeightEdit(mine.weights, "r_d=abc").ok());
    EXPECT_FALSE(applyWeightEdit(mine.weights, "nope=1").ok());
    const auto previous = setProjectPreset(p, mine);
    ASSERT_TRUE(previous.has_value());
    EXPECT_EQ(previous->weights.rD, 0.5);
    // Through the project file and back.
    auto loaded = prep::projectFromJson(prep::projectToJson(p), "t.frayproj");
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    auto presets = projectPresets(*loaded, "t.frayproj");
    ASSERT_TRUE(presets.ok());
    EXPECT_EQ(find(*presets, "infighter")->weights.rD, 0.4);
    EXPECT_TRUE(removeProjectPreset(p, "infighter").has_value());
    presets = projectPresets(p, "t.frayproj");
    EXPECT_EQ(find(*presets, "infighter")->weights.rD, 0.5);
}

}  // namespace
}  // namespace fray::sim

namespace fray::sim {
namespace {

// Styles differ measurably (SPEC 2.3): infighter closer than the general
// boxer, the general boxer closer than the outboxer (mirror matches).
TEST(SimStyles, PreferredDistanceOrdersStyles) {
    auto meanDistance = [](const std::string& preset) {
        double sum = 0;
        int n = 0;
        for (std::uint64_t seed = 1; seed <= 2; ++seed) {
            auto scene = test::runSpec(test::duelSpec(3, 3, seed, 15.0, preset, preset));
            EXPECT_TRUE(scene.ok());
            if (!scene.ok()) return 0.0;
            const auto m = computeMetrics(*scene, test::demoWorld().library);
            for (const auto& c : m.characters) sum += c.meanOpponentDistance.value_or(0.0), ++n;
        }
        return sum / n;
    };
    const double in = meanDistance("infighter"), general = meanDistance("general-boxer"), out = meanDistance("outboxer");
    RecordProperty("infighter", std::to_string(in));
    RecordProperty("general", std::to_string(general));
    RecordProperty("outboxer", std::to_string(out));
    EXPECT_LT(in, general);
    EXPECT_LT(general, out);
}

}  // namespace
}  // namespace fray::sim

namespace fray::sim {
namespace {

// Deeper is smarter (thesis 4.5.1): a general boxer expanding 4 levels lands
// more than twice the blows of one expanding 2, and wins 70 % of 20 short
// seeded matches. (The issue's matches of 20 s are measured by
// scripts/duel_series.py, too long for CI: see docs/TREE_EXPANSION.md.)
// Over 80 seeds of these 12 s matches the exact search wins 62, the root
// beam of 16 61 and of 8 59; ten seeds were too few to tell them apart
// (seeds 11-20: the exact search 6 of 10), so 20 are played.
TEST(SimDepth, DeeperBoxerWinsMostMatches) {
    int wins = 0, matches = 0, hitsDeep = 0, hitsShallow = 0;
    for (std::uint64_t seed = 1; seed <= 20; ++seed) {
        auto scene = test::runSpec(test::duelSpec(4, 2, seed, 12.0));
        ASSERT_TRUE(scene.ok()) << scene.error().message;
        const auto hits = test::landedHits(*scene);
        hitsDeep += hits[0], hitsShallow += hits[1];
        wins += hits[0] > hits[1];
        ++matches;
    }
    RecordProperty("wins", wins);
    RecordProperty("hits_depth4", hitsDeep);
    RecordProperty("hits_depth2", hitsShallow);
    // Depth 4 is searched in full under the default leaf budget (seeds 1-10
    // at the old 150,000, some decisions at depth 3: 7 of 10). Seeds 1-20
    // measured: exact 14 won, hits 30 vs 8; beam 16: 15, 30 vs 9; beam 8:
    // 15, 28 vs 11.
    EXPECT_GE(wins * 10, matches * 7) << wins << " wins of " << matches << "; hits " << hitsDeep << " vs " << hitsShallow;
    EXPECT_GT(hitsDeep, 2 * hitsShallow) << hitsDeep << " vs " << hitsShallow;
}

// Thesis 4.5.1 (figures 4.8 and 4.9): the tired boxer, whose every action is
// slower, keeps being hit by the energetic one at equal depth, and beats it
// when it looks five levels ahead against two. Matches of 60 s (9 of 10 won,
// hits 81 vs 16): in 15 s ones most end 0-1 or 1-1, too few blows to decide
// (3 of 10 won), and at 40 s it is 6 of 10.
TEST(SimDepth, SmartTiredBoxerBeatsEnergeticOne) {
    struct Series {
        int wins = 0, hitsTired = 0, hitsEnergetic = 0;
    };
    auto series = [](int depthTired) {
        Series s;
        for (std::uint64_t seed = 1; seed <= 10; ++seed) {
            auto scene = test::runSpec(
                duelSpec(depthTired, 2, seed, 60.0, "general-boxer", "general-boxer", "shadowbox_tired", "shadowbox_energetic"));
            EXPECT_TRUE(scene.ok()) << scene.error().message;
            if (!scene.ok()) continue;
            const auto hits = test::landedHits(*scene);
            s.hitsTired += hits[0], s.hitsEnergetic += hits[1];
            s.wins += hits[0] > hits[1];
        }
        return s;
    };
    const Series smart = series(5), equal = series(2);
    RecordProperty("wins_tired_depth5", smart.wins);
    RecordProperty("wins_tired_depth2", equal.wins);
    RecordProperty("hits_tired_depth5", smart.hitsTired);
    RecordProperty("hits_energetic_vs_depth5", smart.hitsEnergetic);
    RecordProperty("hits_tired_depth2", equal.hitsTired);
    RecordProperty("hits_energetic_vs_depth2", equal.hitsEnergetic);
    EXPECT_GT(smart.wins, 5) << "tired depth 5 won " << smart.wins << " of 10; hits " << smart.hitsTired << " vs "
                             << smart.hitsEnergetic;
    EXPECT_GT(smart.hitsTired, smart.hitsEnergetic);
    // At equal depth the energetic boxer lands more.
    EXPECT_LT(equal.wins, 5) << "tired depth 2 won " << equal.wins << " of 10";
    EXPECT_LT(equal.hitsTired, equal.hitsEnergetic);
}

}  // namespace
}  // namespace fray::sim

namespace fray::sim {
namespace {

// Cooperation (thesis 4.5.2): 10 fighting pairs, each moving along a circle
// of radius 6 m (10 degrees every 5 s, starting where it stands) with the
// path-following preset, stay on their paths (mean error < 0.5 m for every
// character), never touch another pair, and still land blows.
TEST(SimCooperation, TenPairsFollowCircularPathsWhileFighting) {
    constexpr double kRadius = 6.0, kDuration = 20.0, kStepDeg = 10.0, kStepSeconds = 5.0;
    const std::string actions = R"(["@punch", "@kick", "@block", "@avoid", "@step", "@idle", "@transition", "@turn"])";
    std::string characters;
    for (int pair = 0; pair < 10; ++pair) {
        for (int member = 0; member < 2; ++member) {
            // Partners 1.1 m apart along the circle, facing each other.
            const double a = 2.0 * std::numbers::pi * pair / 10.0 + (member == 0 ? 0.0 : 0.19);
            const double sign = member == 0 ? 1.0 : -1.0;
            const double heading = std::atan2(-std::sin(a) * sign, std::cos(a) * sign) * 180.0 / std::numbers::pi;
            std::string path;
            for (int j = 0; j * kStepSeconds <= kDuration + kStepSeconds; ++j) {
                const double b = a + j * kStepDeg * std::numbers::pi / 180.0;
                path += (j ? ", " : "") + std::string(R"({"x": )") + std::to_string(kRadius * std::cos(b)) +
                        R"(, "z": )" + std::to_string(kRadius * std::sin(b)) + R"(, "time": )" +
                        std::to_string(j * kStepSeconds) + "}";
            }
            const std::string name = (member == 0 ? "red" : "blue") + std::to_string(pair);
            const std::string opponent = (member == 0 ? "blue" : "red") + std::to_string(pair);
            characters += (characters.empty() ? "" : ",\n") + std::string(R"({"name": ")") + name + R"(", "side": )" +
                          std::to_string(member) + R"(, "group": )" + std::to_string(pair) +
                          R"(, "preset": "general-boxer-path", "depth": 2, "motions": ["shadowbox_energetic"], "actions": )" +
                          actions + R"(, "start": {"x": )" + std::to_string(kRadius * std::cos(a)) + R"(, "z": )" +
                          std::to_string(kRadius * std::sin(a)) + R"(, "heading_deg": )" + std::to_string(heading) +
                          R"(}, "path": [)" + path + R"(], "opponent": ")" + opponent + R"("})";
        }
    }
    auto scene = test::runSpec(R"({"version": 1, "duration": )" + std::to_string(kDuration) +
                               R"(, "seed": 1, "characters": [)" + characters + "]}");
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    const auto m = computeMetrics(*scene, test::demoWorld().library);
    double sum = 0.0;
    for (const auto& c : m.characters) {
        ASSERT_TRUE(c.pathErrorMean.has_value()) << c.name;
        EXPECT_LT(*c.pathErrorMean, 0.5) << c.name;
        sum += *c.pathErrorMean;
    }
    int pairsFighting = 0;
    for (int pair = 0; pair < 10; ++pair) {
        const auto& r = m.characters[static_cast<std::size_t>(2 * pair)];
        const auto& b = m.characters[static_cast<std::size_t>(2 * pair + 1)];
        pairsFighting += r.hitsGiven + b.hitsGiven > 0 ? 1 : 0;
    }
    std::printf("10 pairs: mean path error %.2f m, %zu hits, %d pairs landed blows, %d cross-group penetrations\n",
                sum / static_cast<double>(m.characters.size()), scene->hits.size(), pairsFighting,
                m.crossGroupPenetrations);
    EXPECT_EQ(m.crossGroupPenetrations, 0);
    EXPECT_GE(pairsFighting, 8);
}

}  // namespace
}  // namespace fray::sim

namespace fray::sim {
namespace {

// Chase (thesis 4.5.2) on the running take inside a 6 m stage: a depth-4
// chaser catches a depth-2 runaway sooner than a chaser at equal depth (2 vs
// 2, 4 vs 4), and two cooperating depth-2 chasers sooner than one. Mean time
// to the first catch over seeded chases of 30 s, a chase without a catch
// counting as 30 s. (20 seeds with scripts/chase_series.py: 14.1 / 22.5 /
// 20.7 s and 10.4 s; docs/TREE_EXPANSION.md.)
TEST(SimChase, DeeperAndTwoChasersCatchSooner) {
    constexpr double kSeconds = 30.0;
    constexpr int kSeeds = 12;
    auto meanCatch = [&](int chaserDepth, int runawayDepth, int chasers) {
        double total = 0;
        int caught = 0;
        for (int seed = 1; seed <= kSeeds; ++seed) {
            std::string chars = R"({"name": "runaway", "side": 1, "preset": "runaway", "depth": )" + std::to_string(runawayDepth) +
                                R"(, "motions": ["running_around"], "start": {"x": 2, "z": 0, "heading_deg": 90}})";
            for (int k = 0; k < chasers; ++k) {
                const double z = 1.2 * k - 0.6 * (chasers - 1);
                chars += R"(, {"name": "chaser)" + std::to_string(k) + R"(", "side": 0, "preset": "chaser", "depth": )" +
                         std::to_string(chaserDepth) + R"(, "motions": ["running_around"], "start": {"x": 0, "z": )" +
                         std::to_string(z) + R"(, "heading_deg": 90}})";
            }
            const std::string spec = R"({"version": 1, "duration": )" + std::to_string(kSeconds) + R"(, "seed": )" +
                                     std::to_string(seed) + R"(, "stop_on_catch": true, "start_jitter": {"distance": 0.3, "angle_deg": 20},
                "arena": {"x": 1, "z": 0, "radius": 6}, "characters": [)" + chars + "]}";
            auto scene = test::runSpec(spec);
            EXPECT_TRUE(scene.ok()) << (scene.ok() ? "" : scene.error().message);
            if (!scene.ok()) return kSeconds;
            double first = kSeconds;
            for (const auto& c : scene->catches) first = std::min(first, c.time);
            caught += first < kSeconds;
            total += first;
        }
        RecordProperty("caught_" + std::to_string(chasers) + "x" + std::to_string(chaserDepth) + "v" + std::to_string(runawayDepth),
                       caught);
        return total / kSeeds;
    };
    const double equal2 = meanCatch(2, 2, 1), deeper = meanCatch(4, 2, 1), equal4 = meanCatch(4, 4, 1), two = meanCatch(2, 2, 2);
    RecordProperty("mean_catch_2v2", std::to_string(equal2));
    RecordProperty("mean_catch_4v2", std::to_string(deeper));
    RecordProperty("mean_catch_4v4", std::to_string(equal4));
    RecordProperty("mean_catch_two_chasers_2v2", std::to_string(two));
    std::printf("mean time to catch (s): 2 vs 2 %.2f, 4 vs 2 %.2f, 4 vs 4 %.2f, two chasers 2 vs 2 %.2f\n", equal2, deeper, equal4, two);
    EXPECT_LT(deeper, equal2);
    EXPECT_LT(deeper, equal4);
    EXPECT_LT(two, equal2);
}

}  // namespace
}  // namespace fray::sim
