#pragma once
// Action-level motion graph (SPEC 1.5, thesis 3.3). Every action contributes
// its start pose and its end pose; K-means groups all of them into clusters
// whose largest pose-to-centre distance is below a threshold. Each cluster is
// a node, each action an edge from the node of its start pose to the node of
// its end pose, and Next(a) is every action that starts where a ends.
//
// Pose distance units. Every term is scaled to read roughly as "radians of
// joint motion", so one threshold works for every skeleton and capture rate:
//  - upper body: mean over the upper-body joints of the angle (rad) between
//    the two local rotations. The angle between rotations, not a difference of
//    Euler angles, so wrapping (179 vs -179 degrees) and the Euler order do
//    not matter. The pelvis is included as its world tilt with the heading
//    removed, which tells lying from standing.
//  - legs: pelvis->ankle vectors in the pelvis heading frame divided by the
//    leg length (hip to ankle at rest); a leg swinging by x rad about the hip
//    moves its vector by about x. Mean of the two legs.
//  - height: pelvis height above the world floor divided by the leg length.
//  - derivatives: the same quantities per second, times kVelocityScale
//    (0.1 s), so 1 rad/s of difference counts like 0.1 rad of pose
//    difference. Finite differences over ~1/60 s whatever the capture rate.
// The sum of means (instead of the SPEC's plain sums) keeps the scale
// independent of how many joints the skeleton has. D is a metric (sum of
// metrics), so two poses in one cluster are at most 2 * threshold apart.
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include "fray/core/joint_guess.h"
#include "fray/core/motion.h"
#include "fray/core/progress.h"
#include "fray/core/result.h"

namespace fray::prep {

// Seconds that turn a rate difference into a pose difference (see above).
inline constexpr double kVelocityScale = 0.1;

// One action of motions[motion]: frames [firstFrame, lastFrame], inclusive.
struct ActionRef {
    int motion = 0;
    int firstFrame = 0;
    int lastFrame = 0;
    friend bool operator==(const ActionRef&, const ActionRef&) = default;
};

// Weights of the six terms of D (SPEC 1.5: per data set).
struct GraphWeights {
    double upper = 1, upperVel = 1, leg = 1, legVel = 1, height = 1, heightVel = 1;
    static GraphWeights fighting();    // all terms equal
    static GraphWeights locomotion();  // upper body small: the legs decide
    // "fighting" or "locomotion"; nullopt for any other name.
    static std::optional<GraphWeights> preset(std::string_view name);
    friend bool operator==(const GraphWeights&, const GraphWeights&) = default;
};

// What D needs of one pose. Values are already normalised (see the top).
struct PoseFeature {
    // [0] pelvis world rotation without its heading, then the local rotation
    // of every upper-body joint (upperBodyJoints order).
    std::vector<glm::quat> rotations;
    std::vector<glm::vec3> angularVelocities;  // rad/s, same order, local frames
    std::array<glm::vec3, 2> legs{};           // [left, right] pelvis->ankle, heading frame, / leg length
    std::array<glm::vec3, 2> legVelocities{};  // 1/s
    float height = 0.0f;                       // pelvis height / leg length
    float heightVelocity = 0.0f;               // 1/s
};

// Upper-body joints: every joint on the chains from the head and both hands
// down to (not including) the pelvis, ascending. Fingers are not included.
std::vector<int> upperBodyJoints(const Skeleton& skeleton, const StandardJoints& joints);
// Mean rest length hip -> ankle of the two legs (m); 1 when it cannot be measured.
double legLength(const Skeleton& skeleton, const StandardJoints& joints);
// Heading (rad about +Y, 0 = facing +Z) of a pose from its world positions:
// the direction perpendicular to the hip line (right hip -> left hip), on the floor.
double headingOf(std::span<const glm::vec3> worldPositions, const StandardJoints& joints);

// Feature of one frame. Needs pelvis, head, hands, hips and feet
// (buildMotionGraph checks; here it is a precondition).
PoseFeature poseFeature(const Motion& motion, const StandardJoints& joints, int frame);
// SPEC 1.5 D(A, B). Both features must come from the same skeleton.
double poseDistance(const PoseFeature& a, const PoseFeature& b, const GraphWeights& weights);

// D of one pose against many, each packed once (forced reactions match a
// victim's posture against every reactive clip's opening poses). distance()
// gives the same value as poseDistance.
class PoseMatcher {
public:
    explicit PoseMatcher(const GraphWeights& weights = GraphWeights::fighting()) : weights_(weights) {}
    void add(const PoseFeature& pose);
    std::size_t size() const { return count_.size(); }
    // A pose to match, packed on demand for each rotation count it meets.
    class Probe {
    public:
        explicit Probe(const PoseFeature& pose) : pose_(&pose) {}

    private:
        friend class PoseMatcher;
        const PoseFeature* pose_;
        int n_ = -1;
        std::vector<float> packed_;
    };
    double distance(Probe& probe, std::size_t i) const;
    // distance(probe, i) + offset when that is below bound, else nothing
    // (the same value and test, summed only as far as needed: a search for
    // the best match skips most poses part way).
    std::optional<double> distanceBelow(Probe& probe, std::size_t i, double offset, double bound) const;

private:
    // Pose i packed as the probe is (the probe packed for it first); n: their rotations.
    const float* row(Probe& probe, std::size_t i, int& n) const;
    GraphWeights weights_;
    std::vector<float> packed_;
    std::vector<std::size_t> offset_;
    std::vector<int> count_;  // rotations per pose
};

struct GraphOptions {
    GraphWeights weights;
    // Largest allowed distance of a pose to its cluster centre, in the units
    // above (~radians). At 0.2 the demo library's 633 actions give about 30
    // nodes with 93-95 % of the actions in the largest strongly connected
    // component (seeds 1-8); lower it for closer joins (more nodes, fewer
    // connections), raise it for a denser graph.
    double threshold = 0.2;
    int maxNodes = 4096;  // K never grows past this; maxClusterDistance then tells how close it got
    std::uint64_t seed = 1;
};

struct GraphStats {
    int nodes = 0, edges = 0;
    double meanOutDegree = 0;  // edges per node
    int maxOutDegree = 0;
    int largestSccActions = 0;  // actions in the largest strongly connected set of the action graph (a -> Next(a))
    double sccShare = 0;        // largestSccActions / edges
    int deadEnds = 0;           // actions with an empty Next()
};

struct MotionGraph {
    int nodeCount = 0;
    std::vector<int> startNode, endNode;   // per action (edge)
    // Per action, ascending: the actions whose start node is its end node,
    // plus the action that continues it in its capture (see connectNodes).
    std::vector<std::vector<int>> next;
    std::vector<std::uint8_t> inLargestScc;  // per action: in the largest strongly connected set of actions
    int naturalEdges = 0;                  // capture continuations that clustering alone had not connected
    std::vector<PoseFeature> centres;      // per node: the cluster centre
    GraphStats stats;
    double maxClusterDistance = 0;  // achieved largest pose-to-centre distance
    int kmeansRounds = 0;           // K growth rounds it took
};

// Per action, the action that starts on the frame after its last in the same
// motion (its continuation in the capture), or -1.
std::vector<int> naturalSuccessors(std::span<const ActionRef> actions);

// Fills next, inLargestScc and stats of g from its node count and the
// start/end node of every action (indices in [0, g.nodeCount)). Used by
// buildMotionGraph, and to restore a graph from the project cache.
// `successors` (naturalSuccessors of the actions; may be empty) adds each
// action's continuation to its Next(): the capture's own transition needs no
// blend, yet its two sides, a frame apart, can fall in different clusters
// (on the demo running take every turn was a dead end without it).
void connectNodes(MotionGraph& g, std::vector<int> startNode, std::vector<int> endNode,
                  std::span<const int> successors = {});

// The transition gaps of a set of actions: for every action's end pose, D to
// the nearest start pose of any action other than its own continuation in its
// capture (naturalSuccessors), ascending. Clusters hold the poses within the
// threshold of a centre (itself near a pose), so an end joins a start of gap g
// reliably only when the threshold is about g or more: these gaps say
// how sparse the data is, whatever its skeleton, rate or source. At most
// maxEnds ends are measured (an even stride over them). Same validation and
// errors as buildMotionGraph.
Result<std::vector<double>> transitionGaps(std::span<const Motion* const> motions, std::span<const StandardJoints> joints,
                                           std::span<const ActionRef> actions, const GraphWeights& weights,
                                           int maxEnds = 4000, const ProgressFn& progress = {});

// The threshold the data asks for (docs/MOTION_GRAPH.md, "Threshold from the
// data"): the gap that kDataThresholdShare of the ends are within, times
// a margin of 1.5 (centres are means, not poses). The graph uses
// max(default threshold, this) when the user set no threshold.
inline constexpr double kDataThresholdShare = 0.9;
inline constexpr int kDataThresholdMaxEnds = 4000;
double thresholdFromGaps(std::span<const double> sortedGaps);

// Builds the graph. motions and joints are parallel; every motion must have
// the same skeleton (names and hierarchy). Deterministic for a seed. Fails
// with a readable message on bad input, or "cancelled" when progress says so.
Result<MotionGraph> buildMotionGraph(std::span<const Motion* const> motions, std::span<const StandardJoints> joints,
                                     std::span<const ActionRef> actions, const GraphOptions& options,
                                     const ProgressFn& progress = {});

}  // namespace fray::prep
