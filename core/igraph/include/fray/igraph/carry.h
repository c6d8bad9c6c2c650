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
#include <filesystem>
#include <memory>
#include <optional>
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
    double seconds = 0;                     // build time (not in the file: beside it, FILE.build.json)
    std::uint64_t libraryKey = 0;           // sim::libraryFingerprint of the library it was built from
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

// ---- the carry graph file (docs/IGRAPH.md, "Carry graph file") ---------------------------

// The carry graph file's layout, and the rule its states and edges were made
// by (the pair's state, the carry distance, the simulation of a joint edge).
// A file of another rule is stale: build the graph again.
inline constexpr std::uint32_t kCarryGraphFileVersion = 1;
inline constexpr std::uint32_t kCarryGraphRule = 1;
// Its first 8 bytes; the duel's graph file starts "FRAYIGPH".
inline constexpr std::string_view kCarryGraphMagic = "FRAYIGCA";

// Magic, version, rule, the library's fingerprint, the build options and
// statistics, the actions, states and edges, a CRC-32 of everything before.
// The same graph gives the same bytes (the build time is not in them).
Result<std::string> carryGraphBytes(const CarryGraph& g);
Status saveCarryGraph(const CarryGraph& g, const std::filesystem::path& file);
// Refused with the file's name: not a carry graph (a duel's graph is named as
// such), another version (ErrorKind::Unsupported), another rule or other
// carry-end actions than the library has now (ErrorKind::Stale: build it
// again), a checksum that does not match, values out of range, trailing data.
Result<CarryGraph> readCarryGraph(std::string_view bytes, std::string_view fileName, const sim::ActionLibrary& lib);
Result<CarryGraph> loadCarryGraph(const std::filesystem::path& file, const sim::ActionLibrary& lib);
// Without a library (igraph stats): every check but the library's.
Result<CarryGraph> readCarryGraphUnbound(std::string_view bytes, std::string_view fileName);

// ---- the eight policies, recomputed in the background -------------------------------------

// One policy per direction (8), for one set of weights and depth.
struct CarryPolicySet {
    CarryWeights weights;
    int depth = 0;
    std::vector<CarryPolicy> policies;  // index = direction
    double seconds = 0;                 // wall clock of the eight
};
// The eight directions' policies (in parallel; the same as eight computeCarryPolicy calls).
Result<CarryPolicySet> computeCarryPolicies(const CarryGraph& g, const CarryWeights& w, int depth, const ProgressFn& progress = {});

// The collaborative policies recomputed in a background thread when a reward
// weight or the depth changes, while the previous ones keep playing (the
// duel's PolicyService machinery: fray/igraph/background.h).
class CarryPolicyService {
public:
    CarryPolicyService(std::shared_ptr<const CarryGraph> graph, std::shared_ptr<const CarryPolicySet> initial);
    ~CarryPolicyService();  // cancels a computation in flight and waits for it
    CarryPolicyService(const CarryPolicyService&) = delete;
    CarryPolicyService& operator=(const CarryPolicyService&) = delete;
    std::shared_ptr<const CarryPolicySet> current() const;  // never null
    // Invalid weights or depth are refused at once (the current set stays);
    // a request while one runs cancels the running one.
    Status request(const CarryWeights& w, int depth);
    bool busy() const;
    Status wait();  // the last error of a finished computation, if any

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// ---- the pair in real time (fray-play --carry) ------------------------------------------------

// Two carriers driven decision by decision as time advances: along a path
// (the same choices as runCarry), or in a direction the user steers (world
// frame), or holding. The scene grows as time passes: the carriers' actions
// up to the one playing, the box's keys every 1/30 s up to now.
class CarryDriver {
public:
    // path: followed when given (the start as runCarry's); else the pair
    // starts with the box's middle at `start`, carrier A facing `heading`
    // (sim::angleOf's convention), holding until steered.
    static Result<std::unique_ptr<CarryDriver>> make(const sim::ActionLibrary& lib, std::shared_ptr<const CarryGraph> g,
                                                     std::shared_ptr<const CarryPolicySet> policies, std::optional<CarryPath> path,
                                                     glm::vec2 start = {0, 0}, double heading = 0, double lookahead = 0.35);
    // The policies used from the next decision on (the same graph; invalid sets are refused).
    Status setPolicies(std::shared_ptr<const CarryPolicySet> policies);
    const std::shared_ptr<const CarryPolicySet>& policies() const { return policies_; }
    // Steering (without a path): the desired direction of the box on the
    // floor, world frame (sim::angleOf), and whether to move at all.
    void steer(double worldAngle, bool moving);
    double desiredAngle() const { return desired_; }
    bool moving() const { return moving_; }
    bool followsPath() const { return path_.has_value(); }
    const std::optional<CarryPath>& path() const { return path_; }
    // Advances dt s (> 0): decisions at the exact ends of the actions, box keys every 1/30 s.
    void advance(double dt);
    double time() const { return time_; }
    const sim::Scene& scene() const { return scene_; }

    struct Now {
        int direction = -1;          // the policy direction (0..7, k*45 degrees left of A's forward) of the last decision; -1: holding
        int state = -1;              // the graph state it fell in (or the nearest)
        bool offGraph = false;
        double gripDistance = 0;     // the grips' distance at the last box key (m)
        double pathError = -1;       // the box middle's distance from the path then (m; < 0: no path)
        glm::vec2 boxMiddle{0.0f};   // on the floor, then
        double heading = 0;          // carrier A's heading at the last decision
    };
    const Now& now() const { return now_; }
    const CarryRunStats& stats() const { return stats_; }  // so far (path errors: with a path)
    double boxLength() const { return graph_->options.boxLength; }
    const CarryGraph& graph() const { return *graph_; }

private:
    CarryDriver(const sim::ActionLibrary& lib, std::shared_ptr<const CarryGraph> g, std::shared_ptr<const CarryPolicySet> p);
    void decide();
    void sampleBox(double t);
    const sim::ActionLibrary& lib_;
    std::shared_ptr<const CarryGraph> graph_;
    std::shared_ptr<const CarryPolicySet> policies_;
    std::optional<CarryPath> path_;
    sim::Scene scene_;
    sim::RootXf a_, b_;
    double time_ = 0, next_ = 0, lookahead_ = 0.35;
    double desired_ = 0;
    bool moving_ = false;
    std::int64_t samples_ = 0;
    double pathSum_ = 0;
    Now now_;
    CarryRunStats stats_;
};

}  // namespace fray::igraph
