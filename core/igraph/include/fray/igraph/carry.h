#pragma once
// The Interaction Graph for collaboration (SPEC 3.4-3.5, thesis 5.5): two
// carriers holding the two ends of one long box, face to face. The same
// pipeline as the duel's, for a pair that decides together:
//
//  - CarryGraph: off-policy sampling by selective expansion of the joint game
//    tree (both carriers launch an action at every decision; children ranked
//    by C + J, J the constraint: grips a box length apart, carriers facing),
//    states clustered under D of SPEC 3.3 at the carry scale, edges by
//    simulating every pair of actions from every state.
//  - computeCarryPolicy: W = -(w_theta*theta^2 + w_d*(d - d_p)^2 +
//    w_v*|v - v_p|^2), one policy per desired direction of the box (8, in
//    carrier A's frame), dynamic programming (max everywhere) to depth D.
//  - runCarry: the pair follows a user path (polyline or circle) by taking,
//    at each decision, the policy of the direction toward the path ahead;
//    the result is an ordinary sim::Scene with the box as a "box" body.
#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "fray/core/progress.h"
#include "fray/core/result.h"
#include "fray/igraph/igraph.h"
#include "fray/sim/action_library.h"
#include "fray/sim/scene.h"

namespace fray::igraph {

inline constexpr int kCarryDirections = 8;

struct CarryOptions {
    std::uint64_t seed = 1;
    std::string prefix = "carry_end_";  // the carry-end actions, by name (the demo actor's carry set)
    double boxLength = 1.6;             // d_p: grip to grip (m); the demo pair's box
    // Sampling (SPEC 3.2).
    double expandFraction = 0.2;
    std::int64_t maxSamples = 20000;
    double minNewShare = 0.02;
    int maxRounds = 60;
    int startStates = 16;
    int maxFrontier = 400;
    // Clustering and edges (SPEC 3.3) at the carry scale: the constraint is a
    // few centimetres (5 % of the box), so the sigmas are a few centimetres
    // and degrees, not the duel's 0.5 m and 30 degrees.
    DistanceScale scale{0.03, 0.03, 4};
    int kmeansIterations = 2;
    int variantsPerClass = 1;   // edge actions per action name and carrier (0: every variant)
    double joinRadius = 1.5;
    bool parallel = true;       // TBB; results do not depend on it
};

// A joint edge: carrier A launched actionA and B actionB in state `from`.
struct CarryEdge {
    std::int32_t to = 0;
    std::int16_t actionA = 0, actionB = 0;
    float boxX = 0, boxZ = 0;     // the box middle's move on the floor, in A's frame at the start (m; x left, z forward)
    float gripError = 0;          // the largest |grip distance - box length| during the edge (m)
    float seconds = 0;            // its duration (the longer action)
};

struct CarryGraph {
    std::vector<InteractionState> states;   // cluster means (r, theta_A, theta_B)
    std::vector<std::uint32_t> firstEdge;   // states.size() + 1
    std::vector<CarryEdge> edges;
    std::vector<int> actions;               // the carry-end actions (library indices)
    int hold = -1;                          // the action a pair holds with when a state has no edge
    CarryOptions options;
    double gripReach = 0;                   // grip ahead of the pelvis (m), mean over the actions' first samples
    double gripHeight = 0;
    std::int64_t samples = 0, rounds = 0, simulated = 0;
    double seconds = 0;                     // build time
    std::size_t memoryBytes() const;
    // The state an interaction state falls in (within joinRadius; -1: none),
    // or with nearest true the nearest state with edges.
    int find(const InteractionState& s, bool nearest) const;
};

// Builds the carry graph from the library's carry-end actions. Refused
// when the library has none ("...no carry-end actions...").
Result<CarryGraph> buildCarryGraph(const sim::ActionLibrary& lib, const CarryOptions& options, const ProgressFn& progress = {});

// W = -(w_theta*(theta_A^2 + theta_B^2) + w_d*e^2 + w_v*|v - v_p|^2) per edge,
// e the largest grip-distance error during the edge, theta the facing
// angles where it ends, v the box's velocity, v_p `speed` m/s in the
// desired direction.
struct CarryWeights {
    double wTheta = 1, wD = 400, wV = 8, speed = 0.35, gamma = 1;
};
// Every weight a finite number >= 0 (gamma in [0, 1]); the message names the field.
Status validate(const CarryWeights& w);
// Edits one weight by "name=value" (w_theta, w_d, w_v, speed, gamma).
Status applyCarryEdit(CarryWeights& w, std::string_view edit);

// Direction k (0..7) of the box in A's frame: k * 45 degrees left of A's forward.
glm::vec2 carryDirection(int k);

struct CarryPolicy {
    int direction = 0, depth = 0;
    CarryWeights weights;
    std::vector<std::int32_t> best;  // per state: the chosen edge (-1: none)
    std::vector<double> value;
    double seconds = 0;
};
// Dynamic programming (max everywhere) to `depth` >= 1.
Result<CarryPolicy> computeCarryPolicy(const CarryGraph& g, const CarryWeights& w, int direction, int depth,
                                       const ProgressFn& progress = {});
double carryEdgeReward(const CarryGraph& g, const CarryEdge& e, const CarryWeights& w, int direction);

// A user path on the floor: "circle:R" (radius R m about the origin,
// counter-clockwise from (R, 0)), or a JSON file
// {"version": 1, "loop": false, "points": [[x, z], ...]}.
struct CarryPath {
    std::vector<glm::vec2> points;
    bool loop = false;
};
Result<CarryPath> parseCarryPath(std::string_view spec);                          // "circle:R"
Result<CarryPath> carryPathFromJson(std::string_view json, std::string_view fileName);
// Distance of a floor point from the path.
double distanceToCarryPath(const CarryPath& path, glm::vec2 p);

struct CarryRunOptions {
    double duration = 60;
    double lookahead = 0.35;  // m along the path ahead of the box's nearest point (the 8 directions steer back within lookahead * tan(22.5 deg))
    std::uint64_t seed = 1;
    std::string record;      // kept as the scene's spec text
};

struct CarryRunStats {
    std::int64_t decisions = 0, offGraph = 0, holds = 0;
    double pathErrorMean = 0, pathErrorMax = 0;  // box middle to the path (m), every 1/30 s
    double gripErrorMax = 0;                     // max |grip distance - box length| / box length, every 1/30 s
    double decideSeconds = 0;
};

struct CarryRun {
    sim::Scene scene;  // carriers 0 and 1, the box (body "box") as character 2
    CarryRunStats stats;
};

// Two carriers following `path`: each decision looks up the pair's state
// and takes the edge of the policy for the direction (of the 8) nearest
// the way to the path ahead. `policies` holds one policy per direction.
Result<CarryRun> runCarry(const sim::ActionLibrary& lib, const CarryGraph& g, const std::vector<CarryPolicy>& policies,
                          const CarryPath& path, const CarryRunOptions& options, const ProgressFn& progress = {});

// The grip (midpoint of the hands) of an action at time t into it, in the action's frame.
glm::vec3 gripAt(const sim::ActionLibrary& lib, int action, double t);

}  // namespace fray::igraph
