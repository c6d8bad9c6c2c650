#pragma once
// The Interaction Graph's scene kinds as setups (issues 23 and 24): a duel
// and a team fight driven by the graph's min-max policies, and two carriers
// of a long box following a path. Their parameters are the flags of
// `fray-cli igraph play` as a JSON object (docs/AUTHORING.md "Interaction
// Graph setups"); the carry path is an ordinary setup trajectory of the
// pseudo-character "box" (the box's middle). This header reads and checks
// the parameters; running them (core/pipeline, fray/pipeline/graph_setup.h)
// needs fray_igraph. Plain C++20, no Qt.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "fray/core/result.h"
#include "fray/setup/scene_setup.h"

namespace fray::setup {

// The character whose trajectory a carry setup's box follows.
inline constexpr const char* kCarryPathCharacter = "box";

struct GraphSetupParams {
    SetupKind kind = SetupKind::GraphDuel;
    double duration = 20;        // s, (0, 3600]
    std::uint64_t seed = 1;      // placements (duel, teams); the carry graph's sampling and the run (carry)
    // graph-duel and graph-teams: character 0's side ("red", "you") and the other side.
    std::string style = "general", opponentStyle = "general";  // general | infighter | outboxer
    int depth = 3, opponentDepth = 3;                          // min-max depth, 1..64 (carry: its policies' depth)
    std::string you = "graph", opponent = "graph";             // duel: graph | static (a static target)
    int red = 1, blue = 1;                                     // teams: team sizes, 1..5000 each
    double distance = 1.3;                                     // duel: start distance (m), [0.5, 10]
    double jitter = 0.3;                                       // placement jitter, m and degrees/20, [0, 2]
    bool refine = false;                                       // MatchOptions::refine
    std::int64_t graphStates = 80000;                          // a graph built in memory (no valid graph file): archive limit
    // graph-carry.
    std::int64_t carryStates = 20000;                          // the carry graph's archive limit
    std::vector<std::pair<std::string, double>> carryWeights;  // reward edits: w_theta, w_d, w_v, speed, gamma
};

inline bool isGraphKind(SetupKind k) { return k == SetupKind::GraphDuel || k == SetupKind::GraphTeams || k == SetupKind::GraphCarry; }

// Reads and checks a graph setup's parameters. Errors name the setup and the
// JSON path of the field ("setup 'fight': /depth: must be an integer from 1
// to 64"); unknown fields are refused by name. A carry setup also needs the
// box's trajectory (a polyline of 2+ points, an arc or a circle) unless
// `checkPath` is false (a parameter edit before the path is drawn).
Result<GraphSetupParams> graphParams(const SceneSetup& setup, bool checkPath = true);

// The carry setup's trajectory (nullptr when it has none).
const Trajectory* carryTrajectory(const SceneSetup& setup);

}  // namespace fray::setup
