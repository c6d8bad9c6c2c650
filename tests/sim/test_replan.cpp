// Incremental re-planning (PlanCache, docs/TREE_EXPANSION.md "Re-planning
// after an edit"): after an edit simulate() resumes from the last decision
// the edit cannot reach, and the scene is byte for byte the one a full
// re-plan of the edited spec makes; what came before the resume point is the
// last scene's.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <string>

#include "sim/sim_fixture.h"

namespace fray::sim {
namespace {

std::string bytes(const Scene& s) { return sceneToJson(s, test::demoWorld().library); }

SceneSpec parsed(const std::string& text) {
    auto spec = test::parseSpec(text);
    EXPECT_TRUE(spec.ok()) << (spec ? "" : spec.error().message);
    return spec ? *spec : SceneSpec{};
}

// Plans `before` into a fresh cache, then `after` from it; checks that the
// incremental scene is the full re-plan's, byte for byte, and that every
// action starting before the resume point is the first scene's. Returns how it went.
ReplanInfo editAndCompare(const SceneSpec& before, const SceneSpec& after, const char* what) {
    const auto& w = test::demoWorld();
    PlanCache cache;
    ReplanInfo first;
    auto a = simulate(w.library, w.project.combos, before, cache, {}, &first);
    EXPECT_TRUE(a.ok()) << (a ? "" : a.error().message);
    EXPECT_FALSE(first.incremental);
    EXPECT_FALSE(cache.empty());
    if (!a) return {};
    ReplanInfo info;
    const auto t0 = std::chrono::steady_clock::now();
    auto inc = simulate(w.library, w.project.combos, after, cache, {}, &info);
    const double tInc = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_TRUE(inc.ok()) << (inc ? "" : inc.error().message);
    const auto t1 = std::chrono::steady_clock::now();
    auto full = simulate(w.library, w.project.combos, after);
    const double tFull = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
    EXPECT_TRUE(full.ok()) << (full ? "" : full.error().message);
    if (!inc || !full) return info;
    EXPECT_EQ(bytes(*inc), bytes(*full)) << what << ": the incremental re-plan differs from the full one";
    std::printf("%s: %s, resumed at %.2f s, %lld decisions kept, %lld planned (%.2f s; full %.2f s)%s%s\n", what,
                info.incremental ? "incremental" : "from the start", info.resumedAt, static_cast<long long>(info.decisionsKept),
                static_cast<long long>(info.decisionsPlanned), tInc, tFull, info.reason.empty() ? "" : ": ", info.reason.c_str());
    EXPECT_EQ(info.decisionsKept + info.decisionsPlanned, full->stats.decisions);
    // The prefix: every instance that starts before the resume point is the first scene's.
    for (std::size_t c = 0; c < a->characters.size(); ++c) {
        const auto& x = a->characters[c].track;
        const auto& y = inc->characters[c].track;
        for (std::size_t i = 0; i < x.size() && i < y.size() && x[i].start < info.resumedAt; ++i) {
            EXPECT_EQ(x[i].action, y[i].action) << what << ": character " << c << " instance " << i;
            EXPECT_EQ(x[i].start, y[i].start) << what << ": character " << c << " instance " << i;
            EXPECT_EQ(x[i].root.pos, y[i].root.pos) << what << ": character " << c << " instance " << i;
        }
    }
    return info;
}

std::string withPins(std::string text, const std::string& pins) {
    text.insert(text.size() - 1, R"(, "pins": )" + pins);
    return text;
}

// A pin late in a duel (on one of the first scene's late decisions of 'a',
// swapped for a kick or a punch the motion graph allows there): the
// decisions well before it are kept.
TEST(SimReplan, LatePinResumesAndMatchesAFullReplan) {
    const std::string base = test::duelSpec(3, 2, 1, 12.0);
    const auto& w = test::demoWorld();
    auto plain = simulate(w.library, w.project.combos, parsed(base));
    ASSERT_TRUE(plain.ok()) << plain.error().message;
    std::string pinned;
    double pinTime = 0;
    for (const auto& inst : plain->characters[0].track) {
        if (inst.forced || inst.start < 8.0 || !pinned.empty()) continue;
        for (const char* key : {"@kick", "@punch"}) {
            char buf[128];
            std::snprintf(buf, sizeof buf, R"([{"character": "a", "time": %.3f, "action": "%s"}])", inst.start, key);
            if (simulate(w.library, w.project.combos, parsed(withPins(base, buf))).ok()) {
                pinned = buf, pinTime = inst.start;
                break;
            }
        }
    }
    ASSERT_FALSE(pinned.empty()) << "no late decision of 'a' takes a kick or punch pin";
    const auto info = editAndCompare(parsed(base), parsed(withPins(base, pinned)), "late pin");
    EXPECT_TRUE(info.incremental);
    EXPECT_GE(info.decisionsKept, 5) << "a pin at " << pinTime << " s of 12 should keep the first seconds";
    EXPECT_LT(info.resumedAt, pinTime - kPinEarly);
    // And back: removing it again.
    const auto back = editAndCompare(parsed(withPins(base, pinned)), parsed(base), "late pin removed");
    EXPECT_TRUE(back.incremental);
}

// A weight or the seed: every decision reads it, so everything is planned again.
TEST(SimReplan, WeightOrSeedChangePlansFromTheStart) {
    const SceneSpec base = parsed(test::duelSpec(2, 2, 1, 6.0));
    SceneSpec weights = base;
    weights.characters[0].weights.wR = 20;
    const auto w = editAndCompare(base, weights, "weight w_r 10 -> 20");
    EXPECT_FALSE(w.incremental);
    EXPECT_EQ(w.decisionsKept, 0);
    EXPECT_FALSE(w.reason.empty());
    const auto s = editAndCompare(base, parsed(test::duelSpec(2, 2, 2, 6.0)), "seed 1 -> 2");
    EXPECT_FALSE(s.incremental);
}

// A longer or shorter scene: the decisions before the old (new) end are kept.
TEST(SimReplan, DurationChangeKeepsTheDecisionsBeforeIt) {
    const auto longer = editAndCompare(parsed(test::duelSpec(2, 2, 1, 5.0)), parsed(test::duelSpec(2, 2, 1, 7.0)), "duration 5 -> 7 s");
    EXPECT_TRUE(longer.incremental);
    const auto shorter = editAndCompare(parsed(test::duelSpec(2, 2, 1, 7.0)), parsed(test::duelSpec(2, 2, 1, 5.0)), "duration 7 -> 5 s");
    EXPECT_TRUE(shorter.incremental);
    EXPECT_EQ(shorter.decisionsPlanned, 0);
}

// A timed path of eight checkpoints: moving the last one keeps the
// decisions before the character heads for the fifth (the path term reads
// three checkpoints beyond the next one) and before the seventh's time.
std::string pathDuel(double lastX) {
    std::string path;
    for (int k = 0; k < 8; ++k) {
        const double x = k == 7 ? lastX : -0.25 * k;
        path += (k ? ", " : "") + std::string(R"({"x": )") + std::to_string(x) + R"(, "z": 0, "time": )" + std::to_string(1.0 + k) + "}";
    }
    const std::string actions = R"(["@punch", "@kick", "@block", "@avoid", "@step", "@idle", "@transition", "@turn"])";
    return R"({"version": 1, "duration": 9, "seed": 1, "characters": [
      {"name": "a", "side": 0, "depth": 2, "preset": "general-boxer-path", "motions": ["shadowbox_energetic"], "actions": )" +
           actions + R"(, "start": {"x": 0, "z": 0, "heading_deg": 90}, "path": [)" + path + R"(]},
      {"name": "b", "side": 1, "depth": 2, "preset": "general-boxer", "motions": ["shadowbox_energetic"], "actions": )" + actions +
           R"(, "start": {"x": 1.2, "z": 0, "heading_deg": -90}}]})";
}

TEST(SimReplan, LateCheckpointMoveResumesAndMatchesAFullReplan) {
    const auto info = editAndCompare(parsed(pathDuel(-1.75)), parsed(pathDuel(-2.4)), "last checkpoint moved");
    EXPECT_TRUE(info.incremental);
    // An early one: the first checkpoint moved is read from the first decision.
    SceneSpec early = parsed(pathDuel(-1.75));
    early.characters[0].path[0].pos.y += 0.3f;
    const auto e = editAndCompare(parsed(pathDuel(-1.75)), early, "first checkpoint moved");
    EXPECT_FALSE(e.incremental);
}

}  // namespace
}  // namespace fray::sim

namespace fray::sim {
namespace {

// Two duels in separate groups (characters interact within their group
// only): a pin on the second group's boxer keeps the first group's whole run
// and resumes the second late.
TEST(SimReplan, AGroupTheEditDoesNotReachKeepsItsWholeRun) {
    const std::string actions = R"(["@punch", "@kick", "@block", "@avoid", "@step", "@idle", "@transition", "@turn"])";
    const auto boxer = [&](const char* name, int side, int group, double x, double heading) {
        return std::string(R"({"name": ")") + name + R"(", "side": )" + std::to_string(side) + R"(, "group": )" + std::to_string(group) +
               R"(, "depth": 2, "preset": "general-boxer", "motions": ["shadowbox_energetic"], "actions": )" + actions +
               R"(, "start": {"x": )" + std::to_string(x) + R"(, "z": 0, "heading_deg": )" + std::to_string(heading) + "}}";
    };
    const std::string base = R"({"version": 1, "duration": 8, "seed": 1, "characters": [)" + boxer("a", 0, 0, 0, 90) + ", " +
                             boxer("b", 1, 0, 1.2, -90) + ", " + boxer("c", 0, 1, 6, 90) + ", " + boxer("d", 1, 1, 7.2, -90) + "]}";
    const auto& w = test::demoWorld();
    auto plain = simulate(w.library, w.project.combos, parsed(base));
    ASSERT_TRUE(plain.ok()) << plain.error().message;
    std::string pinned;
    for (const auto& inst : plain->characters[2].track) {
        if (inst.forced || inst.start < 5.0 || !pinned.empty()) continue;
        for (const char* key : {"@kick", "@punch", "@block"}) {
            char buf[128];
            std::snprintf(buf, sizeof buf, R"([{"character": "c", "time": %.3f, "action": "%s"}])", inst.start, key);
            if (simulate(w.library, w.project.combos, parsed(withPins(base, buf))).ok()) {
                pinned = buf;
                break;
            }
        }
    }
    ASSERT_FALSE(pinned.empty()) << "no late decision of 'c' takes a pin";
    const auto info = editAndCompare(parsed(base), parsed(withPins(base, pinned)), "pin in the second group");
    EXPECT_TRUE(info.incremental);
    std::int64_t firstGroup = 0;  // decisions of a and b: every track instance they chose
    for (int c : {0, 1}) {
        const auto& track = plain->characters[static_cast<std::size_t>(c)].track;
        for (std::size_t i = 1; i < track.size(); ++i) firstGroup += track[i].forced ? 0 : 1;
    }
    EXPECT_GT(info.decisionsKept, firstGroup) << "the first group's decisions and some of the second's are kept";
}

// The demo chase (three characters in one game tree, the scene ends at the
// first catch): a shorter scene.
TEST(SimReplan, ChaseDurationChangeMatchesAFullReplan) {
    const std::string text = R"({"version": 1, "duration": 12, "seed": 1, "stop_on_catch": true, "arena": {"x": 1, "z": 0, "radius": 6}, "characters": [
      {"name": "runaway", "side": 1, "preset": "runaway", "depth": 2, "motions": ["running_around"], "start": {"x": 2, "z": 0, "heading_deg": 90}},
      {"name": "chaser1", "side": 0, "preset": "chaser", "depth": 2, "motions": ["running_around"], "start": {"x": 0, "z": -0.6, "heading_deg": 90}},
      {"name": "chaser2", "side": 0, "preset": "chaser", "depth": 2, "motions": ["running_around"], "start": {"x": 0, "z": 0.6, "heading_deg": 90}}]})";
    std::string shorter = text;
    shorter.replace(shorter.find("\"duration\": 12"), 14, "\"duration\": 7");
    const auto info = editAndCompare(parsed(text), parsed(shorter), "chase 12 -> 7 s");
    EXPECT_TRUE(info.incremental);
}

}  // namespace
}  // namespace fray::sim
