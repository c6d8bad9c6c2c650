// Composition at scale (issue 27): the floor grid that replaces passes over
// every character, and a domino crowd of a few thousand over a large painted
// field (the 10,000-character demo is measured by fray-bench, BM_DominoCrowd).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <numbers>
#include <random>
#include <set>

#include <nlohmann/json.hpp>
#include <tbb/task_arena.h>

#include "compose_grid.h"
#include "interaction.h"
#include "fray/sim/compose.h"
#include "fray/sim/compose/domino.h"
#include "fray/sim/compose/football.h"
#include "fray/sim/compose/rat.h"
#include "fray/sim/metrics.h"
#include "fray/sim/patches.h"
#include "fray/sim/patterns.h"
#include "sim/demo_world.h"
#include "sim/scene_crop.h"

namespace fray::sim {
namespace {

using test::demoWorld;
using test::footballWorld;

// Every box that overlaps the query box is among the grid's candidates, and
// the candidates come in increasing order, each once.
TEST(FloorGrid, NearFindsEveryOverlapInOrder) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> pos(-30.0f, 30.0f), size(0.0f, 3.0f);
    auto box = [&] {
        const glm::vec2 lo(pos(rng), pos(rng));
        return SweptBox{lo, lo + glm::vec2(size(rng), size(rng))};
    };
    std::vector<SweptBox> boxes;
    detail::FloorGrid grid(2.0f);
    for (int i = 0; i < 2000; ++i) {
        boxes.push_back(box());
        grid.insert(i, boxes.back());
    }
    grid.insert(2000, SweptBox::empty());  // an empty box is in no cell
    int found = 0;
    for (int q = 0; q < 500; ++q) {
        const SweptBox query = box();
        const std::vector<int> near = grid.near(query);
        EXPECT_TRUE(std::is_sorted(near.begin(), near.end()));
        EXPECT_EQ(std::adjacent_find(near.begin(), near.end()), near.end());
        EXPECT_EQ(std::count(near.begin(), near.end(), 2000), 0);
        for (int i = 0; i < 2000; ++i) {
            if (!boxes[static_cast<std::size_t>(i)].overlaps(query)) continue;
            ++found;
            EXPECT_TRUE(std::binary_search(near.begin(), near.end(), i)) << "box " << i << " missed by query " << q;
        }
        EXPECT_LT(near.size(), 200u);  // the neighbourhood, not everyone
    }
    EXPECT_GT(found, 100);
}

// The floor discs round the core boxes (the composers' first body test):
// two bodies whose discs are apart never overlap by coreBodiesOverlap, near
// the origin and far out (the rounding of placing them), and the discs do
// tell apart most pairs within the pelvis reach (the test is worth making).
TEST(CoreDiscs, ApartBodiesNeverOverlap) {
    const auto& lib = demoWorld().library;
    constexpr float kShrink = 0.82f;
    const detail::CoreDiscs discs(lib, kShrink);
    std::mt19937 rng(11);
    std::uniform_int_distribution<int> action(0, lib.size() - 1);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    int near = 0, apart = 0, overlapping = 0;
    for (const float far : {0.0f, 3000.0f}) {
        for (int i = 0; i < 20000; ++i) {
            auto pose = [&](glm::vec2 at) {
                const int a = action(rng);
                const double tau = unit(rng) * lib.actions()[static_cast<std::size_t>(a)].duration;
                const double heading = (unit(rng) * 2 - 1) * std::numbers::pi;
                const RootXf clip = lib.rootAt(a, tau);
                // Its pelvis near `at`: the clip's first frame placed so.
                RootXf root{at, heading};
                root.pos -= FloorRotation(heading)(clip.pos);
                return detail::BodyPose{a, tau, root};
            };
            const glm::vec2 base(far, -far);
            const float d = static_cast<float>(unit(rng)) * 1.2f;
            const double dir = unit(rng) * 2 * std::numbers::pi;
            const detail::CoreBody a(lib, pose(base), kShrink), b(lib, pose(base + d * headingVector(dir)), kShrink);
            const bool overlap = detail::coreBodiesOverlap(a, b, 1.2f);
            const bool discsApart = detail::CoreDiscs::apart(discs.placed(a), discs.placed(b));
            ++near;
            apart += discsApart ? 1 : 0;
            overlapping += overlap ? 1 : 0;
            EXPECT_FALSE(discsApart && overlap) << "pair " << i << " at " << far << " m";
        }
    }
    EXPECT_GT(overlapping, 1000);  // both answers occur
    EXPECT_GT(apart, near / 4);    // the discs spare the boxes of many pairs
}

// The swept spheres (the rat's test of a neighbour's whole instance): a body
// whose core spheres are apart from the swept spheres of a clip placed
// somewhere overlaps by coreBodiesOverlap no body playing that clip there, at
// any of its samples, near the origin and far out; the spheres placed are the
// boxes' (CoreBody::boxes: the same floats), and the test tells apart many
// pairs within the pelvis reach (it is worth making).
TEST(CoreSpheres, ApartFromTheSweptSpheresNeverOverlaps) {
    const auto& lib = demoWorld().library;
    constexpr float kShrink = 0.82f;
    const detail::CoreSpheres spheres(lib, kShrink);
    std::mt19937 rng(12);
    std::uniform_int_distribution<int> action(0, lib.size() - 1);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    int pairs = 0, apart = 0, overlapping = 0;
    for (const float far : {0.0f, 3000.0f}) {
        for (int i = 0; i < 1500; ++i) {
            const glm::vec2 base(far, -far);
            const int a = action(rng), b = action(rng);
            const auto& A = lib.actions()[static_cast<std::size_t>(a)];
            const auto& B = lib.actions()[static_cast<std::size_t>(b)];
            const double tau = unit(rng) * A.duration;
            const RootXf ra{base, (unit(rng) * 2 - 1) * std::numbers::pi};
            const float d = static_cast<float>(unit(rng)) * 1.2f;
            const RootXf rb{base + d * headingVector(unit(rng) * 2 * std::numbers::pi), (unit(rng) * 2 - 1) * std::numbers::pi};
            const detail::CoreBody me(lib, detail::BodyPose{a, tau, ra}, kShrink);
            const int sample = lib.sampleAt(a, tau);
            const auto mine = spheres.placed(a, sample, ra, me.rotation());
            for (std::size_t k = 0; k < mine.centre.size(); ++k) {
                ASSERT_EQ(mine.centre[k], me.boxes()[k].centre);
                ASSERT_EQ(mine.radius[k], me.radii()[k]);
            }
            const bool sweptApart = detail::CoreSpheres::apart(mine, spheres.swept(b, rb));
            apart += sweptApart ? 1 : 0;
            for (int s = 0; s < B.sampleCount; ++s) {
                const detail::CoreBody them(lib, detail::BodyPose{b, (s + 0.5) / kSampleRate, rb}, kShrink);
                const bool overlap = detail::coreBodiesOverlap(me, them, 1e9f);  // the spheres and boxes alone
                ++pairs;
                overlapping += overlap ? 1 : 0;
                EXPECT_FALSE(sweptApart && overlap) << "pair " << i << " sample " << s << " at " << far << " m";
            }
        }
    }
    std::printf("CoreSpheres: %d pairs, %d overlapping, %d of 3000 apart\n", pairs, overlapping, apart);
    EXPECT_GT(overlapping, pairs / 20);  // both answers occur
    EXPECT_GT(apart, 3000 / 5);          // many bodies need no box of the clip's
}

const PatchLibrary& fallLibrary() {
    static const PatchLibrary lib = [] {
        PatchLibrary out;
        for (const auto& p : defaultPatterns()) {
            if (p.name != "fall-fall") continue;
            if (auto st = generatePatches(demoWorld().library, p, PatternSet{}, out); !st) throw std::runtime_error(st.error().message);
        }
        buildConnections(demoWorld().library, out);
        return out;
    }();
    return lib;
}

// A 60 m x 60 m painted field at 0.5 m a pixel with a hole in the middle.
FloorBitmap field() {
    FloorBitmap f;
    f.width = f.height = 120;
    f.metresPerPixel = 0.5;
    f.origin = glm::vec2(-30.0f);
    f.painted.assign(120 * 120, 1);
    for (int y = 56; y < 64; ++y) {
        for (int x = 56; x < 64; ++x) f.painted[static_cast<std::size_t>(y * 120 + x)] = 0;
    }
    return f;
}

// Thousands of people over a large painted field, every one of them knocked
// over by the one before (none left standing idle), without bodies passing
// through each other (measured on windows of the scene), the same bytes for
// the same seed.
TEST(ComposeScale, DominoCrowdFillsALargeField) {
    const auto& lib = demoWorld().library;
    DominoSpec domino;
    domino.floor = field();
    for (int z = -25; z <= 25; z += 10) {
        for (int x = -25; x <= 25; x += 10) domino.starts.push_back({0.5 + 0.1 * (x + z + 50) / 10, glm::vec2(x, z)});
    }
    domino.background = 0;
    domino.maxCharacters = 3000;
    ComposeSpec spec = ComposeSpec::of(domino);
    spec.seed = 3;
    ComposeStats st;
    auto scene = compose(lib, fallLibrary(), spec, &st);
    ASSERT_TRUE(scene) << scene.error().message;
    const auto* ds = st.part<DominoStats>();
    ASSERT_NE(ds, nullptr);
    const int n = static_cast<int>(scene->characters.size());
    std::printf("%d characters, %d chain falls, %.0f %% of the field covered, composed in %.2f s\n", n, ds->chainFalls,
                100.0 * ds->paintedCoverage, st.seconds);
    EXPECT_GE(n, 1300);
    EXPECT_EQ(ds->chainFalls + static_cast<int>(domino.starts.size()), n) << "everyone but the starts is knocked over";
    EXPECT_EQ(static_cast<int>(scene->hits.size()), ds->chainFalls);
    EXPECT_GE(ds->paintedCoverage, 0.5);
    for (const auto& [lo, hi] : {std::pair{glm::vec2(-30.0f, -30.0f), glm::vec2(-22.0f, -22.0f)},
                                 std::pair{glm::vec2(4.0f, 6.0f), glm::vec2(12.0f, 14.0f)}}) {
        const Scene window = test::cropScene(*scene, lib, lo, hi);
        ASSERT_GE(window.characters.size(), 20u);
        const auto m = computeMetrics(window, lib);
        EXPECT_EQ(m.penetrationFrames, 0) << "window at (" << lo.x << ", " << lo.y << ")";
    }
    auto again = compose(lib, fallLibrary(), spec);
    ASSERT_TRUE(again);
    EXPECT_EQ(sceneToJson(*again, lib), sceneToJson(*scene, lib));
}

// The football library's run-tackle-avoid patches with their connection tables.
void footballRunPatches(const ActionLibrary& lib, PatchLibrary& patches) {
    for (const auto& p : defaultPatterns()) {
        if (p.name == "run-tackle-avoid") {
            ASSERT_TRUE(generatePatches(lib, p, PatternSet{}, patches));
        }
    }
    buildConnections(lib, patches);
}

// Many football runs at once: every carrier gets past its tacklers to the
// goal line, the runs keep clear of each other, and composing them in
// parallel gives the same bytes as on one thread.
TEST(ComposeScale, FootballRunsSideBySide) {
    const auto& lib = footballWorld().library;
    PatchLibrary patches;
    ASSERT_NO_FATAL_FAILURE(footballRunPatches(lib, patches));
    FootballSpec football;
    football.runs = 24;
    football.tacklers = 4;
    football.goal = 40;
    football.spread = 20 * std::numbers::pi / 180;
    football.directions = {{0.0, 0.0}, {5.0, 0.4}, {10.0, -0.3}};
    ComposeSpec spec = ComposeSpec::of(football);
    spec.duration = 60;
    ComposeStats st;
    auto scene = compose(lib, patches, spec, &st);
    ASSERT_TRUE(scene) << scene.error().message;
    const auto* fs = st.part<FootballStats>();
    ASSERT_NE(fs, nullptr);
    EXPECT_GE(fs->goalReached, 0.0) << "some carrier never reached the goal line";
    EXPECT_GE(fs->tacklersPassed, 3 * football.runs);
    int carriers = 0;
    for (const auto& c : scene->characters) carriers += c.name.ends_with("/carrier") ? 1 : 0;
    EXPECT_EQ(carriers, football.runs);
    for (const auto& h : scene->hits) EXPECT_FALSE(scene->characters[static_cast<std::size_t>(h.defender)].name.ends_with("/carrier"));
    // The runs differ (each carrier its own arrows), and none passes through
    // another's: the first runs measured together.
    std::set<std::vector<std::pair<int, long>>> distinct;  // carriers' runs: (action, start in ms) each
    for (const auto& c : scene->characters) {
        if (!c.name.ends_with("/carrier")) continue;
        std::vector<std::pair<int, long>> run;
        for (const auto& i : c.track) run.emplace_back(i.action, std::lround(i.start * 1000));
        distinct.insert(run);
    }
    EXPECT_GE(distinct.size(), static_cast<std::size_t>(football.runs / 2));
    const Scene firstRuns = test::cropSceneTo(*scene, [](int, const SceneCharacter& c) {
        return c.name.starts_with("run-1/") || c.name.starts_with("run-2/") || c.name.starts_with("run-3/") ||
               c.name.starts_with("run-6/") || c.name.starts_with("run-7/");
    });
    EXPECT_EQ(computeMetrics(firstRuns, lib).penetrationFrames, 0);
    std::string oneThread;
    tbb::task_arena arena(1);
    arena.execute([&] {
        auto again = compose(lib, patches, spec);
        ASSERT_TRUE(again);
        oneThread = sceneToJson(*again, lib);
    });
    EXPECT_EQ(oneThread, sceneToJson(*scene, lib));
    // Each run's ball is held by its own carrier where that carrier runs; the
    // file stores the holds (version 3), and reading it makes the very keys
    // the composer made.
    int balls = 0;
    const ScenePoser poser(*scene, lib);
    for (const auto& c : scene->characters) {
        if (c.body != "ball") continue;
        ++balls;
        ASSERT_TRUE(c.held());
        const auto& carrier = scene->characters[static_cast<std::size_t>(c.holder)];
        EXPECT_EQ(carrier.name, c.name.substr(0, c.name.find('/')) + "/carrier");
        EXPECT_EQ(c.keys.size(), static_cast<std::size_t>(heldKeyCount(c.heldFrom, c.heldTo)));
        // At the carrier's right hand (its run moved into its row), up to the keys' interpolation.
        std::vector<glm::vec3> world;
        poser.worldPositions(c.holder, 2.01, world);
        const int hand = lib.motion(lib.actions()[static_cast<std::size_t>(carrier.track.front().action)].motion).joints.rightHand;
        EXPECT_LT(glm::distance(ballGripAt(c, 2.01), world[static_cast<std::size_t>(hand)]), 0.05f) << c.name;
    }
    EXPECT_EQ(balls, football.runs);
    const std::string text = sceneToJson(*scene, lib);
    EXPECT_NE(text.find("\"version\": 3"), std::string::npos);
    auto back = sceneFromJson(text, "crowd.frayscene", lib);
    ASSERT_TRUE(back) << back.error().message;
    ASSERT_EQ(back->characters.size(), scene->characters.size());
    for (std::size_t i = 0; i < scene->characters.size(); ++i) EXPECT_EQ(back->characters[i].keys, scene->characters[i].keys) << i;
}

// The runs of the football crowd's spec (resources/demo/football_crowd.json:
// six tacklers, doubles, arrows spread 20 degrees) have no penetration at
// the scene's samples: a tackle that misses was body-tested only at its own
// actions' samples, which fall between the scene's when a run step starts on
// a half sample, and a few avoid patches graze the carrier there (before the
// fix, 1-3 samples in every 29 runs of the 10,000-character crowd).
TEST(ComposeScale, FootballCrowdRunsMissTheCarrierCleanly) {
    const auto& lib = footballWorld().library;
    PatchLibrary patches;
    ASSERT_NO_FATAL_FAILURE(footballRunPatches(lib, patches));
    FootballSpec football;
    football.runs = 60;
    football.tacklers = 6;
    football.goal = 45;
    football.doubles = true;
    football.spread = 20 * std::numbers::pi / 180;
    football.directions = {{0.0, 0.0}, {5.0, 25 * std::numbers::pi / 180}, {10.0, -20 * std::numbers::pi / 180}};
    ComposeSpec spec = ComposeSpec::of(football);
    spec.duration = 60;
    auto scene = compose(lib, patches, spec);
    ASSERT_TRUE(scene) << scene.error().message;
    // The metrics compare every pair: ten runs at a time (the runs stand apart).
    for (int first = 1; first <= football.runs; first += 10) {
        const Scene part = test::cropSceneTo(*scene, [&](int, const SceneCharacter& c) {
            const int run = std::stoi(c.name.substr(4, c.name.find('/') - 4));
            return run >= first && run < first + 10;
        });
        const auto m = computeMetrics(part, lib);
        EXPECT_EQ(m.penetrationFrames, 0) << "runs " << first << "-" << first + 9
                                          << (m.penetrations.empty() ? std::string()
                                                                     : ": " + part.characters[static_cast<std::size_t>(m.penetrations[0].a)].name +
                                                                           " at " + std::to_string(m.penetrations[0].time) + " s");
    }
}

}  // namespace
}  // namespace fray::sim

namespace fray::sim {
namespace {

// A looped idle (ActionInstance::loop) poses, contacts and measures as the
// repetitions it stands for did when each was an instance of its own, and
// the rat's bystanders are one looped instance each (issue 27: a bystander
// of a 1,000 s scene was a thousand instances).
TEST(LoopedIdle, RatBystandersLoopAndPoseAsRepeatedInstances) {
    const auto& lib = demoWorld().library;
    ComposeSpec spec = ComposeSpec::of(RatSpec{});
    auto& own = *spec.part<RatSpec>();
    own.ratPath = {{-6, 0}, {6, 0.5f}, {6, 3}, {-6, 3}};  // 27 s of rat: a bystander stands through many times round
    own.crowd = 40;
    own.spacing = 0.8;
    own.reach = 0.6;
    spec.seed = 3;
    const PatchLibrary none;
    auto scene = compose(lib, none, spec);
    ASSERT_TRUE(scene) << scene.error().message;
    int looped = 0, standers = 0;
    for (std::size_t c = 1; c < scene->characters.size(); ++c) {
        const auto& track = scene->characters[c].track;
        ASSERT_FALSE(track.empty());
        EXPECT_LE(track.size(), 4u) << "person " << c << ": standing takes one instance, not one a time round";
        if (track.size() == 1) ++standers;
        for (const auto& inst : track) looped += inst.looped() ? 1 : 0;
    }
    EXPECT_GE(standers, 10);
    ASSERT_GE(looped, standers);

    // The same scene with every looped instance written out as its
    // repetitions (the format before loops).
    Scene expanded = *scene;
    for (auto& ch : expanded.characters) {
        std::vector<ActionInstance> out;
        for (const auto& inst : ch.track) {
            for (int k = 0; k < inst.repeats(); ++k) {
                ActionInstance once = inst;
                once.loop = 0;
                once.start = inst.repeatStart(k);
                if (inst.looped()) once.end = std::min(inst.end, inst.repeatStart(k + 1));
                out.push_back(once);
            }
        }
        ch.track = std::move(out);
    }
    const ScenePoser a(*scene, lib), b(expanded, lib);
    Pose pa, pb;
    int seams = 0;
    for (std::size_t c = 1; c < scene->characters.size(); c += 3) {
        const auto& inst = scene->characters[c].track.front();
        if (inst.looped()) seams += inst.repeats() - 1;
        for (int f = 0; f <= static_cast<int>(scene->duration * 30) + 2; ++f) {
            const double t = f / 30.0;
            a.pose(static_cast<int>(c), t, pa);
            b.pose(static_cast<int>(c), t, pb);
            ASSERT_EQ(pa.translations, pb.translations) << "person " << c << " at " << t << " s";
            ASSERT_EQ(pa.rotations, pb.rotations) << "person " << c << " at " << t << " s";
            ASSERT_EQ(a.contacts(static_cast<int>(c), t), b.contacts(static_cast<int>(c), t));
        }
        // Just before, at and just after each seam (the 0.15 s blend).
        if (inst.looped()) {
            for (int k = 1; k < inst.repeats(); ++k) {
                for (double dt : {-1e-9, 0.0, 1e-9, 0.05}) {
                    const double t = inst.repeatStart(k) + dt;
                    a.pose(static_cast<int>(c), t, pa);
                    b.pose(static_cast<int>(c), t, pb);
                    ASSERT_EQ(pa.translations, pb.translations) << "person " << c << " at seam " << k;
                    ASSERT_EQ(pa.rotations, pb.rotations) << "person " << c << " at seam " << k;
                }
            }
        }
    }
    EXPECT_GE(seams, 40);  // over the third of the crowd posed here
    // The metrics, the kinematic one over every seam included, are the same.
    EXPECT_EQ(metricsToJson(computeMetrics(*scene, lib)), metricsToJson(computeMetrics(expanded, lib)));
    const JointTracks ka = kinematicTracks(*scene, lib, 30), kb = kinematicTracks(expanded, lib, 30);
    ASSERT_EQ(ka.joints, kb.joints);
    const PostureMetrics qa = computePostureMetrics(*scene, lib, ka, ka), qb = computePostureMetrics(expanded, lib, kb, kb);
    EXPECT_EQ(postureMetricsToJson(qa), postureMetricsToJson(qb));
    int boundaries = 0;
    for (const auto& c : qa.characters) boundaries += c.boundaries;
    EXPECT_GE(boundaries, seams);

    // Saved as version 2 with the loops, read back the same; the expanded
    // scene (no loops) is still written as version 1.
    const std::string text = sceneToJson(*scene, lib);
    EXPECT_NE(text.find("\"version\": 2"), std::string::npos);
    EXPECT_NE(text.find("\"loop\": "), std::string::npos);
    EXPECT_NE(sceneToJson(expanded, lib).find("\"version\": 1"), std::string::npos);
    auto back = sceneFromJson(text, "l.frayscene", lib);
    ASSERT_TRUE(back) << back.error().message;
    EXPECT_EQ(sceneToJson(*back, lib), text);
    // A loop in a version-1 file, or one longer than the clip, is refused by name.
    std::string v1 = text;
    v1.replace(v1.find("\"version\": 2"), 12, "\"version\": 1");
    auto bad = sceneFromJson(v1, "l.frayscene", lib);
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().message.find("l.frayscene: /characters/"), std::string::npos) << bad.error().message;
    EXPECT_NE(bad.error().message.find("/loop: looped instances need scene version 2"), std::string::npos) << bad.error().message;
    std::string longLoop = text;
    const auto at = longLoop.find("\"loop\": ");
    longLoop.replace(at, longLoop.find_first_of(",\n}", at) - at, "\"loop\": 500");
    bad = sceneFromJson(longLoop, "l.frayscene", lib);
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().message.find("/loop: must be between"), std::string::npos) << bad.error().message;
    std::string v4 = text;
    v4.replace(v4.find("\"version\": 2"), 12, "\"version\": 4");
    bad = sceneFromJson(v4, "l.frayscene", lib);
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().message.find("/version: version 4 is not supported (this build reads 1 to 3)"), std::string::npos) << bad.error().message;
    // A version-3 file (held bodies) reads loops too.
    std::string v3 = text;
    v3.replace(v3.find("\"version\": 2"), 12, "\"version\": 3");
    auto three = sceneFromJson(v3, "l.frayscene", lib);
    ASSERT_TRUE(three) << three.error().message;
    EXPECT_EQ(sceneToJson(*three, lib), text);
}

}  // namespace
}  // namespace fray::sim

namespace fray::sim {
namespace {

// The rat's people decide one after another, each trying its ways out in
// parallel batches (issue 27): the scene is the same bytes whatever the
// number of threads, bumps and pushes included; and the scene file, its
// characters written in parallel and spliced in, is exactly what one dump of
// the whole document prints.
TEST(ComposeScale, RatSameBytesWhateverTheThreadCount) {
    const auto& lib = test::demoWorld().library;
    ComposeSpec spec = ComposeSpec::of(RatSpec{});
    auto& own = *spec.part<RatSpec>();
    own.ratPath = {{-8, 0}, {8, 0}, {8, 2.5f}, {-8, 2.5f}};  // two rows, as the 10,000-person benchmark's
    own.crowd = 160;
    own.spacing = 0.8;
    own.bumps = 1.0;  // seek bumps: pushes, and pushes of the pushed
    spec.seed = 5;
    const PatchLibrary none;
    ComposeStats st;
    auto scene = compose(lib, none, spec, &st);
    ASSERT_TRUE(scene) << scene.error().message;
    const auto* rs = st.part<RatStats>();
    ASSERT_NE(rs, nullptr);
    EXPECT_GE(rs->ratAvoided, 20);
    EXPECT_GE(rs->bumps, 3) << "the test needs bumps to cover the pushes' tests";
    const std::string text = sceneToJson(*scene, lib);
    for (int threads : {1, 3}) {
        std::string again;
        tbb::task_arena arena(threads);
        arena.execute([&] {
            auto s = compose(lib, none, spec);
            ASSERT_TRUE(s);
            again = sceneToJson(*s, lib);
        });
        EXPECT_TRUE(again == text) << threads << " threads: the scene differs";
    }
    EXPECT_EQ(nlohmann::ordered_json::parse(text).dump(1) + "\n", text);
}

}  // namespace
}  // namespace fray::sim
