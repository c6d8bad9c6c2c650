// core/setup: the Interaction Graph kinds as setups (graph-duel, graph-teams,
// graph-carry): defaults, checked parameters naming the field, the section
// version, the carry path as a trajectory of the box.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "fray/prep/project.h"
#include "fray/setup/convert.h"
#include "fray/setup/graph_setup.h"
#include "fray/setup/scene_setup.h"

using namespace fray;
using namespace fray::setup;
using json = nlohmann::ordered_json;

namespace {

std::string problem(SetupKind kind, const std::string& spec, bool withPath = true) {
    SceneSetup s = makeSetup("g", kind);
    s.spec = spec;
    if (!withPath) s.trajectories.clear();
    auto p = graphParams(s);
    return p ? std::string("ok") : p.error().message;
}

}  // namespace

TEST(GraphSetup, NewSetupsHaveIgraphPlaysDefaults) {
    auto duel = graphParams(makeSetup("d", SetupKind::GraphDuel));
    ASSERT_TRUE(duel) << duel.error().message;
    EXPECT_EQ(duel->duration, 20);
    EXPECT_EQ(duel->seed, 1u);
    EXPECT_EQ(duel->style, "general");
    EXPECT_EQ(duel->depth, 3);
    EXPECT_EQ(duel->you, "graph");
    EXPECT_EQ(duel->opponent, "graph");
    EXPECT_DOUBLE_EQ(duel->distance, 1.3);
    EXPECT_DOUBLE_EQ(duel->jitter, 0.3);
    EXPECT_EQ(duel->graphStates, 80000);
    auto teams = graphParams(makeSetup("t", SetupKind::GraphTeams));
    ASSERT_TRUE(teams) << teams.error().message;
    EXPECT_EQ(teams->red, 10);
    EXPECT_EQ(teams->blue, 10);
    EXPECT_DOUBLE_EQ(teams->jitter, 0.2);
    const SceneSetup carry = makeSetup("c", SetupKind::GraphCarry);
    auto c = graphParams(carry);
    ASSERT_TRUE(c) << c.error().message;
    EXPECT_EQ(c->duration, 60);
    EXPECT_EQ(c->carryStates, 20000);
    ASSERT_NE(carryTrajectory(carry), nullptr);
    // The box is the one character the trajectory tools draw for; the circle of 3 m reads as igraph play's circle:3.
    ASSERT_EQ(characters(carry).size(), 1u);
    EXPECT_EQ(characters(carry)[0].name, "box");
    EXPECT_TRUE(characters(makeSetup("d", SetupKind::GraphDuel)).empty());
    auto text = setupSpecJson(carry);
    ASSERT_TRUE(text) << text.error().message;
    EXPECT_EQ(json::parse(*text)["path"], "circle:3");
    EXPECT_TRUE(isSimulateKind(SetupKind::GraphCarry));
    EXPECT_FALSE(isTreeExpansion(SetupKind::GraphDuel));
}

TEST(GraphSetup, BadParametersNameTheField) {
    EXPECT_EQ(problem(SetupKind::GraphDuel, R"({"depth": 0})"), "setup 'g': /depth: must be an integer from 1 to 64");
    EXPECT_EQ(problem(SetupKind::GraphDuel, R"({"depth": 2.5})"), "setup 'g': /depth: must be an integer from 1 to 64");
    EXPECT_EQ(problem(SetupKind::GraphDuel, R"({"style": "brawler"})"),
              "setup 'g': /style: 'brawler' is not one of general, infighter, outboxer");
    EXPECT_EQ(problem(SetupKind::GraphDuel, R"({"you": 1})"), "setup 'g': /you: must be one of graph, static");
    EXPECT_EQ(problem(SetupKind::GraphDuel, R"({"duration": 0})"), "setup 'g': /duration: must be in (0, 3600]");
    EXPECT_EQ(problem(SetupKind::GraphDuel, R"({"distance": 20})"), "setup 'g': /distance: must be in [0.5, 10]");
    EXPECT_EQ(problem(SetupKind::GraphDuel, R"({"refine": "yes"})"), "setup 'g': /refine: must be true or false");
    EXPECT_NE(problem(SetupKind::GraphDuel, R"({"red": 3})").find("/red: unknown parameter of a graph-duel setup"), std::string::npos);
    EXPECT_EQ(problem(SetupKind::GraphTeams, R"({"blue": 0})"), "setup 'g': /blue: must be an integer from 1 to 5000");
    EXPECT_EQ(problem(SetupKind::GraphTeams, R"({"graph_states": 5})"), "setup 'g': /graph_states: must be an integer from 16 to 10000000");
    EXPECT_EQ(problem(SetupKind::GraphTeams, R"({"version": 2})"), "setup 'g': /version: must be 1");
    EXPECT_EQ(problem(SetupKind::GraphCarry, R"({"weights": {"w_d": -1}})"), "setup 'g': /weights/w_d: must be a finite number >= 0");
    EXPECT_EQ(problem(SetupKind::GraphCarry, R"({"weights": {"gamma": 2}})"), "setup 'g': /weights/gamma: must be in [0, 1]");
    EXPECT_EQ(problem(SetupKind::GraphCarry, R"({"weights": {"w_q": 1}})"),
              "setup 'g': /weights/w_q: unknown reward weight (w_theta, w_d, w_v, speed, gamma)");
    EXPECT_NE(problem(SetupKind::GraphCarry, "{}", false).find("the box has no path"), std::string::npos);
    // A parameter edit before the path is drawn is fine.
    SceneSetup bare = makeSetup("g", SetupKind::GraphCarry);
    bare.trajectories.clear();
    EXPECT_TRUE(graphParams(bare, false));
    EXPECT_EQ(problem(SetupKind::GraphCarry, R"({"duration": 10})"), "ok");
}

TEST(GraphSetup, SectionVersionTwoOnlyWithAGraphKind) {
    EXPECT_EQ(json::parse(setupsToJson({makeSetup("a", SetupKind::Duel)}))["version"], 1);
    const std::string both = setupsToJson({makeSetup("a", SetupKind::Duel), makeSetup("b", SetupKind::GraphTeams)});
    EXPECT_EQ(json::parse(both)["version"], 2);
    prep::Project p = prep::makeProject("t");
    p.laterSections[kSetupSection] = both;
    auto read = projectSetups(p, "t.frayproj");
    ASSERT_TRUE(read) << read.error().message;
    ASSERT_EQ(read->size(), 2u);
    EXPECT_EQ((*read)[1].kind, SetupKind::GraphTeams);
    json future = json::parse(both);
    future["version"] = 3;
    p.laterSections[kSetupSection] = future.dump();
    auto refused = projectSetups(p, "t.frayproj");
    ASSERT_FALSE(refused);
    EXPECT_EQ(refused.error().message, "t.frayproj: /scene/version: version 3 is not supported (this build reads 1 and 2)");
}

TEST(GraphSetup, ImportedCarrySpecKeepsItsPath) {
    auto circle = importSpec("c", R"({"kind": "graph-carry", "duration": 12, "path": "circle:2.5"})", "c.json", {});
    ASSERT_TRUE(circle) << circle.error().message;
    EXPECT_EQ(circle->kind, SetupKind::GraphCarry);
    ASSERT_EQ(circle->trajectories.size(), 1u);
    EXPECT_EQ(circle->trajectories[0].shape, TrajectoryShape::Circle);
    EXPECT_EQ(json::parse(*setupSpecJson(*circle))["path"], "circle:2.5");
    EXPECT_EQ(json::parse(circle->spec).contains("path"), false);
    auto line = importSpec("l", R"({"kind": "graph-carry", "path": {"loop": false, "points": [[0, 0], [2, 0]]}})", "l.json", {});
    ASSERT_TRUE(line) << line.error().message;
    EXPECT_EQ(line->trajectories[0].shape, TrajectoryShape::Polyline);
    const json back = json::parse(*setupSpecJson(*line))["path"];
    EXPECT_EQ(back["loop"], false);
    EXPECT_EQ(back["points"].size(), 21u);  // sampled every 0.1 m
    auto bad = importSpec("b", R"({"kind": "graph-duel", "path": "circle:2"})", "b.json", {});
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.error().message, "b.json: /path: only a graph-carry setup has a path");
    auto typo = importSpec("b", R"({"kind": "graph-teams", "reds": 2})", "b.json", {});
    ASSERT_FALSE(typo);
    EXPECT_NE(typo.error().message.find("/reds: unknown parameter"), std::string::npos);
}
