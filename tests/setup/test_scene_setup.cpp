// core/setup: setups stored in the project, their conversions and edits.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>

#include <nlohmann/json.hpp>

#include "fray/prep/project.h"
#include "fray/setup/affected.h"
#include "fray/setup/convert.h"
#include "fray/setup/hand_made.h"
#include "fray/setup/paint.h"
#include "fray/setup/scene_setup.h"
#include "patch_library_builder.h"  // core/sim/src: to fill a library by hand

using namespace fray;
using namespace fray::setup;
namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

namespace {

std::string readFile(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

const fs::path kSpecs = FRAY_DEMO_SPECS;

// A stand-in for the CLI's PNG reader: a checkerboard of the asked scale.
Result<sim::FloorBitmap> fakeFloor(const fs::path& file, double mpp, glm::vec2 origin) {
    if (!fs::exists(file)) return makeError(file.string() + ": no such file");
    sim::FloorBitmap f;
    f.width = 30, f.height = 20, f.metresPerPixel = mpp, f.origin = origin;
    for (int i = 0; i < f.width * f.height; ++i) f.painted.push_back(static_cast<std::uint8_t>((i / 3) % 2));
    return f;
}

}  // namespace

TEST(SceneSetup, EveryKindRoundTripsThroughTheProjectFile) {
    prep::Project p = prep::makeProject("t");
    std::vector<SceneSetup> setups;
    for (SetupKind k : allSetupKinds()) setups.push_back(makeSetup(std::string("s-") + setupKindName(k), k));
    Trajectory t;
    t.character = "red";
    t.shape = TrajectoryShape::Circle;
    t.points = {{0, 0}, {2, 0}};
    t.loop = true;
    t.checkpoints = {{{0, 2}, 3.0, "@punch"}, {{-2, 0}, std::nullopt, ""}};
    setups[0].trajectories.push_back(t);
    setups[0].pins.push_back({"red", 2.5, "jab_1"});
    setups[2].patches.rejected = {1, 4};
    setups[2].patches.kept = {2};
    setProjectSetups(p, setups);
    const std::string bytes = prep::projectToJson(p);
    auto back = prep::projectFromJson(bytes, "t.frayproj");
    ASSERT_TRUE(back.ok()) << back.error().message;
    auto read = projectSetups(*back, "t.frayproj");
    ASSERT_TRUE(read.ok()) << read.error().message;
    EXPECT_EQ(*read, setups);
    EXPECT_EQ(prep::projectToJson(*back), bytes);
    // No setups: no section.
    setProjectSetups(p, {});
    EXPECT_EQ(p.laterSections.count(kSetupSection), 0u);
}

TEST(SceneSetup, DamagedSectionsNameTheFileAndPath) {
    auto load = [](const std::string& section) {
        prep::Project p = prep::makeProject("t");
        p.laterSections[kSetupSection] = section;
        auto r = projectSetups(p, "bad.frayproj");
        return r ? std::string("ok") : r.error().message;
    };
    const std::string good = setupsToJson({makeSetup("a", SetupKind::Domino)});
    EXPECT_EQ(load(good), "ok");
    auto edit = [&](const std::function<void(json&)>& f) {
        json j = json::parse(good);
        f(j);
        return j.dump();
    };
    EXPECT_NE(load(edit([](json& j) { j["setups"][0]["floor"]["width"] = 0; })).find("bad.frayproj: /scene/setups/0/floor/width: must be 1 to"), std::string::npos);
    EXPECT_NE(load(edit([](json& j) { j["setups"][0]["floor"]["data"] = "AAAA"; })).find("/scene/setups/0/floor/data: damaged"), std::string::npos);
    EXPECT_NE(load(edit([](json& j) { j["setups"][0]["kind"] = "brawl"; })).find("/scene/setups/0/kind: unknown setup kind 'brawl'"), std::string::npos);
    EXPECT_NE(load(edit([](json& j) { j["setups"].push_back(j["setups"][0]); })).find("/scene/setups/1/name: 'a' is used by another setup"), std::string::npos);
    EXPECT_NE(load(edit([](json& j) { j["setups"][0]["spec"] = 3; })).find("/scene/setups/0/spec: must be an object"), std::string::npos);
    EXPECT_NE(load(edit([](json& j) { j["setups"][0]["patches"]["rejected"] = {3, 2}; })).find("ascending"), std::string::npos);
}

TEST(SceneSetup, FloorEncodingIsLossless) {
    std::mt19937 rng(7);
    for (int trial = 0; trial < 5; ++trial) {
        FloorPaint f;
        f.width = 1 + static_cast<int>(rng() % 300), f.height = 1 + static_cast<int>(rng() % 200);
        for (int i = 0; i < f.width * f.height; ++i) f.painted.push_back(static_cast<std::uint8_t>(rng() % 2));
        auto back = decodeFloor(encodeFloor(f), f.width, f.height, "floor");
        ASSERT_TRUE(back.ok()) << back.error().message;
        EXPECT_EQ(back->painted, f.painted);
    }
    EXPECT_FALSE(decodeFloor("not base64!", 2, 2, "f").ok());
}

TEST(SceneSetup, TrajectoryShapes) {
    Trajectory circle{"a", TrajectoryShape::Circle, {{1, 1}, {3, 1}}, false, false, {}};
    auto line = sampleTrajectory(circle, 0.25);
    ASSERT_TRUE(line.ok());
    for (const auto& p : *line) EXPECT_NEAR(std::hypot(p.x - 1, p.z - 1), 2.0, 1e-9);
    EXPECT_EQ(line->front(), (Point{3, 1}));
    EXPECT_EQ(line->back(), (Point{3, 1}));  // once round, back to the start
    // Counter-clockwise seen from above: from +x towards +z first.
    EXPECT_GT((*line)[1].z, 1.0);
    Trajectory arc{"a", TrajectoryShape::Arc, {{-1, 0}, {0, 1}, {1, 0}}, false, false, {}};
    auto arcLine = sampleTrajectory(arc, 0.1);
    ASSERT_TRUE(arcLine.ok());
    for (const auto& p : *arcLine) EXPECT_GE(p.z, -1e-9);  // through (0, 1), not the other way round
    arc.points[1] = {0, 0};
    auto flat = sampleTrajectory(arc);
    ASSERT_FALSE(flat.ok());
    EXPECT_NE(flat.error().message.find("on a line"), std::string::npos);
    Trajectory empty{"a", TrajectoryShape::Polyline, {}, false, false, {}};
    auto none = sampleTrajectory(empty);
    ASSERT_FALSE(none.ok());
    EXPECT_NE(none.error().message.find("is empty"), std::string::npos);
}

TEST(SceneSetup, StrokesChangeExactlyTheReportedPixels) {
    SceneSetup s = makeSetup("d", SetupKind::Domino);
    FloorPaint f = *s.floor;
    const FloorPaint blank = f;
    FloorStroke brush;
    brush.points = {{-2, 0}, {2, 0}};
    brush.radius = 0.5;
    auto changes = applyStroke(f, brush);
    ASSERT_TRUE(changes.ok());
    EXPECT_GT(changes->size(), 100u);
    std::size_t painted = 0;
    for (auto b : f.painted) painted += b;
    EXPECT_EQ(painted, changes->size());
    EXPECT_TRUE(toFloorBitmap(f).paintedAt({0.0f, 0.0f}));
    EXPECT_FALSE(toFloorBitmap(f).paintedAt({0.0f, 1.0f}));
    // Undo by the changes' old values: bit for bit the blank floor.
    FloorPaint undone = f;
    for (const auto& c : *changes) undone.painted[static_cast<std::size_t>(c.index)] = c.before;
    EXPECT_EQ(undone, blank);
    // Fill the region around the stroke: everything but the stroke.
    FloorStroke fill;
    fill.tool = FloorStroke::Tool::Fill;
    fill.points = {{-9, -5}};
    auto filled = applyStroke(f, fill);
    ASSERT_TRUE(filled.ok());
    EXPECT_EQ(filled->size() + changes->size(), f.painted.size());
    // Text: letters in the stamp's alphabet only.
    FloorPaint t = blank;
    FloorStroke text;
    text.tool = FloorStroke::Tool::Text;
    text.text = "Hi 2";
    text.points = {{-8, -4}};
    text.letterHeight = 1.4;
    text.startTime = 1.0;
    auto stamped = applyStroke(t, text);
    ASSERT_TRUE(stamped.ok());
    EXPECT_GT(stamped->size(), 50u);
    const auto starts = strokeStarts(t, text);
    ASSERT_EQ(starts.size(), 3u);  // H, I, 2 (not the space)
    EXPECT_DOUBLE_EQ(starts[2].time, 3.0);
    for (const auto& st : starts) EXPECT_TRUE(toFloorBitmap(t).paintedAt({static_cast<float>(st.pos.x), static_cast<float>(st.pos.z)}));
    text.text = "a&b";
    FloorPaint u = blank;
    EXPECT_FALSE(applyStroke(u, text).ok());
    EXPECT_EQ(u, blank);
}

TEST(SceneSetup, ImportedSpecsConvertBackToTheSameJson) {
    for (const char* name : {"duel.json", "chase.json", "domino.json", "football.json", "one_vs_many.json", "rat.json"}) {
        SCOPED_TRACE(name);
        const std::string text = readFile(kSpecs / name);
        auto s = importSpec("imported", text, kSpecs / name, fakeFloor);
        ASSERT_TRUE(s.ok()) << s.error().message;
        auto spec = setupSpecJson(*s);
        ASSERT_TRUE(spec.ok()) << spec.error().message;
        // Same keys, order, values and number spellings: what the scene records.
        EXPECT_EQ(json::parse(*spec).dump(), json::parse(text).dump());
        // And it survives the project file.
        prep::Project p = prep::makeProject("t");
        setProjectSetups(p, {*s});
        auto back = projectSetups(*prep::projectFromJson(prep::projectToJson(p), "t"), "t");
        ASSERT_TRUE(back.ok());
        EXPECT_EQ(back->front(), *s);
    }
    EXPECT_EQ(importSpec("d", readFile(kSpecs / "duel.json"), kSpecs / "duel.json", fakeFloor)->kind, SetupKind::Duel);
    EXPECT_EQ(importSpec("c", readFile(kSpecs / "chase.json"), kSpecs / "chase.json", fakeFloor)->kind, SetupKind::Chase);
    auto domino = importSpec("d", readFile(kSpecs / "domino.json"), kSpecs / "domino.json", fakeFloor);
    ASSERT_TRUE(domino->floor);
    EXPECT_EQ(domino->floor->width, 30);
    EXPECT_EQ(domino->floor->origin, (Point{-10, -6}));
    // Bad specs: the file and the path.
    auto bad = importSpec("x", "{\"kind\": \"brawl\"}", "x.json", fakeFloor);
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("x.json: /kind: unknown scene kind 'brawl'"), std::string::npos);
    auto missing = importSpec("x", "{\"kind\": \"domino\", \"floor\": {\"bitmap\": \"nope.png\"}}", "/tmp/x.json", fakeFloor);
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.error().message.find("nope.png"), std::string::npos);
}

TEST(SceneSetup, EditsKeepTheirNumbersAndRefuseBadValues) {
    SceneSetup s = *importSpec("d", readFile(kSpecs / "duel.json"), kSpecs / "duel.json", fakeFloor);
    const std::string before = s.spec;
    ASSERT_TRUE(setCharacterStart(s, "blue", {1.1, 0, -90}).ok());
    EXPECT_EQ(s.spec, before);  // nothing moved: nothing rewritten
    ASSERT_TRUE(setCharacterStart(s, "blue", {1.5, 0.25, -90}).ok());
    EXPECT_EQ(characters(s)[1].start, (Placement{1.5, 0.25, -90}));
    EXPECT_FALSE(setCharacterStart(s, "green", {}).ok());
    ASSERT_TRUE(moveTeam(s, 0, 1, 1).ok());
    EXPECT_EQ(characters(s)[0].start, (Placement{1, 1, 90}));
    ASSERT_TRUE(setParameter(s, "/characters/0/depth", "3").ok());
    EXPECT_EQ(characters(s)[0].depth, 3);
    EXPECT_EQ(*parameter(s, "/duration"), "20");
    EXPECT_FALSE(setParameter(s, "/kind", "\"rat\"").ok());
    EXPECT_FALSE(setParameter(s, "duration", "3").ok());
    EXPECT_FALSE(setParameter(s, "/duration", "{").ok());
    ASSERT_TRUE(setParameter(s, "/seed", "null").ok());
    EXPECT_FALSE(parameter(s, "/seed"));
    SceneSetup r = makeSetup("r", SetupKind::Rat);
    EXPECT_FALSE(setRatPath(r, {{0, 0}}).ok());
    ASSERT_TRUE(setRatPath(r, {{0, 0}, {3, 1}, {5, 5}}).ok());
    EXPECT_EQ(ratPath(r).size(), 3u);
    SceneSetup o = makeSetup("o", SetupKind::OneVsMany);
    EXPECT_FALSE(setTimedCommands(o, {{0, "dance"}}).ok());
    EXPECT_FALSE(setTimedCommands(o, {{5, "punch"}, {1, "kick"}}).ok());
    EXPECT_FALSE(setTimedCommands(o, {{0, "move"}}).ok()) << "a move needs the place to move to";
    ASSERT_TRUE(setTimedCommands(o, {{0, "move", Point{3, -1.5}}, {5, "avoid", Point{1, 1}}, {6, "kick"}}).ok());
    EXPECT_EQ(timedCommands(o)[1].action, "avoid");
    EXPECT_EQ(timedCommands(o)[0].at, (Point{3, -1.5}));
    EXPECT_EQ(timedCommands(o)[2].at, std::nullopt);
    SceneSetup v = makeSetup("v", SetupKind::OneVsOne);
    EXPECT_FALSE(setTimedCommands(v, {{0, "move", Point{1, 1}}}).ok()) << "move commands are one-vs-many's";
    SceneSetup f = makeSetup("f", SetupKind::Football);
    EXPECT_FALSE(setRunDirections(f, {{0, 85}}).ok()) << "the compose parser allows 80 degrees at most";
    ASSERT_TRUE(setRunDirections(f, {{0, 10, Point{0, -3}}, {4, -30}}).ok());
    EXPECT_EQ(runDirections(f)[0].at, (Point{0, -3}));
    EXPECT_EQ(runDirections(f)[1].at, std::nullopt);
}

TEST(SceneSetup, TrajectoriesBecomeCheckpointPaths) {
    SceneSetup s = makeSetup("d", SetupKind::Duel);
    Trajectory t{"red", TrajectoryShape::Circle, {{0, 0}, {2, 0}}, false, true, {{{0, 2}, 3.0, "@punch"}, {{0, -2}, 9.0, ""}}};
    s.trajectories.push_back(t);
    auto text = setupSpecJson(s);
    ASSERT_TRUE(text.ok()) << text.error().message;
    const json j = json::parse(*text);
    const json& path = j["characters"][0]["path"];
    ASSERT_GT(path.size(), 8u);
    // A looped circle with timed checkpoints is followed once round by their
    // schedule, back to where it starts (a time is passed once) ...
    EXPECT_FALSE(j["characters"][0].contains("loop_path"));
    EXPECT_EQ(path.back()["x"], 2.0);
    EXPECT_EQ(path.back()["z"], 0.0);
    {
        // ... and without times it keeps looping.
        SceneSetup untimed = s;
        for (auto& c : untimed.trajectories[0].checkpoints) c.time.reset();
        const json u = json::parse(*setupSpecJson(untimed));
        EXPECT_TRUE(u["characters"][0]["loop_path"].get<bool>());
        EXPECT_NE(u["characters"][0]["path"].back(), path.back());
    }
    // The checkpoints are in the path, in order, with their time and action.
    int first = -1, second = -1;
    for (std::size_t i = 0; i < path.size(); ++i) {
        if (path[i].contains("time") && path[i]["time"] == 3.0) first = static_cast<int>(i);
        if (path[i].contains("time") && path[i]["time"] == 9.0) second = static_cast<int>(i);
    }
    ASSERT_GE(first, 0);
    EXPECT_GT(second, first);
    EXPECT_EQ(path[static_cast<std::size_t>(first)]["action"], "@punch");
    // A drawn trajectory is followed: w_path unless the weights give one.
    EXPECT_EQ(j["characters"][0]["weights"]["w_path"], kDrawnPathWeight);
    EXPECT_FALSE(j["characters"][1].contains("weights"));
    s.spec = json::parse(s.spec).dump();
    json withWeight = json::parse(s.spec);
    withWeight["characters"][0]["weights"] = json{{"w_path", 7}};
    s.spec = withWeight.dump();
    EXPECT_EQ(json::parse(*setupSpecJson(s))["characters"][0]["weights"]["w_path"], 7);
    // A trajectory for someone who is not there is an error naming them.
    s.trajectories[0].character = "green";
    auto bad = setupSpecJson(s);
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("'green'"), std::string::npos);
}

TEST(SceneSetup, RejectedPatchesLeaveTheLibrary) {
    // A hand-filled library (white box: core/sim's builder header).
    sim::PatchLibrary lib;
    sim::PatchLibrary::Data& d = sim::detail::built(lib);
    for (int i = 0; i < 4; ++i) {
        sim::Patch p;
        p.score = i;
        d.patches.push_back(p);
        d.temporal.push_back({});
        d.spatial.push_back({});
        d.initialPose.push_back(i);
        d.finalPose.push_back(i);
    }
    d.standardPoses.resize(4);
    ASSERT_TRUE(lib.complete());
    d.temporal[0] = {{1, 0, -1}, {2, 0, -1}, {3, 1, 0}};
    d.spatial[3] = {{0, 0, 1, 0.5f, 0.0f}, {2, 1, 0, 0.25f, 0.0f}};
    auto out = withoutRejected(lib, {2});
    ASSERT_TRUE(out.ok());
    ASSERT_EQ(out->patches().size(), 3u);
    ASSERT_TRUE(out->complete());
    EXPECT_EQ(out->patches()[2].score, 3);
    ASSERT_EQ(out->temporal()[0].size(), 2u);
    EXPECT_EQ(out->temporal()[0][0].to, 1);
    EXPECT_EQ(out->temporal()[0][1].to, 2);  // was 3
    ASSERT_EQ(out->spatial()[2].size(), 1u);
    EXPECT_EQ(out->spatial()[2][0].to, 0);
    EXPECT_EQ(out->finalPose(), (std::vector<int>{0, 1, 3}));
    EXPECT_FALSE(withoutRejected(lib, {4}).ok());
}

TEST(SceneSetup, AffectedCharactersFollowTheEditAndTheirInteractions) {
    // Four rats standing still, far apart; rat 1 and 2 interact (a hit) at 5 s.
    sim::Scene scene;
    scene.duration = 10;
    scene.spec = R"({"kind": "domino"})";
    const float xs[] = {0, 10, 20, 40};
    for (int i = 0; i < 4; ++i) {
        sim::SceneCharacter c;
        c.name = "c" + std::to_string(i);
        c.body = "rat";
        c.keys = {{0, {{xs[i], 0.0f}, 0}, -1}, {10, {{xs[i], 0.0f}, 0}, -1}};
        scene.characters.push_back(c);
    }
    sim::HitEvent h;
    h.time = 5, h.attacker = 1, h.defender = 2;
    scene.hits.push_back(h);
    sim::ActionLibrary lib;
    SetupEdit e;
    e.kind = SetupEdit::Kind::Stroke;
    e.lo = {-1, -1}, e.hi = {1, 1}, e.time = 0;
    EXPECT_EQ(affectedCharacters(scene, lib, e), (std::vector<int>{0}));
    e.lo = {9, -1}, e.hi = {9.5, 1};
    EXPECT_EQ(affectedCharacters(scene, lib, e), (std::vector<int>{1, 2}));  // 2 interacts with 1 after the edit
    e.time = 6;  // the hit is over by then
    EXPECT_EQ(affectedCharacters(scene, lib, e), (std::vector<int>{1}));
    e.lo = {30, -1}, e.hi = {31, 1};
    EXPECT_TRUE(affectedCharacters(scene, lib, e).empty());
    SetupEdit start;
    start.kind = SetupEdit::Kind::Start;
    start.character = "c3";
    EXPECT_EQ(affectedCharacters(scene, lib, start), (std::vector<int>{3}));
    scene.characters[0].side = 1, scene.characters[3].side = 1;
    start.side = 1;  // the team of c0 and c3 moved
    EXPECT_EQ(affectedCharacters(scene, lib, start), (std::vector<int>{0, 3}));
    SetupEdit other;
    EXPECT_EQ(affectedCharacters(scene, lib, other).size(), 4u);
}

TEST(SceneSetup, HandMadePatchRecipesRoundTripAndErrors) {
    prep::Project p;
    std::vector<HandMadePatch> recipes(1);
    recipes[0].pattern = "attack-fall";
    recipes[0].initial = {0.9, 0.5, -2.75, 0.25};
    recipes[0].actions = {std::vector<std::string>{"jab"}, std::vector<std::string>{}};
    setProjectHandMadePatches(p, recipes);
    auto back = projectHandMadePatches(p, "p.frayproj");
    ASSERT_TRUE(back) << back.error().message;
    ASSERT_EQ(back->size(), 1u);
    EXPECT_EQ((*back)[0].pattern, "attack-fall");
    EXPECT_EQ((*back)[0].actions, recipes[0].actions);
    EXPECT_NEAR((*back)[0].initial.theta2, -2.75, 1e-4);
    EXPECT_NEAR((*back)[0].initial.r, 0.9, 1e-9);
    setProjectHandMadePatches(p, {});
    EXPECT_EQ(p.laterSections.count(kHandMadeSection), 0u);
    p.laterSections[kHandMadeSection] = R"({"version": 1, "patches": [{"pattern": "x", "r": 99, "theta1_deg": 0, "theta2_deg": 0, "actions": [["a"], []]}]})";
    auto bad = projectHandMadePatches(p, "p.frayproj");
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().message.find("/hand_made_patches/patches/0/r"), std::string::npos) << bad.error().message;
    p.laterSections[kHandMadeSection] = R"({"version": 1, "patches": [{"pattern": "x", "r": 1, "theta1_deg": 0, "theta2_deg": 0, "actions": [[], []]}]})";
    bad = projectHandMadePatches(p, "p.frayproj");
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().message.find("character 1 needs"), std::string::npos) << bad.error().message;
}
