// Interaction Patches (SPEC 4): PatternLists, generation and its validity
// rules, connection tables, standard poses, the patch cache and composition,
// on the demo project.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <set>
#include <tuple>

#include <tbb/task_arena.h>

#include "fray/core/atomic_file.h"
#include "fray/sim/compose.h"
#include "fray/sim/compose/domino.h"
#include "fray/sim/compose/football.h"
#include "fray/sim/compose/luggage.h"
#include "fray/sim/compose/one_vs_many.h"
#include "fray/sim/compose/one_vs_one.h"
#include "fray/sim/compose/rat.h"
#include "fray/sim/metrics.h"
#include "fray/sim/patches.h"
#include "fray/sim/patterns.h"
#include "fray/setup/affected.h"
#include "sim/demo_world.h"
#include "temp_dir.h"

namespace fray::sim {
namespace {

using test::demoWorld;
using test::footballWorld;
constexpr double kDeg = 3.14159265358979323846 / 180.0;

PatternList pattern(const std::string& name) {
    for (const auto& p : defaultPatterns()) {
        if (p.name == name) return p;
    }
    throw std::runtime_error("no pattern " + name);
}

// The fighting library used by the composition tests (generated once).
const PatchLibrary& fightLibrary() {
    static const PatchLibrary lib = [] {
        PatchLibrary out;
        const PatternSet set;
        for (const char* name : {"attack-defence-attack-fall", "attack-fall", "attack-attack-fall"}) {
            auto st = generatePatches(demoWorld().library, pattern(name), set, out);
            if (!st) throw std::runtime_error(st.error().message);
        }
        buildConnections(demoWorld().library, out);
        return out;
    }();
    return lib;
}

prep::Project projectWithPatterns(const std::string& section) {
    prep::Project p = demoWorld().project;
    p.laterSections[kPatternSection] = section;
    return p;
}

TEST(PatchPatterns, ProjectSectionRoundTripAndErrors) {
    const auto ok = projectPatterns(projectWithPatterns(R"({"patterns": [{"name": "p", "entries": [
        {"character": 1, "annotation": "attack"}, {"character": 2, "annotation": "fall"}],
        "weights": {"contact": 2, "distance": 1, "timing": 0.5}, "threshold": 0.6, "spread": true}],
        "initial_conditions": {"punch": {"distance": [0.5, 1.0]}}})"),
                                    "demo.frayproj");
    ASSERT_TRUE(ok) << ok.error().message;
    ASSERT_EQ(ok->patterns.size(), 1u);
    EXPECT_EQ(ok->patterns[0].entries[1], (PatternEntry{1, "fall"}));
    EXPECT_DOUBLE_EQ(ok->patterns[0].weights.contact, 2.0);
    EXPECT_TRUE(ok->patterns[0].spread);
    EXPECT_DOUBLE_EQ(ok->rangeFor("punch").maxDistance, 1.0);
    EXPECT_DOUBLE_EQ(ok->rangeFor("punch").maxAngle, defaultRange("punch").maxAngle);  // unset fields keep the default
    prep::Project written = demoWorld().project;
    setProjectPatterns(written, *ok);
    const auto again = projectPatterns(written, "again");
    ASSERT_TRUE(again);
    EXPECT_EQ(again->patterns, ok->patterns);
    EXPECT_EQ(again->rangeFor("punch"), ok->rangeFor("punch"));

    const std::pair<std::string, std::string> bad[] = {
        {R"({"patterns": [{"name": "p", "entries": [{"character": 1, "annotation": "uppercutz"}, {"character": 2, "annotation": "fall"}]}]})",
         "/pattern_lists/patterns/0/entries/0/annotation: unknown annotation 'uppercutz'"},
        {R"({"patterns": [{"name": "p", "entries": [{"character": 3, "annotation": "attack"}]}]})",
         "/pattern_lists/patterns/0/entries/0/character: must be 1 or 2"},
        {R"({"patterns": [{"name": "p", "entries": []}]})", "/pattern_lists/patterns/0/entries: must be a non-empty array"},
        {R"({"patterns": [{"name": "p", "entries": [{"character": 1, "annotation": "attack"}]}]})",
         "needs entries for both characters"},
        {R"({"initial_conditions": {"punch": {"distance": [1.5, 0.5]}}})", "/pattern_lists/initial_conditions/punch/distance: low is above high"},
        {R"({"patterns": [], "extra": 1})", "/pattern_lists/extra: unknown field"},
        {R"({"patterns": [{"name": "p", "spread": "yes", "entries": [{"character": 1, "annotation": "attack"}, {"character": 2, "annotation": "fall"}]}]})",
         "/pattern_lists/patterns/0/spread: must be true or false"},
    };
    for (const auto& [section, message] : bad) {
        const auto r = projectPatterns(projectWithPatterns(section), "demo.frayproj");
        ASSERT_FALSE(r) << section;
        EXPECT_NE(r.error().message.find(message), std::string::npos) << r.error().message;
        EXPECT_EQ(r.error().message.rfind("demo.frayproj: ", 0), 0u) << r.error().message;
    }
}

TEST(PatchPatterns, UnsatisfiableEntriesAreNamed) {
    const auto& lib = demoWorld().library;
    const PatternSet set;
    PatternList p;
    p.name = "football";
    p.entries = {{0, "run"}, {1, "tackle"}, {0, "avoid"}};
    auto st = checkPattern(p, set, lib);
    ASSERT_FALSE(st);
    EXPECT_NE(st.error().message.find("pattern 'football', entry 2 (character 2, tackle): no action in the project has this annotation"),
              std::string::npos)
        << st.error().message;
    p.entries = {{1, "fall"}, {0, "attack"}};
    st = checkPattern(p, set, lib);
    ASSERT_FALSE(st);
    EXPECT_NE(st.error().message.find("entry 1 (character 2, fall): a reaction needs an earlier action of the other character"),
              std::string::npos)
        << st.error().message;
    PatchLibrary out;
    EXPECT_FALSE(generatePatches(lib, p, set, out));
    EXPECT_TRUE(out.patches().empty());
}

TEST(PatchConfigs, DistanceAndPlacement) {
    // F of SPEC 4.4: C_r = 0.30 m, C_theta = 180 degrees.
    EXPECT_NEAR(configDistance({1.0, 0, 0, 0}, {1.3, 0, 0, 0}), 1.0, 1e-9);
    EXPECT_NEAR(configDistance({1.0, std::numbers::pi / 2, 0, 0}, {1.0, 0, 0, 0}), 0.25, 1e-9);
    const PatchConfig c{1.2, 0.3, -0.5, 0};
    const auto places = placeConfig(c);
    const PatchConfig back = configOf(places[0], places[1]);
    EXPECT_NEAR(back.r, c.r, 1e-5);
    EXPECT_NEAR(back.theta1, c.theta1, 1e-5);
    EXPECT_NEAR(back.theta2, c.theta2, 1e-5);
}

TEST(PatchGeneration, KeptPatchesFollowTheirPattern) {
    const auto& lib = demoWorld().library;
    const auto& out = fightLibrary();
    ASSERT_GT(out.patches().size(), 100u);
    const auto& s = out.stats();
    EXPECT_EQ(s.paths, s.kept + s.duplicates + s.belowThreshold + s.tooClose + s.wrongOrder + s.unintendedHit + s.missedContact);
    EXPECT_GT(s.unintendedHit + s.tooClose + s.missedContact, 0);  // the rules do discard paths
    for (const auto& p : out.patches()) {
        const auto& pattern = out.patterns()[static_cast<std::size_t>(p.pattern)];
        EXPECT_GE(p.score, pattern.threshold);
        // Every action a character plays follows its entries in order; reactions are forced by a blow.
        std::array<std::vector<const PatternEntry*>, 2> entries;
        for (const auto& e : pattern.entries) entries[static_cast<std::size_t>(e.character)].push_back(&e);
        for (int c = 0; c < 2; ++c) {
            std::size_t k = 0;
            for (const auto& inst : p.tracks[static_cast<std::size_t>(c)]) {
                const auto& act = lib.actions()[static_cast<std::size_t>(inst.action)];
                if (k < entries[static_cast<std::size_t>(c)].size() &&
                    matchesAnnotation(act, entries[static_cast<std::size_t>(c)][k]->annotation)) {
                    if (isReactiveAnnotation(entries[static_cast<std::size_t>(c)][k]->annotation)) {
                        EXPECT_TRUE(inst.forced);
                        const bool caused = std::any_of(p.hits.begin(), p.hits.end(), [&](const HitEvent& h) {
                            return h.defender == c && std::fabs(h.time - inst.start) < 1e-9;
                        });
                        EXPECT_TRUE(caused) << "a reaction without a blow";
                    }
                    ++k;
                } else {
                    EXPECT_TRUE(act.is(kIdle)) << act.label() << " is neither the next entry nor a hold";
                }
            }
            EXPECT_EQ(k, entries[static_cast<std::size_t>(c)].size()) << "character " << c + 1 << " missed an entry";
        }
        // Blows land only on a character whose next entry is a reaction, never on an avoid.
        for (const auto& h : p.hits) {
            const auto& track = p.tracks[static_cast<std::size_t>(h.defender)];
            const bool reacted = std::any_of(track.begin(), track.end(), [&](const ActionInstance& i) {
                return i.forced && std::fabs(i.start - h.time) < 1e-9;
            });
            EXPECT_TRUE(reacted || h.blocked);
        }
        EXPECT_EQ(p.swept[0].size(), p.swept[1].size());
        EXPECT_GE(static_cast<double>(p.swept[0].size()) * kSweptSlice, p.duration - 1e-9);
    }
}

TEST(PatchGeneration, DeterministicAndParallelIndependent) {
    const auto& lib = demoWorld().library;
    const PatternSet set;
    GenerateOptions serial;
    serial.parallel = false;
    PatchLibrary a, b;
    ASSERT_TRUE(generatePatches(lib, pattern("attack-attack-fall"), set, a));
    ASSERT_TRUE(generatePatches(lib, pattern("attack-attack-fall"), set, b, serial));
    const test::TempDir dir("fray_patch_determinism_");
    buildConnections(lib, a);
    buildConnections(lib, b);
    ASSERT_TRUE(savePatchLibrary(a, dir / "a.patches"));
    ASSERT_TRUE(savePatchLibrary(b, dir / "b.patches"));
    EXPECT_EQ(*readWholeFile(dir / "a.patches"), *readWholeFile(dir / "b.patches"));
}

TEST(PatchGeneration, ProgressAndCancel) {
    const auto& lib = demoWorld().library;
    const PatternSet set;
    std::atomic<bool> cancel{true};
    PatchLibrary out;
    auto st = generatePatches(lib, pattern("attack-fall"), set, out, {}, cancelWhen(cancel));
    ASSERT_FALSE(st);
    EXPECT_TRUE(st.error().isCancelled()) << st.error().message;
    EXPECT_TRUE(out.patches().empty());
    int calls = 0;
    st = generatePatches(lib, pattern("attack-fall"), set, out, {}, [&](double, std::string_view) { return ++calls < 3; });
    ASSERT_FALSE(st);
    EXPECT_EQ(calls, 3);
}

TEST(PatchGeneration, HandMadePatchesUseTheSameRules) {
    const auto& lib = demoWorld().library;
    const auto& gen = fightLibrary();
    // Replaying a generated attack-fall patch by hand gives the same patch.
    const Patch* src = nullptr;
    for (const auto& p : gen.patches()) {
        if (gen.patterns()[static_cast<std::size_t>(p.pattern)].name == "attack-fall") src = &p;
    }
    ASSERT_NE(src, nullptr);
    PatchLibrary out;
    ASSERT_TRUE(addHandMadePatch(lib, pattern("attack-fall"), src->initial, {{{src->tracks[0][0].action}, {}}}, out));
    ASSERT_EQ(out.patches().size(), 1u);
    EXPECT_TRUE(out.patches()[0].handMade);
    EXPECT_EQ(out.patches()[0].hits.size(), src->hits.size());
    EXPECT_NEAR(out.patches()[0].score, src->score, 1e-9);
    // Out of reach: the blow never lands, the fall is never caused.
    PatchConfig far = src->initial;
    far.r = 3.0;
    auto st = addHandMadePatch(lib, pattern("attack-fall"), far, {{{src->tracks[0][0].action}, {}}}, out);
    ASSERT_FALSE(st);
    EXPECT_NE(st.error().message.find("never caused by a blow"), std::string::npos) << st.error().message;
    // A kick where the pattern wants a punch... any attack is fine; a block is not.
    int block = -1;
    for (int i = 0; i < lib.size() && block < 0; ++i) {
        if (lib.actions()[static_cast<std::size_t>(i)].is(kBlock)) block = i;
    }
    st = addHandMadePatch(lib, pattern("attack-fall"), src->initial, {{{block}, {}}}, out);
    ASSERT_FALSE(st);
    EXPECT_NE(st.error().message.find("is not 'attack' (entry 1)"), std::string::npos) << st.error().message;
}

TEST(PatchTables, ConnectionsAndStandardPoses) {
    const auto& lib = demoWorld().library;
    const auto& out = fightLibrary();
    ASSERT_EQ(out.temporal().size(), out.patches().size());
    std::size_t both = 0, one = 0;
    for (std::size_t a = 0; a < out.patches().size(); ++a) {
        const Patch& pa = out.patches()[a];
        for (const auto& l : out.temporal()[a]) {
            const Patch& pb = out.patches()[static_cast<std::size_t>(l.to)];
            for (int k = 0; k < 2; ++k) {
                if (l.shared >= 0 && l.shared != k) continue;
                const int m = l.roles ? 1 - k : k;
                // Motion-graph continuity of every continuing character.
                EXPECT_EQ(lib.startNode()[static_cast<std::size_t>(pb.tracks[static_cast<std::size_t>(m)].front().action)],
                          lib.endNode()[static_cast<std::size_t>(pa.tracks[static_cast<std::size_t>(k)].back().action)]);
            }
            if (l.shared < 0) {
                ++both;
                const PatchConfig fin = l.roles ? PatchConfig{pa.final.r, pa.final.theta2, pa.final.theta1, 0} : pa.final;
                EXPECT_LE(configDistance(fin, pb.initial), 0.5 + 1e-9);
            } else {
                ++one;
            }
        }
        for (const auto& l : out.spatial()[a]) {
            const auto& ta = pa.tracks[static_cast<std::size_t>(l.sharedA)];
            const auto& tb = out.patches()[static_cast<std::size_t>(l.to)].tracks[static_cast<std::size_t>(l.sharedB)];
            // The shared character's series lines up in clip time.
            const auto it = std::find_if(ta.begin(), ta.end(), [&](const ActionInstance& i) {
                return i.action == tb.front().action &&
                       std::fabs((i.start - i.offset) - (tb.front().start - tb.front().offset) - static_cast<double>(l.offset)) < 1e-4;
            });
            ASSERT_NE(it, ta.end());
            EXPECT_NEAR(static_cast<double>(l.from), tb.front().start + (it->offset - tb.front().offset), 1e-4);
        }
    }
    EXPECT_GT(both, 0u);
    EXPECT_GT(one, 0u);
    // Every initial and final configuration is close to its standard pose (unless the pose count hit its cap).
    ASSERT_FALSE(out.standardPoses().empty());
    if (out.standardPoses().size() < 64) {
        for (std::size_t i = 0; i < out.patches().size(); ++i) {
            EXPECT_LE(configDistance(out.patches()[i].initial, out.standardPoses()[static_cast<std::size_t>(out.initialPose()[i])]), 0.35 + 1e-9);
        }
    }
}

// The temporal table asks the motion graph once per pair of distinct actions,
// skips placing most swept boxes and builds its rows in parallel: its links
// must be exactly those of the rule (docs/PATCHES.md) applied to every pair of
// patches and role mapping, and one thread must build the same tables as many.
TEST(PatchTables, TemporalLinksMatchThePairwiseRuleWithOneThreadOrMany) {
    const auto& lib = demoWorld().library;
    const auto& out = fightLibrary();
    const std::size_t n = out.patches().size();
    ASSERT_GT(n, 50u);
    constexpr float kClearance = 0.15f;  // m between the swept boxes of characters that must not meet
    std::size_t both = 0, one = 0;
    for (std::size_t a = 0; a < n; ++a) {
        const Patch& pa = out.patches()[a];
        std::vector<std::tuple<int, int, int>> want, have;  // (to, roles, shared)
        for (std::size_t b = 0; b < n; ++b) {
            const Patch& pb = out.patches()[b];
            for (int roles = 0; roles < 2; ++roles) {
                const int m0 = roles ? 1 : 0;  // b's character that a's character 0 becomes
                const bool cont[2] = {
                    lib.continuesInto(pa.tracks[0].back().action, pb.tracks[static_cast<std::size_t>(m0)].front().action),
                    lib.continuesInto(pa.tracks[1].back().action, pb.tracks[static_cast<std::size_t>(1 - m0)].front().action)};
                const PatchConfig fin = roles ? PatchConfig{pa.final.r, pa.final.theta2, pa.final.theta1, pa.final.delay} : pa.final;
                if (cont[0] && cont[1] && configDistance(fin, pb.initial) <= 0.5) {
                    want.emplace_back(static_cast<int>(b), roles, -1);
                    continue;
                }
                // One continues; the other leaves, standing where a leaves it,
                // and must stay clear of every swept box of b's newcomer.
                for (int k = 0; k < 2; ++k) {
                    if (!cont[k]) continue;
                    const int m = k == 0 ? m0 : 1 - m0;
                    const RootXf xf = pa.endPlacement(lib, k) * pb.tracks[static_cast<std::size_t>(m)].front().root.inverse();
                    const SweptBox leaving = pa.swept[static_cast<std::size_t>(1 - k)].back();
                    const auto& joiner = pb.swept[static_cast<std::size_t>(1 - m)];
                    const bool meets = std::any_of(joiner.begin(), joiner.end(),
                                                   [&](const SweptBox& s) { return placedBox(s, xf).overlaps(leaving, kClearance); });
                    if (meets) continue;
                    want.emplace_back(static_cast<int>(b), roles, k);
                    break;
                }
            }
        }
        for (const auto& l : out.temporal()[a]) have.emplace_back(l.to, l.roles, l.shared);
        for (const auto& w : want) ++(std::get<2>(w) < 0 ? both : one);
        ASSERT_EQ(have, want) << "patch " << a;
    }
    EXPECT_GT(both, 0u);
    EXPECT_GT(one, 0u);

    PatchLibrary single = out;  // buildConnections replaces its tables
    tbb::task_arena oneThread(1);
    oneThread.execute([&] { buildConnections(lib, single); });
    ASSERT_EQ(single.temporal().size(), n);
    for (std::size_t a = 0; a < n; ++a) {
        ASSERT_EQ(single.temporal()[a].size(), out.temporal()[a].size()) << "patch " << a;
        for (std::size_t i = 0; i < out.temporal()[a].size(); ++i) {
            EXPECT_EQ(single.temporal()[a][i].to, out.temporal()[a][i].to);
            EXPECT_EQ(single.temporal()[a][i].roles, out.temporal()[a][i].roles);
            EXPECT_EQ(single.temporal()[a][i].shared, out.temporal()[a][i].shared);
        }
        ASSERT_EQ(single.spatial()[a].size(), out.spatial()[a].size()) << "patch " << a;
    }
    EXPECT_EQ(single.initialPose(), out.initialPose());
}

const PatchLibrary& dominoLibrary();

// Spatial connections between fall-fall patches (SPEC 4.3): a victim's fall
// goes on as the next patch's pusher, and the one who pushed the victim
// never touches the next victim: checked by the metrics on a scene of the
// three of them, independently of the table's own test.
TEST(PatchTables, SpatialLinksChainFallersWithoutContact) {
    const auto& lib = demoWorld().library;
    const auto& out = dominoLibrary();
    std::size_t chained = 0, checked = 0;
    for (std::size_t a = 0; a < out.patches().size(); ++a) {
        const Patch& pa = out.patches()[a];
        for (const auto& l : out.spatial()[a]) {
            if (l.sharedA != 1 || l.sharedB != 0) continue;
            ++chained;
            if (chained % 97 != 1) continue;  // a spread-out sample
            const Patch& pb = out.patches()[static_cast<std::size_t>(l.to)];
            const auto& victim = pa.tracks[1];
            const auto fall = std::find_if(victim.begin(), victim.end(), [](const ActionInstance& i) { return i.forced; });
            ASSERT_NE(fall, victim.end());
            const ActionInstance& head = pb.tracks[0].front();
            ASSERT_EQ(fall->action, head.action);
            EXPECT_LE(head.offset, fall->offset + 1e-6);
            const RootXf xf = fall->root * head.root.inverse();
            const double shift = std::max(0.0, -static_cast<double>(l.offset));
            Scene scene;
            for (int c = 0; c < 3; ++c) {
                SceneCharacter ch;
                ch.name = c == 0 ? "pusher" : c == 1 ? "victim" : "next victim";
                for (ActionInstance i : c < 2 ? pa.tracks[static_cast<std::size_t>(c)] : pb.tracks[1]) {
                    const double at = c < 2 ? shift : shift + static_cast<double>(l.offset);
                    i.start += at, i.end += at;
                    if (c == 2) i.root = xf * i.root;
                    ch.track.push_back(i);
                }
                scene.characters.push_back(ch);
                scene.duration = std::max(scene.duration, ch.track.back().end);
            }
            const auto m = computeMetrics(scene, lib);
            for (const auto& p : m.penetrations) {
                EXPECT_FALSE(p.a == 0 && p.b == 2) << "patch " << a << " -> " << l.to << ": the pusher touches the next victim at "
                                                   << p.time - shift << " s";
            }
            ++checked;
        }
    }
    EXPECT_GT(chained, 1000u);
    EXPECT_GE(checked, 10u);
}

TEST(PatchCache, RoundTripAndBadFiles) {
    const auto& lib = demoWorld().library;
    const auto& gen = fightLibrary();
    const test::TempDir dir("fray_patch_cache_");
    const auto file = dir / "demo.patches";
    ASSERT_TRUE(savePatchLibrary(gen, file));
    auto back = loadPatchLibrary(file, lib);
    ASSERT_TRUE(back) << back.error().message;
    ASSERT_EQ(back->patches().size(), gen.patches().size());
    for (std::size_t i = 0; i < gen.patches().size(); ++i) {
        EXPECT_EQ(back->patches()[i].tracks[0].size(), gen.patches()[i].tracks[0].size());
        EXPECT_EQ(back->patches()[i].initial, gen.patches()[i].initial);
        EXPECT_EQ(back->patches()[i].hits.size(), gen.patches()[i].hits.size());
    }
    EXPECT_EQ(back->patterns(), gen.patterns());
    const std::string bytes = *readWholeFile(file);
    // Actions the project does not have.
    const ActionLibrary recut = ActionLibrary::catalogue({lib.actions().begin(), lib.actions().begin() + 3}, lib.vocabulary());
    auto r = readPatchLibrary(bytes, "x.patches", recut);
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("made from other actions"), std::string::npos);
    r = readPatchLibrary(bytes.substr(0, bytes.size() / 2), "x.patches", lib);
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("x.patches: the patch library is truncated or corrupt"), std::string::npos);
    r = readPatchLibrary("{\"not\": \"binary\"}", "x.patches", lib);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().message, "x.patches: not a Fray patch library");
}

int countAttacks(const Scene& scene, int c, std::uint32_t flag) {
    int n = 0;
    for (const auto& i : scene.characters[static_cast<std::size_t>(c)].track) {
        n += demoWorld().library.actions()[static_cast<std::size_t>(i.action)].is(flag) ? 1 : 0;
    }
    return n;
}

TEST(PatchCompose, OneVsManyMeetsEnemiesInSequenceWithoutCollisions) {
    const auto& lib = demoWorld().library;
    ComposeSpec spec = ComposeSpec::of(OneVsManySpec{});
    auto& own = *spec.part<OneVsManySpec>();
    own.enemies = 10;
    spec.duration = 120;
    ComposeStats st;
    auto scene = compose(lib, fightLibrary(), spec, &st);
    ASSERT_TRUE(scene) << scene.error().message;
    ASSERT_EQ(scene->characters.size(), 11u);
    // Each enemy is knocked down by the main character, one after another.
    double last = -1;
    int met = 0;
    for (int e = 1; e <= 10; ++e) {
        const auto it = std::find_if(scene->hits.begin(), scene->hits.end(),
                                     [&](const HitEvent& h) { return h.attacker == 0 && h.defender == e && !h.blocked; });
        if (it == scene->hits.end()) continue;
        EXPECT_GT(it->time, last) << "enemy " << e << " out of sequence";
        last = it->time;
        ++met;
    }
    EXPECT_GE(met, 8);
    const auto m = computeMetrics(*scene, lib);
    EXPECT_EQ(m.penetrationFrames, 0) << "unintended collisions";
    EXPECT_LE(st.maxJunctionError, 0.3);  // newcomers walk all the way to their patch
    // Other seeds: still no collision.
    for (std::uint64_t seed : {2u, 3u}) {
        ComposeSpec other = spec;
        other.seed = seed;
        other.part<OneVsManySpec>()->enemies = 8;
        auto s2 = compose(lib, fightLibrary(), other);
        ASSERT_TRUE(s2) << s2.error().message;
        EXPECT_EQ(computeMetrics(*s2, lib).penetrationFrames, 0) << "seed " << seed;
    }
    // Newcomers are not in the scene before they walk in.
    for (int e = 2; e <= 10; ++e) EXPECT_FALSE(scene->present(e, 0.5));
    // Same seed, same scene.
    auto again = compose(lib, fightLibrary(), spec);
    ASSERT_TRUE(again);
    EXPECT_EQ(sceneToJson(*scene, lib), sceneToJson(*again, lib));
}

// One-vs-many with many main characters (issue 27): every main character
// knocks its own enemies down one after another, nobody is hit by another
// fight, the fights keep clear of each other (no penetration over the whole
// scene), and the bytes do not depend on the number of threads.
TEST(PatchCompose, ManyMainCharactersFightTheirOwnEnemies) {
    const auto& lib = demoWorld().library;
    ComposeSpec spec = ComposeSpec::of(OneVsManySpec{});
    auto& own = *spec.part<OneVsManySpec>();
    own.mains = 6;
    own.enemies = 4;
    spec.duration = 60;
    spec.seed = 3;
    ComposeStats st;
    auto scene = compose(lib, fightLibrary(), spec, &st);
    ASSERT_TRUE(scene) << scene.error().message;
    ASSERT_EQ(scene->characters.size(), 30u);
    auto indexOf = [&](const std::string& name) {
        for (std::size_t c = 0; c < scene->characters.size(); ++c) {
            if (scene->characters[c].name == name) return static_cast<int>(c);
        }
        return -1;
    };
    auto fightOf = [&](int c) {
        const std::string& n = scene->characters[static_cast<std::size_t>(c)].name;
        return n.substr(0, n.find('/'));
    };
    for (const auto& h : scene->hits) EXPECT_EQ(fightOf(h.attacker), fightOf(h.defender)) << "a blow from another fight";
    int knocked = 0;
    for (int k = 1; k <= 6; ++k) {
        const std::string fight = "fight-" + std::to_string(k) + "/";
        const int mainC = indexOf(fight + "main");
        ASSERT_GE(mainC, 0) << fight;
        double last = -1;
        for (int e = 1; e <= 4; ++e) {
            const int enemy = indexOf(fight + "enemy-" + std::to_string(e));
            ASSERT_GE(enemy, 0) << fight << e;
            const auto it = std::find_if(scene->hits.begin(), scene->hits.end(),
                                         [&](const HitEvent& h) { return h.attacker == mainC && h.defender == enemy && !h.blocked; });
            if (it == scene->hits.end()) continue;
            EXPECT_GT(it->time, last) << fight << "enemy " << e << " out of sequence";
            last = it->time;
            ++knocked;
        }
    }
    EXPECT_GE(knocked, 6 * 3);
    EXPECT_EQ(computeMetrics(*scene, lib).penetrationFrames, 0) << "unintended collisions";
    EXPECT_LE(st.maxJunctionError, 0.3);
    // The fights differ (each its own seed), and stand apart.
    const int main1 = indexOf("fight-1/main"), main2 = indexOf("fight-2/main");
    ASSERT_GE(main1, 0);
    ASSERT_GE(main2, 0);
    EXPECT_GT(glm::length(scene->characters[static_cast<std::size_t>(main1)].track.front().root.pos -
                          scene->characters[static_cast<std::size_t>(main2)].track.front().root.pos),
              6.0f);
    std::string oneThread;
    tbb::task_arena arena(1);
    arena.execute([&] {
        auto again = compose(lib, fightLibrary(), spec);
        ASSERT_TRUE(again);
        oneThread = sceneToJson(*again, lib);
    });
    EXPECT_EQ(oneThread, sceneToJson(*scene, lib));
}

// The one-vs-many crowd of the demo (resources/demo/one_vs_many_crowd.json,
// 1,000 fights of 9; fight k has the crowd's seed + k - 1, so a crowd of two
// with seed k composes fight k first) as good as the demo fight (issue 27):
// the fights where, before, a newcomer walked into its main character (its
// walk was tested against the main character standing where its last action
// left it, not stepping into the patch: 89, 93, 138, 758, 844, 891) or slid
// 27-85 cm in one frame (it walked into a guard shorter than the blend at a
// seam, and the knock-down after it dropped the walk's pose: 171, 297, 486,
// 721) have no penetration, every foot slides less than 20 cm a frame (the
// demo fight's worst is 17.5 cm, a main character's clip) and every enemy is
// knocked down by its own main character.
TEST(PatchCompose, CrowdNewcomersWalkIntoTheirFightsCleanly) {
    const auto& lib = demoWorld().library;
    ComposeSpec spec = ComposeSpec::of(OneVsManySpec{});
    auto& own = *spec.part<OneVsManySpec>();
    own.mains = 2;
    own.enemies = 9;
    spec.duration = 120;
    spec.entryRadius = 8;
    spec.patterns = {"attack-defence-attack-fall", "attack-fall", "attack-attack-fall"};
    spec.commands = {{0.0, "punch", std::nullopt}, {20.0, "kick", std::nullopt}};
    for (const int fight : {89, 93, 138, 171, 297, 486, 721, 758, 844, 891}) {
        spec.seed = static_cast<std::uint64_t>(fight);
        auto scene = compose(lib, fightLibrary(), spec);
        ASSERT_TRUE(scene) << scene.error().message;
        ASSERT_EQ(scene->characters.size(), 20u);
        const auto m = computeMetrics(*scene, lib);
        EXPECT_EQ(m.penetrationFrames, 0) << "fights " << fight << "-" << fight + 1
                                          << (m.penetrations.empty() ? std::string()
                                                                     : ": " + scene->characters[static_cast<std::size_t>(m.penetrations[0].a)].name +
                                                                           " and " + scene->characters[static_cast<std::size_t>(m.penetrations[0].b)].name +
                                                                           " at " + std::to_string(m.penetrations[0].time) + " s");
        for (std::size_t c = 0; c < m.characters.size(); ++c) {
            EXPECT_LT(m.characters[c].footSkateMax, 20.0) << "fights " << fight << "-" << fight + 1 << ": " << scene->characters[c].name;
        }
        std::set<int> knocked;
        for (const auto& h : scene->hits) {
            const auto& attacker = scene->characters[static_cast<std::size_t>(h.attacker)].name;
            const auto& defender = scene->characters[static_cast<std::size_t>(h.defender)].name;
            if (h.blocked || attacker.substr(attacker.find('/')) != "/main") continue;
            EXPECT_EQ(attacker.substr(0, attacker.find('/')), defender.substr(0, defender.find('/')));
            knocked.insert(h.defender);
        }
        EXPECT_EQ(knocked.size(), 18u) << "fights " << fight << "-" << fight + 1;
    }
}

TEST(PatchCompose, UserCommandsSteerTheMainCharacter) {
    const auto& lib = demoWorld().library;
    ComposeSpec spec = ComposeSpec::of(OneVsManySpec{});
    auto& own = *spec.part<OneVsManySpec>();
    own.enemies = 8;
    spec.duration = 120;
    spec.commands = {{0.0, "kick"}};
    auto kicks = compose(lib, fightLibrary(), spec);
    spec.commands = {{0.0, "punch"}};
    auto punches = compose(lib, fightLibrary(), spec);
    ASSERT_TRUE(kicks && punches);
    EXPECT_GT(countAttacks(*kicks, 0, kKick), countAttacks(*punches, 0, kKick));
    EXPECT_GT(countAttacks(*punches, 0, kPunch), countAttacks(*kicks, 0, kPunch));
}

// A move command placed on the floor (the editor's Command tool): once it is
// due the main character walks there, then meets the next enemy there.
TEST(PatchCompose, MoveCommandsWalkTheMainCharacterThere) {
    const auto& lib = demoWorld().library;
    ComposeSpec spec = ComposeSpec::of(OneVsManySpec{});
    spec.part<OneVsManySpec>()->enemies = 6;
    spec.duration = 120;
    const glm::vec2 place(7.0f, 5.0f);
    const auto nearest = [&](const Scene& s, double from) {
        double best = 1e9, when = -1;
        const auto& main = s.characters[0];
        for (const auto& inst : main.track) {
            if (inst.end < from) continue;
            for (double t = std::max(inst.start, from); t <= inst.end; t += 0.1) {
                const double d = glm::length(inst.placementAt(lib, inst.clipTimeAt(t)).pos - place);
                if (d < best) best = d, when = t;
            }
        }
        return std::pair{best, when};
    };
    spec.commands = {{0.0, "punch", std::nullopt}};
    auto still = compose(lib, fightLibrary(), spec);
    ASSERT_TRUE(still) << still.error().message;
    spec.commands = {{0.0, "punch", std::nullopt}, {10.0, "move", place}};
    auto moved = compose(lib, fightLibrary(), spec);
    ASSERT_TRUE(moved) << moved.error().message;
    const auto [before, beforeWhen] = nearest(*still, 10.0);
    const auto [after, afterWhen] = nearest(*moved, 10.0);
    std::printf("main character: nearest %.2f m to the move's place without it, %.2f m at %.1f s with it\n", before, after, afterWhen);
    EXPECT_GT(before, 3.0) << "the place is away from where the fight goes without the command";
    EXPECT_LT(after, 0.5) << "the main character walked there";
    EXPECT_GE(afterWhen, 10.0) << "not before the command's time";
    EXPECT_EQ(computeMetrics(*moved, lib).penetrationFrames, 0);
    // The spec form: "at" [x, z]; a move needs it and belongs to one-vs-many.
    const auto parsed = parseComposeSpec(R"({"kind": "one-vs-many", "commands": [{"time": 2, "action": "move", "at": [7, 5]}]})", "c.json", fightLibrary());
    ASSERT_TRUE(parsed) << parsed.error().message;
    ASSERT_TRUE(parsed->commands[0].at.has_value());
    EXPECT_EQ(*parsed->commands[0].at, place);
    const auto noPlace = parseComposeSpec(R"({"kind": "one-vs-many", "commands": [{"time": 2, "action": "move"}]})", "c.json", fightLibrary());
    ASSERT_FALSE(noPlace);
    EXPECT_NE(noPlace.error().message.find("/commands/0/at"), std::string::npos) << noPlace.error().message;
    const auto otherKind = parseComposeSpec(R"({"kind": "one-vs-one", "commands": [{"time": 2, "action": "move", "at": [1, 1]}]})", "c.json", fightLibrary());
    ASSERT_FALSE(otherKind);
    EXPECT_NE(otherKind.error().message.find("one-vs-many"), std::string::npos) << otherKind.error().message;
}

TEST(PatchCompose, OneVsOneFightsOnWithRecycling) {
    const auto& lib = demoWorld().library;
    ComposeSpec spec = ComposeSpec::of(OneVsOneSpec{});
    spec.duration = 40;
    ComposeStats st;
    auto scene = compose(lib, fightLibrary(), spec, &st);
    ASSERT_TRUE(scene) << scene.error().message;
    ASSERT_EQ(scene->characters.size(), 2u);
    EXPECT_GE(scene->duration, 40.0);
    EXPECT_GE(st.patchesUsed, 5);
    EXPECT_GT(st.temporalLinks + st.recycled, 0);
    EXPECT_LE(st.maxJunctionError, 0.3);
    EXPECT_GE(scene->hits.size(), 3u);
    const auto m = computeMetrics(*scene, lib);
    EXPECT_EQ(m.penetrationFrames, 0);
    // Both characters' tracks are continuous in time.
    for (const auto& c : scene->characters) {
        for (std::size_t i = 1; i < c.track.size(); ++i) EXPECT_NEAR(c.track[i].start, c.track[i - 1].end, 1e-6);
    }
}

// The domino library: falling bodies knocking people over (generated once).
const PatchLibrary& dominoLibrary() {
    static const PatchLibrary lib = [] {
        PatchLibrary out;
        auto st = generatePatches(demoWorld().library, pattern("fall-fall"), PatternSet{}, out);
        if (!st) throw std::runtime_error(st.error().message);
        buildConnections(demoWorld().library, out);
        return out;
    }();
    return lib;
}

// Discs painted on a 16 m x 16 m floor at 0.1 m per pixel.
FloorBitmap discs(const std::vector<std::pair<glm::vec2, float>>& centres) {
    FloorBitmap f;
    f.width = f.height = 160;
    f.metresPerPixel = 0.1;
    f.origin = glm::vec2(-8.0f);
    f.painted.assign(160 * 160, 0);
    for (int y = 0; y < 160; ++y) {
        for (int x = 0; x < 160; ++x) {
            const glm::vec2 p = f.origin + glm::vec2(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f) * 0.1f;
            for (const auto& [c, r] : centres) {
                if (glm::length(p - c) < r) f.painted[static_cast<std::size_t>(y * 160 + x)] = 1;
            }
        }
    }
    return f;
}

bool falls(const SceneCharacter& c) {
    return std::any_of(c.track.begin(), c.track.end(), [](const ActionInstance& i) { return i.forced; }) ||
           (!c.track.empty() && demoWorld().library.actions()[static_cast<std::size_t>(c.track.back().action)].is(kFalling));
}

// Live re-plan of a domino scene (issue 23): after a stroke, every character
// fray::setup::affectedCharacters does not name keeps a byte-identical track
// (matched by name: a longer or shorter chain renumbers no one else).
// Returns how many characters the stroke could affect; fails the test for
// every other character whose track changed.
std::size_t expectOthersKeepTracks(const Scene& before, const Scene& after, const setup::SetupEdit& e, const char* what, int* others) {
    const auto& lib = demoWorld().library;
    const std::vector<int> affected = setup::affectedCharacters(before, lib, e);
    int count = 0, kept = 0;
    for (int c = 0; c < static_cast<int>(before.characters.size()); ++c) {
        if (std::find(affected.begin(), affected.end(), c) != affected.end()) continue;
        ++count;
        const auto& name = before.characters[static_cast<std::size_t>(c)].name;
        const auto it = std::find_if(after.characters.begin(), after.characters.end(), [&](const SceneCharacter& x) { return x.name == name; });
        bool same = it != after.characters.end();
        EXPECT_TRUE(same) << what << ": " << name << " is out of the stroke's reach but gone";
        if (!same) continue;
        const auto& a = before.characters[static_cast<std::size_t>(c)].track;
        const auto& b = it->track;
        same = a.size() == b.size();
        for (std::size_t i = 0; same && i < a.size(); ++i)
            same = a[i].action == b[i].action && a[i].start == b[i].start && a[i].end == b[i].end && a[i].offset == b[i].offset &&
                   a[i].root.pos == b[i].root.pos && a[i].root.heading == b[i].root.heading && a[i].forced == b[i].forced;
        EXPECT_TRUE(same) << what << ": " << name << " is out of the stroke's reach but its track changed";
        kept += same ? 1 : 0;
    }
    std::printf("domino, %s: the stroke could affect %zu of %zu characters; %d of the other %d kept byte-identical tracks\n", what,
                affected.size(), before.characters.size(), kept, count);
    *others = count;
    return affected.size();
}

// A domino scene on a disc of 3 m at (-2, 0) with `background` bystanders,
// composed before and after a stroke (a disc of `radius` at `centre`, painted
// from the start); checks the others' tracks as above.
struct StrokeRun {
    std::size_t characters = 0, affected = 0;
    int others = 0;
};
StrokeRun paintAStroke(ComposeSpec spec, int background, glm::vec2 centre, float radius, const char* what) {
    const auto& lib = demoWorld().library;
    auto& own = *spec.part<DominoSpec>();
    own.floor = discs({{glm::vec2(-2.0f, 0.0f), 3.0f}});
    own.starts = {{0.5, glm::vec2(-2.0f, 0.0f)}};
    own.background = background;
    StrokeRun run;
    auto before = compose(lib, dominoLibrary(), spec);
    ComposeSpec edited = spec;
    edited.part<DominoSpec>()->floor = discs({{glm::vec2(-2.0f, 0.0f), 3.0f}, {centre, radius}});
    auto after = compose(lib, dominoLibrary(), edited);
    if (!before || !after) {
        ADD_FAILURE() << what << ": " << (before ? after.error().message : before.error().message);
        return run;
    }
    setup::SetupEdit e;
    e.kind = setup::SetupEdit::Kind::Stroke;
    e.lo = {centre.x - radius, centre.y - radius}, e.hi = {centre.x + radius, centre.y + radius};
    run.characters = before->characters.size();
    run.affected = expectOthersKeepTracks(*before, *after, e, what, &run.others);
    return run;
}

TEST(PatchCompose, DominoStrokeFarFromTheChainKeepsTheOthersTracks) {
    const StrokeRun run = paintAStroke(ComposeSpec::of(DominoSpec{}), 30, glm::vec2(5.5f, 5.5f), 0.6f, "far stroke");
    EXPECT_GT(run.others, 20);
    EXPECT_LT(run.affected, run.characters / 4);
}

// A stroke on the edge of the painted area changes the chain (it reaches
// someone who falls, and through the hits everyone in the chain); the
// bystanders outside the stroke's reach keep their tracks, because each
// stands in a floor cell chosen from the seed and the painting near it only,
// and, with the spec's duration, stands as long whatever the chain does.
TEST(PatchCompose, DominoStrokeOnTheChainKeepsTheBystandersTracks) {
    ComposeSpec spec = ComposeSpec::of(DominoSpec{});
    spec.duration = 20, spec.durationGiven = true;
    const StrokeRun run = paintAStroke(spec, 60, glm::vec2(1.2f, 0.0f), 0.8f, "stroke on the chain");
    EXPECT_GE(run.others, 15);  // most bystanders stand well away from the stroke
}

TEST(PatchCompose, DominoFallsInsideThePaintedAreaOnly) {
    const auto& lib = demoWorld().library;
    ComposeSpec spec = ComposeSpec::of(DominoSpec{});
    auto& own = *spec.part<DominoSpec>();
    own.floor = discs({{glm::vec2(0.0f), 4.0f}});
    own.starts = {{0.5, glm::vec2(0.0f)}};
    own.background = 30;
    int totalChain = 0;
    double coverage = 0;
    for (std::uint64_t seed : {1u, 3u, 4u}) {
        spec.seed = seed;
        ComposeStats st;
        auto scene = compose(lib, dominoLibrary(), spec, &st);
        ASSERT_TRUE(scene) << scene.error().message;
        ASSERT_NE(st.part<DominoStats>(), nullptr);
        const DominoStats& dst = *st.part<DominoStats>();
        int inside = 0, insideFell = 0, outside = 0, outsideFell = 0;
        for (int c = 0; c < static_cast<int>(scene->characters.size()); ++c) {
            const auto& ch = scene->characters[static_cast<std::size_t>(c)];
            const auto& first = ch.track.front();
            const glm::vec2 standing = first.placementAt(lib, first.offset).pos;
            if (own.floor.paintedAt(standing)) {
                ++inside, insideFell += falls(ch) ? 1 : 0;
            } else {
                ++outside, outsideFell += falls(ch) ? 1 : 0;
            }
        }
        EXPECT_GE(insideFell, 0.95 * inside) << "seed " << seed;
        EXPECT_LE(outsideFell, 0.05 * outside) << "seed " << seed;
        std::printf("seed %llu: %d of 30 bystanders stand (%.2f m from the painted area)\n", static_cast<unsigned long long>(seed), dst.bystanders,
                    dst.bystanderClearance);
        EXPECT_EQ(outside, dst.bystanders);
        EXPECT_EQ(dst.bystanders, 30);
        EXPECT_GE(dst.chainFalls, 3) << "seed " << seed;
        EXPECT_EQ(static_cast<int>(scene->hits.size()), dst.chainFalls);
        // Beyond the first faller's victims, every fall comes through a
        // spatial connection of the patch the faller fell in (SPEC 4.3).
        EXPECT_GE(dst.spatialFalls, dst.chainFalls - 3) << "seed " << seed;
        // How much of the disc the chain fills: 82, 61 and 47 % measured on
        // seeds 1, 3, 4 (57-70 % when fallers were matched by their clip
        // alone; the greedy chains vary with the seed).
        std::printf("seed %llu: %d chain falls (%d by spatial connection), the falls cover %.0f %% of the painted area\n",
                    static_cast<unsigned long long>(seed), dst.chainFalls, dst.spatialFalls, 100.0 * dst.paintedCoverage);
        EXPECT_GE(dst.paintedCoverage, 0.4) << "seed " << seed;
        coverage += dst.paintedCoverage / 3;
        totalChain += dst.chainFalls;
        const auto m = computeMetrics(*scene, lib);
        EXPECT_EQ(m.penetrationFrames, 0) << "seed " << seed;
        // The scene file keeps the painted area for the viewers.
        const std::string text = sceneToJson(*scene, lib);
        auto back = sceneFromJson(text, "d.frayscene", lib);
        ASSERT_TRUE(back) << back.error().message;
        EXPECT_EQ(back->floor, own.floor);
        std::string broken = text;
        const auto rows = broken.find("\"rows\": [");
        ASSERT_NE(rows, std::string::npos);
        broken.insert(broken.find('"', rows + 10) + 1, "7 ");
        auto bad = sceneFromJson(broken, "d.frayscene", lib);
        ASSERT_FALSE(bad);
        EXPECT_EQ(bad.error().message.rfind("d.frayscene: /floor/rows/0: runs add up to", 0), 0u) << bad.error().message;
        // Each fall is caused by the one before it: the pusher is already falling.
        for (const auto& h : scene->hits) {
            const auto& pusher = scene->characters[static_cast<std::size_t>(h.attacker)];
            const int i = scene->instanceAt(h.attacker, h.time);
            EXPECT_TRUE(lib.actions()[static_cast<std::size_t>(pusher.track[static_cast<std::size_t>(i)].action)].is(kFalling));
        }
    }
    EXPECT_GE(totalChain, 25);
    EXPECT_GE(coverage, 0.55) << "the falls cover too little of the disc on average";
}

TEST(PatchCompose, DominoLettersStartWhenTold) {
    const auto& lib = demoWorld().library;
    ComposeSpec spec = ComposeSpec::of(DominoSpec{});
    auto& own = *spec.part<DominoSpec>();
    spec.seed = 4;
    own.floor = discs({{glm::vec2(-4.0f, 0.0f), 2.5f}, {glm::vec2(4.0f, 0.0f), 2.5f}});
    own.starts = {{0.5, glm::vec2(-4.0f, 0.0f)}, {4.0, glm::vec2(4.0f, 0.0f)}};
    own.background = 0;
    auto scene = compose(lib, dominoLibrary(), spec);
    ASSERT_TRUE(scene) << scene.error().message;
    for (const auto& h : scene->hits) {
        const auto& v = scene->characters[static_cast<std::size_t>(h.defender)].track.front();
        const bool right = v.placementAt(lib, v.offset).pos.x > 0;
        if (right) {
            EXPECT_GE(h.time, 4.0);  // the second letter falls only after its start time
        }
    }
    own.starts = {{0.0, glm::vec2(7.5f, 7.5f)}};
    auto bad = compose(lib, dominoLibrary(), spec);
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().message.find("is not on the painted area"), std::string::npos) << bad.error().message;
    own.starts = {{0.0, glm::vec2(-4.0f, 0.0f)}};
    auto none = compose(lib, fightLibrary(), spec);
    ASSERT_FALSE(none);
    EXPECT_NE(none.error().message.find("no patch where a falling body knocks someone over"), std::string::npos);
}

TEST(PatchCompose, LuggageTravelsTheWholeChain) {
    const auto& lib = demoWorld().library;
    PatchLibrary patches;
    for (const char* name : {"carry-walk-hand-receive-turn-carry", "carry-hand-receive-carry"}) {
        ASSERT_TRUE(generatePatches(lib, pattern(name), PatternSet{}, patches));
    }
    buildConnections(lib, patches);
    ASSERT_GT(patches.patches().size(), 10u);
    // Seeds 3 and 18 were stuck before the carrier could pick the item up
    // again and another porter could come (docs/PATCHES.md). In seed 16 the
    // last giver turned through the last receiver as it settled into its
    // idle: the body test took a track that had ended as held at its last frame.
    for (std::uint64_t seed : {1u, 2u, 3u, 5u, 8u, 16u, 18u}) {
        ComposeSpec spec = ComposeSpec::of(LuggageSpec{});
        auto& own = *spec.part<LuggageSpec>();
        spec.seed = seed;
        own.porters = 4;
        own.handoffs = 9;
        spec.duration = 300;
        auto scene = compose(lib, patches, spec);
        ASSERT_TRUE(scene) << scene.error().message;
        // Every hand-over in time order: the one who received last hands next,
        // within 0.6 s of the receiver reaching out and 1.3 m of it.
        struct Event {
            double time;
            int who;
            bool hand;
            glm::vec2 at;
        };
        std::vector<Event> events;
        for (int c = 0; c < static_cast<int>(scene->characters.size()); ++c) {
            for (const auto& i : scene->characters[static_cast<std::size_t>(c)].track) {
                const auto& a = lib.actions()[static_cast<std::size_t>(i.action)];
                if (a.has("hand") || a.has("receive")) events.push_back({i.start, c, a.has("hand"), i.placementAt(lib, i.offset).pos});
            }
        }
        // In time order, a hand before a receive that starts with it.
        std::sort(events.begin(), events.end(), [](const Event& a, const Event& b) {
            return a.time != b.time ? a.time < b.time : a.hand > b.hand;
        });
        const ScenePoser handPoser(*scene, lib);
        std::vector<glm::vec3> handWorld;
        auto handsOf = [&](int c, double t) {
            handPoser.worldPositions(c, t, handWorld);
            const auto& j =
                lib.motion(lib.actions()[static_cast<std::size_t>(scene->characters[static_cast<std::size_t>(c)].track.front().action)].motion).joints;
            return 0.5f * (handWorld[static_cast<std::size_t>(j.leftHand)] + handWorld[static_cast<std::size_t>(j.rightHand)]);
        };
        int handovers = 0, holder = -1;
        std::vector<int> porters;
        for (std::size_t k = 0; k + 1 < events.size(); ++k) {
            if (!events[k].hand) continue;
            const auto& recv = events[k + 1];
            ASSERT_FALSE(recv.hand) << "a hand-over nobody receives (seed " << seed << ")";
            EXPECT_LE(recv.time - events[k].time, 0.6 + 1e-9);
            EXPECT_LE(glm::length(recv.at - events[k].at), 1.3f);
            if (holder >= 0) {
                EXPECT_EQ(events[k].who, holder) << "the item skipped a porter";
            }
            holder = recv.who;
            porters.push_back(recv.who);
            ++handovers;
            // The hands meet (within the patches' 0.35 m) while the receiver receives.
            const auto& inst = *std::find_if(scene->characters[static_cast<std::size_t>(recv.who)].track.begin(),
                                             scene->characters[static_cast<std::size_t>(recv.who)].track.end(),
                                             [&](const ActionInstance& i) { return std::fabs(i.start - recv.time) < 1e-9; });
            double closest = 1e9;
            for (double t = inst.start; t <= inst.end; t += 1.0 / 30) {
                closest = std::min(closest, static_cast<double>(glm::length(handsOf(events[k].who, t) - handsOf(recv.who, t))));
            }
            EXPECT_LE(closest, 0.35) << "seed " << seed << ": hands apart in the hand-over at " << events[k].time << " s";
        }
        EXPECT_EQ(handovers, 9) << "seed " << seed;
        std::sort(porters.begin(), porters.end());
        porters.erase(std::unique(porters.begin(), porters.end()), porters.end());
        EXPECT_EQ(porters.size(), 4u) << "every porter is recycled";
        EXPECT_EQ(computeMetrics(*scene, lib).penetrationFrames, 0) << "seed " << seed;
        // The bag itself travels with them: a one-joint body, never jumping
        // (at most 0.25 m in a 1/15 s key step: passed from hand to hand),
        // ending in the last receiver's hands.
        const auto& bag = scene->characters.back();
        ASSERT_EQ(bag.body, "bag");
        ASSERT_GE(bag.keys.size(), 2u);
        EXPECT_NEAR(bag.keys.back().time, scene->duration, 1e-6);
        auto centre = [&](const RootKey& k) { return k.at.pos + headingVector(k.at.heading) * (0.5f * kBagLength); };
        for (std::size_t k = 1; k < bag.keys.size(); ++k) {
            EXPECT_LE(glm::length(centre(bag.keys[k]) - centre(bag.keys[k - 1])), 0.25f) << "seed " << seed << " at " << bag.keys[k].time << " s";
        }
        const glm::vec3 hands = handsOf(holder, scene->duration);
        EXPECT_LT(glm::length(centre(bag.keys.back()) - glm::vec2(hands.x, hands.z)), 0.05f) << "seed " << seed;
        EXPECT_NEAR(bag.keys.back().height, hands.y, 0.05f);
        auto back = sceneFromJson(sceneToJson(*scene, lib), "l.frayscene", lib);
        ASSERT_TRUE(back) << back.error().message;
        ASSERT_EQ(back->characters.back().keys.size(), bag.keys.size());
        EXPECT_NEAR(back->characters.back().keys[3].height, bag.keys[3].height, 1e-5f);
    }
}

// Every stage on a small library (coarse grid, two variants per entry): the
// sanitizer build runs this one instead of the full-size tests above, which
// take minutes there. What it composes must load back and measure.
TEST(PatchSmoke, SmallLibraryThroughEveryStage) {
    const auto& lib = demoWorld().library;
    GenerateOptions opt;
    opt.maxChoicesPerEntry = 2;
    opt.distanceStep = 0.4;
    opt.angleStepDegrees = 60;
    opt.delayStep = 0.2;
    PatchLibrary out;
    for (const char* name : {"attack-fall", "attack-defence-attack-fall", "fall-fall", "carry-hand-receive-carry"}) {
        auto st = generatePatches(lib, pattern(name), PatternSet{}, out, opt);
        ASSERT_TRUE(st) << name << ": " << st.error().message;
    }
    ASSERT_FALSE(out.patches().empty());
    buildConnections(lib, out);
    const test::TempDir dir("fray_patch_smoke_");
    ASSERT_TRUE(savePatchLibrary(out, dir / "s.patches"));
    auto back = loadPatchLibrary(dir / "s.patches", lib);
    ASSERT_TRUE(back) << back.error().message;
    EXPECT_EQ(back->patches().size(), out.patches().size());

    std::vector<ComposeSpec> specs(5);
    specs[0] = ComposeSpec::of(OneVsManySpec{.enemies = 3}), specs[0].duration = 60;
    specs[1] = ComposeSpec::of(OneVsOneSpec{}), specs[1].duration = 10;
    DominoSpec domino;
    domino.floor = discs({{glm::vec2(0.0f), 3.0f}}), domino.starts = {{0.2, glm::vec2(0.0f)}}, domino.background = 5;
    specs[2] = ComposeSpec::of(domino);
    specs[3] = ComposeSpec::of(LuggageSpec{.porters = 3, .handoffs = 2}), specs[3].duration = 100;
    RatSpec rat;
    rat.ratPath = {{-3, 0}, {3, 0.5f}}, rat.crowd = 12, rat.reach = 0.6;
    specs[4] = ComposeSpec::of(rat);
    int composed = 0;
    for (const auto& spec : specs) {
        auto scene = compose(lib, out, spec);
        if (!scene) {
            // A small library may leave a kind without a fitting patch: then a clear reason.
            EXPECT_FALSE(scene.error().message.empty());
            continue;
        }
        ++composed;
        const std::string json = sceneToJson(*scene, lib);
        auto again = sceneFromJson(json, "smoke.frayscene", lib);
        ASSERT_TRUE(again) << again.error().message;
        EXPECT_EQ(sceneToJson(*again, lib), json);
        const auto m = computeMetrics(*scene, lib);
        EXPECT_EQ(m.characters.size(), scene->characters.size());
    }
    EXPECT_GE(composed, 3) << specs[0].kind;
}

// American football (SPEC 4.5): the carrier runs for the goal line the way
// the user points, and gets past every tackler that dives at it.
TEST(PatchCompose, FootballCarrierReachesTheGoalPastTheTacklers) {
    const auto& lib = footballWorld().library;
    PatchLibrary patches;
    ASSERT_TRUE(generatePatches(lib, pattern("run-tackle-avoid"), PatternSet{}, patches));
    buildConnections(lib, patches);
    ASSERT_GE(patches.patches().size(), 10u);
    // Spread over the grid: tacklers from near and far, not the first row only.
    double nearest = 1e9, farthest = 0;
    for (const auto& p : patches.patches()) nearest = std::min(nearest, p.initial.r), farthest = std::max(farthest, p.initial.r);
    EXPECT_GE(farthest - nearest, 1.0);
    for (const auto& p : patches.patches()) {
        EXPECT_TRUE(p.hits.empty()) << "a kept tackle patch where the tackle lands";
        EXPECT_TRUE(lib.actions()[static_cast<std::size_t>(p.tracks[1].front().action)].is(kTackle));
        EXPECT_TRUE(lib.actions()[static_cast<std::size_t>(p.tracks[0].back().action)].is(kAvoid));
    }
    // Three runs: the arrow swings right then left, the mirror of that, and
    // straight on (the seed only breaks ties, so the arrows make the difference).
    const double turns[][2] = {{25, -20}, {-25, 20}, {0, 0}};
    for (std::uint64_t seed : {1u, 2u, 3u}) {
        const double first = turns[seed - 1][0] * kDeg, second = turns[seed - 1][1] * kDeg;
        ComposeSpec spec = ComposeSpec::of(FootballSpec{});
        auto& own = *spec.part<FootballSpec>();
        spec.seed = seed;
        own.tacklers = 5;
        own.goal = 40;
        spec.duration = 60;
        own.directions = {{0.0, 0.0}, {5.0, first}, {10.0, second}};
        ComposeStats all;
        auto scene = compose(lib, patches, spec, &all);
        ASSERT_TRUE(scene) << scene.error().message;
        ASSERT_NE(all.part<FootballStats>(), nullptr);
        const FootballStats& stats = *all.part<FootballStats>();
        // The carrier crosses the goal line past at least three tacklers and is never hit.
        EXPECT_GE(stats.goalReached, 0.0) << "seed " << seed;
        EXPECT_GE(stats.tacklersPassed, 3) << "seed " << seed;
        int dives = 0;
        for (const auto& c : scene->characters) {
            for (const auto& i : c.track) dives += lib.actions()[static_cast<std::size_t>(i.action)].is(kTackle) ? 1 : 0;
        }
        EXPECT_EQ(dives, stats.tacklersPassed);
        for (const auto& h : scene->hits) EXPECT_NE(h.defender, 0) << "the carrier was tackled at " << h.time << " s";
        const auto m = computeMetrics(*scene, lib);
        EXPECT_EQ(m.penetrationFrames, 0) << "seed " << seed;
        // It runs the way the user points: its mean direction of travel over
        // the second half of each direction's time is within 15 degrees of it.
        const auto& carrier = scene->characters[0].track;
        auto where = [&](double t) {
            const auto& i = carrier[static_cast<std::size_t>(instanceIndexAt(carrier, t))];
            return i.placementAt(lib, i.clipTimeAt(t)).pos;
        };
        const double windows[][3] = {{2.5, 5.0, 0.0}, {7.5, 10.0, first}, {12.5, 15.0, second}};
        for (const auto& [t0, t1, want] : windows) {
            if (t1 > stats.goalReached) break;
            const double got = angleOf(where(t1) - where(t0));
            EXPECT_LT(std::fabs(wrapAngle(got - want)), 15 * kDeg) << "seed " << seed << ", " << t0 << "-" << t1 << " s";
        }
        // Same seed, same scene.
        auto again = compose(lib, patches, spec);
        ASSERT_TRUE(again);
        const std::string text = sceneToJson(*scene, lib);
        EXPECT_EQ(sceneToJson(*again, lib), text);
        // The scene file keeps the goal line and the arrows for the viewers.
        ASSERT_EQ(scene->marks.size(), 4u);
        EXPECT_EQ(scene->marks[0].kind, "goal");
        EXPECT_FLOAT_EQ(scene->marks[0].points[0].y, 40.0f);
        EXPECT_EQ(scene->marks[3].kind, "arrow");
        auto back = sceneFromJson(text, "f.frayscene", lib);
        ASSERT_TRUE(back) << back.error().message;
        EXPECT_EQ(back->marks, scene->marks);
        // Two tacklers at once where the spatial table joins two patches (the
        // carrier's very same run and cut, the tacklers never meeting).
        ComposeSpec doubles = spec;
        doubles.part<FootballSpec>()->doubles = true;
        ComposeStats twoStats;
        auto two = compose(lib, patches, doubles, &twoStats);
        ASSERT_TRUE(two) << two.error().message;
        ASSERT_NE(twoStats.part<FootballStats>(), nullptr);
        const FootballStats& ds = *twoStats.part<FootballStats>();
        EXPECT_GE(ds.secondTacklers, 1) << "seed " << seed;
        EXPECT_GE(ds.tacklersPassed, 3);
        EXPECT_GE(ds.goalReached, 0.0);
        EXPECT_TRUE(two->hits.empty());
        EXPECT_EQ(computeMetrics(*two, lib).penetrationFrames, 0) << "seed " << seed;
        std::string broken = text;
        broken.replace(broken.find("\"points\": ["), 12, "\"points\": 7, \"x\": [");
        auto bad = sceneFromJson(broken, "f.frayscene", lib);
        ASSERT_FALSE(bad);
        EXPECT_NE(bad.error().message.find("f.frayscene: /marks/0/"), std::string::npos) << bad.error().message;
    }
}

// Rat avoiding (SPEC 4.5): everyone standing within reach of the rat's
// trajectory gets out of its way, or is pushed out of it by a neighbour, or
// (with no way out) reels back; the rat never runs over feet that stay put.
TEST(PatchCompose, RatCrowdGetsOutOfTheWay) {
    const auto& lib = demoWorld().library;
    ComposeSpec spec = ComposeSpec::of(RatSpec{});
    auto& own = *spec.part<RatSpec>();
    own.ratPath = {{-7, -2}, {-3, 1}, {0, -1}, {3, 1.5f}, {7, 0}};
    own.crowd = 70;
    own.spacing = 0.8;
    const PatchLibrary none;  // the rat scene generates its own patches
    EXPECT_FALSE(composeNeedsPatches(R"({"kind": "rat"})"));
    EXPECT_TRUE(composeNeedsPatches(R"({"kind": "domino"})"));
    EXPECT_TRUE(composeNeedsPatches("[1, 2"));
    int bumps = 0, near = 0;
    for (std::uint64_t seed : {1u, 2u, 3u}) {
        spec.seed = seed;
        ComposeStats all;
        auto scene = compose(lib, none, spec, &all);
        ASSERT_TRUE(scene) << scene.error().message;
        ASSERT_NE(all.part<RatStats>(), nullptr);
        const RatStats& st = *all.part<RatStats>();
        ASSERT_FALSE(scene->characters.empty());
        const auto& rat = scene->characters[0];
        ASSERT_EQ(rat.body, "rat");
        EXPECT_TRUE(rat.track.empty());
        EXPECT_FALSE(scene->present(0, 3.0)) << "a creature is not a body for planners and metrics";
        ASSERT_GE(rat.keys.size(), 2u);
        EXPECT_NEAR(rat.keys.front().time, 0.0, 1e-9);
        // It runs the whole trajectory at its speed from its start.
        double length = 0;
        for (std::size_t i = 0; i + 1 < own.ratPath.size(); ++i) length += static_cast<double>(glm::length(own.ratPath[i + 1] - own.ratPath[i]));
        EXPECT_NEAR(rat.keys.back().time, own.ratStart + length / own.ratSpeed, 0.11);
        EXPECT_LT(glm::length(rat.keys.back().at.pos - own.ratPath.back()), 1e-3f);
        EXPECT_EQ(static_cast<int>(scene->characters.size()), own.crowd + 1);
        EXPECT_GE(st.ratNear, 8) << "seed " << seed;
        EXPECT_EQ(st.ratAvoided + st.ratPushed + st.ratStartled + st.ratRunOver, st.ratNear) << "seed " << seed;
        EXPECT_EQ(st.ratRunOver, 0) << "seed " << seed;
        EXPECT_GE(st.ratAvoided, 0.7 * st.ratNear) << "seed " << seed;
        EXPECT_GE(st.ratClearance, 0.08);
        std::printf("seed %llu: %d near the rat: %d avoided, %d pushed, %d reeled back; %d bumps\n",
                    static_cast<unsigned long long>(seed), st.ratNear, st.ratAvoided, st.ratPushed, st.ratStartled, st.bumps);
        // Checked here on the played-back poses, independently of the composer:
        const ScenePoser poser(*scene, lib);
        std::vector<glm::vec3> world;
        int nearHere = 0;
        for (int c = 1; c < static_cast<int>(scene->characters.size()); ++c) {
            const auto& track = scene->characters[static_cast<std::size_t>(c)].track;
            ASSERT_FALSE(track.empty());
            const glm::vec2 spot = track.front().placementAt(lib, track.front().offset).pos;
            double pass = -1, closest = 1e9;
            for (double t = own.ratStart; t <= rat.keys.back().time; t += 0.02) {
                const double d = static_cast<double>(glm::length(creatureAt(rat, t).pos - spot));
                if (d < closest) closest = d, pass = t;
            }
            bool moved = false, forced = false;
            for (const auto& inst : track) {
                forced = forced || inst.forced;
                if (!lib.actions()[static_cast<std::size_t>(inst.action)].is(kIdle) && inst.start < pass + 0.6) moved = true;
            }
            // (a) Everyone within reach moves (steps aside, or is pushed) before the rat is past.
            if (closest < own.reach) {
                ++nearHere;
                EXPECT_TRUE(moved) << "seed " << seed << ": person " << c << " stood still as the rat passed " << closest << " m away";
            }
            if (forced) continue;
            // (b) The rat's body never touches the feet of someone who was not knocked off them.
            const auto& joints = lib.motion(lib.actions()[static_cast<std::size_t>(track.front().action)].motion).joints;
            for (double t = pass - 0.5; t <= pass + 0.5; t += 1.0 / 30) {
                poser.worldPositions(c, t, world);
                const RootXf r = creatureAt(rat, t);
                for (int j : {joints.leftFoot, joints.rightFoot, joints.leftToe, joints.rightToe}) {
                    if (j < 0) continue;
                    const glm::vec2 foot(world[static_cast<std::size_t>(j)].x, world[static_cast<std::size_t>(j)].z);
                    for (float along : {0.0f, 0.5f, 1.0f}) {
                        const float d = glm::length(foot - (r.pos + headingVector(r.heading) * (along * kRatLength)));
                        EXPECT_GT(d, 0.08f) << "seed " << seed << ": the rat ran over person " << c << "'s foot at " << t << " s";
                    }
                }
            }
        }
        EXPECT_EQ(nearHere, st.ratNear) << "seed " << seed;
        // Bumps are contacts: the pushed one starts its reaction then.
        EXPECT_EQ(static_cast<int>(scene->hits.size()), st.bumps);
        for (const auto& h : scene->hits) {
            const auto& pushed = scene->characters[static_cast<std::size_t>(h.defender)].track;
            const auto& inst = pushed[static_cast<std::size_t>(instanceIndexAt(pushed, h.time + 1e-6))];
            EXPECT_TRUE(inst.forced);
            EXPECT_NEAR(inst.start, h.time, 1e-9);
            EXPECT_GT(h.attacker, 0) << "the rat pushes no one on record";
        }
        bumps += st.bumps;
        near += st.ratNear;
        EXPECT_EQ(computeMetrics(*scene, lib).penetrationFrames, 0) << "seed " << seed;
        // Same seed, same scene; the file keeps the rat's body and keys and the trail.
        const std::string text = sceneToJson(*scene, lib);
        auto again = compose(lib, none, spec);
        ASSERT_TRUE(again);
        EXPECT_EQ(sceneToJson(*again, lib), text);
        auto back = sceneFromJson(text, "r.frayscene", lib);
        ASSERT_TRUE(back) << back.error().message;
        EXPECT_EQ(back->characters[0].body, "rat");
        ASSERT_EQ(back->characters[0].keys.size(), rat.keys.size());
        EXPECT_LT(glm::length(back->characters[0].keys[5].at.pos - rat.keys[5].at.pos), 1e-5f);
        ASSERT_EQ(back->marks.size(), 1u);
        EXPECT_EQ(back->marks[0].kind, "trail");
        EXPECT_EQ(&ScenePoser(*back, lib).skeleton(0), creatureSkeleton("rat"));
        std::string dog = text;
        dog.replace(dog.find("\"body\": \"rat\""), 13, "\"body\": \"dog\"");
        auto bad = sceneFromJson(dog, "r.frayscene", lib);
        ASSERT_FALSE(bad);
        EXPECT_EQ(bad.error().message.rfind("r.frayscene: /characters/0/body: unknown body 'dog'", 0), 0u) << bad.error().message;
    }
    EXPECT_GE(bumps, 2) << "nobody bumped into anyone in three crowds of " << own.crowd;
    EXPECT_GE(near, 30);
}

// The rat's {run, AVOID} patches (SPEC 4.5): initial conditions on the SPEC
// grid, and every patch, played back on its own against a straight rat, keeps
// the rat off the person's feet.
TEST(PatchCompose, RatAvoidPatchesKeepTheRatOffTheFeet) {
    const auto& lib = demoWorld().library;
    ComposeSpec spec = ComposeSpec::of(RatSpec{});
    auto& own = *spec.part<RatSpec>();
    own.ratPath = {{0, -5}, {0, 5}};
    own.reach = 1.0;
    own.ratSpeed = 2.5;
    auto table = ratAvoidPatches(lib, spec);
    ASSERT_TRUE(table) << table.error().message;
    ASSERT_GT(table->size(), 1000u);
    std::set<std::pair<long, long>> cells, withPatch;
    for (long l = -6; l <= 6; ++l) {
        for (long f = -9; f < 9; ++f) cells.insert({l, f});
    }
    for (const auto& p : *table) {
        const double l = p.lateral / 0.2, f = p.facing / (std::numbers::pi / 9), k = p.lead / 0.1;
        ASSERT_NEAR(l, std::round(l), 1e-9);
        ASSERT_NEAR(f, std::round(f), 1e-9);
        ASSERT_NEAR(k, std::round(k), 1e-9);
        ASSERT_LE(std::abs(p.lateral), own.reach + 0.2 + 1e-9);
        ASSERT_GT(p.lead, 0.0);
        ASSERT_GE(p.clearance, 0.08);
        ASSERT_FALSE(p.actions.empty());
        withPatch.insert({std::lround(l), std::lround(f) == 9 ? -9 : std::lround(f)});
    }
    // Someone can get out of the rat's way from nearly every configuration within reach.
    int within = 0, covered = 0;
    for (const auto& c : cells) {
        if (std::abs(c.first) > 5) continue;
        ++within;
        covered += withPatch.count(c) ? 1 : 0;
    }
    EXPECT_GE(covered, 0.9 * within) << covered << " of " << within << " cells have a patch";

    // Played back: the person stands in the guard (the longest idle) at the
    // origin, turned `facing` from +Z; the rat runs along +Z, `lateral` m to
    // the person's right (x = -lateral: +X is the left of someone facing +Z).
    int hold = -1;
    double longest = -1;
    for (int a = 0; a < lib.size(); ++a) {
        if (lib.actions()[static_cast<std::size_t>(a)].is(kIdle) && lib.actions()[static_cast<std::size_t>(a)].duration > longest) {
            longest = lib.actions()[static_cast<std::size_t>(a)].duration, hold = a;
        }
    }
    ASSERT_GE(hold, 0);
    constexpr double kPass = 3.0;
    std::vector<glm::vec3> world;
    const std::size_t stride = std::max<std::size_t>(1, table->size() / 400);
    int checked = 0;
    for (std::size_t i = 0; i < table->size(); i += stride) {
        const auto& p = (*table)[i];
        Scene scene;
        SceneCharacter person;
        person.name = "person";
        const RootXf at{glm::vec2(0.0f), p.facing};
        const double ts = kPass - p.lead;
        person.track.push_back({hold, 0.0, 0.0, ts, at * lib.rootAt(hold, 0).inverse(), false, false});
        RootXf place = at * lib.rootAt(p.actions.front(), 0).inverse();
        double t = ts;
        for (int a : p.actions) {
            const auto& A = lib.actions()[static_cast<std::size_t>(a)];
            person.track.push_back({a, t, 0.0, t + A.duration, place, false, false});
            place = place * A.end;
            t += A.duration;
        }
        scene.characters.push_back(person);
        const ScenePoser poser(scene, lib, 0.0);
        const auto& joints = lib.motion(lib.actions()[static_cast<std::size_t>(hold)].motion).joints;
        for (double tt = kPass - 0.5; tt <= std::min(t, kPass + 0.5); tt += 1.0 / 30) {
            poser.worldPositions(0, tt, world);
            const glm::vec2 rat(static_cast<float>(-p.lateral), static_cast<float>(own.ratSpeed * (tt - kPass)));
            for (int j : {joints.leftFoot, joints.rightFoot, joints.leftToe, joints.rightToe}) {
                if (j < 0) continue;
                const glm::vec2 foot(world[static_cast<std::size_t>(j)].x, world[static_cast<std::size_t>(j)].z);
                for (float along : {0.0f, 0.5f, 1.0f}) {
                    const float d = glm::length(foot - (rat + glm::vec2(0.0f, along * kRatLength)));
                    ASSERT_GT(d, 0.08f) << "patch " << i << " (lateral " << p.lateral << " m, facing " << p.facing << ", lead " << p.lead
                                        << " s): the rat runs over a foot at " << tt - kPass << " s";
                }
            }
        }
        ++checked;
    }
    EXPECT_GE(checked, 300);
    // A project with nothing to step aside with (its avoids and steps
    // annotated as idles) has no patches, and says why.
    prep::Project stillProject = demoWorld().project;
    for (auto& m : stillProject.motions) {
        for (auto& a : m.actions.actions) {
            const bool moves = std::any_of(a.annotations.begin(), a.annotations.end(),
                                           [](const std::string& w) { return w == "avoid" || w == "dodge" || w == "step"; });
            if (moves) a.annotations = {"idle"};
        }
    }
    auto still = buildActionLibrary(stillProject, demoWorld().motions, demoWorld().graph);
    ASSERT_TRUE(still) << still.error().message;
    auto none = ratAvoidPatches(*still, spec);
    ASSERT_FALSE(none);
    EXPECT_NE(none.error().message.find("no avoid or step action"), std::string::npos) << none.error().message;
}

TEST(PatchCompose, SpecErrorsNameTheField) {
    const auto& lib = fightLibrary();
    const std::pair<std::string, std::string> bad[] = {
        {R"({"kind": "domino-ish"})", "c.json: /kind: unknown scene kind 'domino-ish'"},
        {R"({"kind": "one-vs-many", "enemies": 0})", "c.json: /enemies: must be between 1 and 1000"},
        {R"({"kind": "one-vs-many", "patterns": ["nope"]})", "c.json: /patterns/0: no pattern 'nope' in the patch library"},
        {R"({"kind": "one-vs-many", "commands": [{"time": 1, "action": "dance"}]})", "c.json: /commands/0/action: unknown command 'dance'"},
        {R"({"kind": "one-vs-many", "duration": -3})", "c.json: /duration: must be in (0, 3600] seconds"},
        {R"({"kind": "one-vs-many", "color": 1})", "c.json: /color: unknown field"},
        {R"([1, 2)", "c.json: /: not valid JSON"},
        {R"({"kind": "domino", "starts": [{"time": 0, "x": 0, "z": 0}]})", "c.json: /floor: a domino scene needs a floor bitmap"},
        {R"({"kind": "domino", "floor": {"bitmap": "a.png"}})", "c.json: /starts: a domino scene needs at least one start"},
        {R"({"kind": "domino", "floor": {"bitmap": "a.png", "metres_per_pixel": 0}, "starts": []})", "c.json: /floor/metres_per_pixel: must be in"},
        {R"({"kind": "domino", "floor": {"bitmap": "a.png"}, "starts": [{"time": 0, "x": 0}]})", "c.json: /starts/0/z: missing"},
        {R"({"kind": "luggage", "porters": 1})", "c.json: /porters: must be between 2 and 100"},
        {R"({"kind": "football", "directions": [{"time": 0, "heading_deg": 95}]})", "c.json: /directions/0/heading_deg: must be within 80 degrees"},
        {R"({"kind": "football", "directions": [{"time": 3, "heading_deg": 0}, {"time": 1, "heading_deg": 0}]})", "c.json: /directions/1/time: directions must be in time order"},
        {R"({"kind": "football", "directions": [{"time": 0, "angle": 0}]})", "c.json: /directions/0/angle: unknown field"},
        {R"({"kind": "football", "tacklers": 0})", "c.json: /tacklers: must be between 1 and 1000"},
        {R"({"kind": "football", "doubles": "yes"})", "c.json: /doubles: must be true or false"},
        {R"({"kind": "rat"})", "c.json: /rat: a rat scene needs the rat's trajectory"},
        {R"({"kind": "rat", "rat": {"path": []}})", "c.json: /rat/path: the rat's trajectory is empty"},
        {R"({"kind": "rat", "rat": {"path": [[0, 0], [0, 0.1]]}})", "c.json: /rat/path: the rat's trajectory is empty"},
        {R"({"kind": "rat", "rat": {"path": [[0, 0], [0]]}})", "c.json: /rat/path/1: must be [x, z]"},
        {R"({"kind": "rat", "rat": {"path": [[0, 0], [0, 5]], "speed": 0}})", "c.json: /rat/speed: must be in [0.3, 10] m/s"},
        {R"({"kind": "rat", "rat": {"path": [[0, 0], [0, 5]], "size": 1}})", "c.json: /rat/size: unknown field"},
        {R"({"kind": "rat", "rat": {"path": [[0, 0], [0, 5]]}, "bumps": 2})", "c.json: /bumps: must be in [0, 1]"},
        {R"({"kind": "rat", "rat": {"path": [[0, 0], [0, 5]]}, "crowd": 0})", "c.json: /crowd: must be between 1 and 20000"},
    };
    for (const auto& [text, message] : bad) {
        const auto r = parseComposeSpec(text, "c.json", lib);
        ASSERT_FALSE(r) << text;
        EXPECT_EQ(r.error().message.rfind(message, 0), 0u) << r.error().message;
    }
    PatchLibrary empty;
    EXPECT_FALSE(compose(demoWorld().library, empty, ComposeSpec::of(OneVsManySpec{})));
}

}  // namespace
}  // namespace fray::sim
