#pragma once
// The Interaction Graph (SPEC 3, thesis chapter 5): a finite state machine of
// two-character interaction states built off-line from the action library, a
// policy table per reward computed over it by min-max, and a run time that
// takes each decision by table look-up.
//
//  - Rules: which actions a graph character may launch, Next() of each, the
//    reactive clips it is forced into, and the interaction engine of fray_sim
//    (hits in time order, blocks, forced reactions) that every simulation here
//    plays by.
//  - buildGraph: off-policy sampling by selective game-tree expansion (3.2),
//    clustering under the SPEC distance (3.3), edges by simulating every
//    action of each state's Next set; the coverage measurement.
//  - computePolicy: min-max to depth D with gamma over a competitive reward (3.4).
//  - Match (runtime.h): many characters in two teams, user commands.
#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

#include "fray/core/progress.h"
#include "fray/core/result.h"
#include "fray/sim/action_library.h"

namespace fray::sim::detail {
class InteractionEngine;
}

namespace fray::igraph {

// The graph file's layout, and the rules its states and edges were made by
// (the interaction state, the distance, the simulation of an edge). A file of
// another rule is stale: build the graph again.
inline constexpr std::uint32_t kGraphFileVersion = 1;
// Its first 8 bytes; the carry graph file starts "FRAYIGCA" (carry.h).
inline constexpr std::string_view kGraphMagic = "FRAYIGPH";
// 2: an edge's blows are expected over its state's spread (BuildOptions::outcomeSamples);
// 3: an action whose result falls in no state is an edge to the nearest state with edges.
inline constexpr std::uint32_t kGraphRule = 3;

// Which actions a graph character may launch and what it reacts with.
class Rules {
public:
    // actions: the library actions a character may choose (empty: every
    // punch, kick, block, avoid, step, idle, transition and turn of the
    // motions that hold an attack: the fighting captures). Refused
    // when none of them is an attack, or none can follow another.
    static Result<std::shared_ptr<const Rules>> make(const sim::ActionLibrary& lib, std::vector<int> actions = {});
    ~Rules();
    Rules(const Rules&) = delete;
    Rules& operator=(const Rules&) = delete;

    const sim::ActionLibrary& library() const { return *lib_; }
    const sim::detail::InteractionEngine& engine() const { return *engine_; }
    int pool() const { return pool_; }
    const std::vector<int>& actions() const { return actions_; }  // ascending
    // The id of the set of actions a character may launch after `action`
    // (its Next() within the chosen actions; an action that nothing follows
    // gets the start set: the chosen idle actions, else all of them).
    int nextSetOf(int action) const { return nextSetOf_[static_cast<std::size_t>(action)]; }
    const std::vector<int>& nextSet(int id) const { return nextSets_[static_cast<std::size_t>(id)]; }
    int nextSetCount() const { return static_cast<int>(nextSets_.size()); }
    // The same with one action per variant class (the sampling's choices).
    const std::vector<int>& foldedSet(int id) const { return folded_[static_cast<std::size_t>(id)]; }
    // Idle actions of the chosen set (a match starts with one); never empty.
    const std::vector<int>& idle() const { return idle_; }
    double fallImpulse() const { return fallImpulse_; }
    // A hash of the chosen actions (a graph is valid for the set it was built with).
    std::uint64_t key() const { return key_; }

private:
    Rules() = default;
    const sim::ActionLibrary* lib_ = nullptr;
    std::unique_ptr<sim::detail::InteractionEngine> engine_;
    int pool_ = 0;
    std::vector<int> actions_, nextSetOf_, idle_;
    std::vector<std::vector<int>> nextSets_, folded_;
    double fallImpulse_ = 30;
    std::uint64_t key_ = 0;
};

// The interaction state of the character about to choose, A, against B
// (SPEC 3.1): distance, each one's facing against the line joining them,
// A's Next set, B's action and B's sample (kSampleRate) in it.
struct InteractionState {
    double r = 0, thetaA = 0, thetaB = 0;
    int nextSet = 0, actionB = 0;
    double frameB = 0;
};

struct DistanceScale {
    double sigmaR = 0.5;                            // m
    double sigmaTheta = std::numbers::pi / 6.0;     // rad
    double frameSigma = 4;                          // samples (kSampleRate): |F_B,i - F_B,j| < frameSigma
};

// D(I_i, I_j) of SPEC 3.3; infinity when the discrete parts differ.
double distance(const InteractionState& a, const InteractionState& b, const DistanceScale& s);

struct BuildOptions {
    std::uint64_t seed = 1;
    // Sampling (SPEC 3.2).
    double expandFraction = 0.2;   // top share of a node's children expanded
    std::int64_t maxSamples = 80000;  // the archive's size limit (distinct samples)
    double minNewShare = 0.02;     // stop when a round's share of new samples falls below
    int maxRounds = 40;
    int startStates = 16;          // sensible start states (seeded)
    int maxFrontier = 200;         // nodes expanded per round at most (a seeded choice beyond)
    double maxDistance = 4.0;      // m: states farther apart are stored, not expanded
    // Clustering and edges (SPEC 3.3).
    DistanceScale scale;
    double cellScale = 1.0;        // archive cells are this fraction of the sigmas (1: one sigma wide)
    int kmeansIterations = 4;
    // Edges per variant class of a Next set (variants: the same name and end
    // node, e.g. the 30 captured jabs): at most this many, spread over the
    // class; 0: every action of the Next set (SPEC 3.3 to the letter).
    int variantsPerClass = 2;
    double joinRadius = 1.5;       // a simulated result within this D of a state falls in it (half a sigma-wide cluster in each term)
    // An edge's blows (given, received) are the mean over the state's mean
    // and this many placements of B around it (r +- outcomeSpreadR, each
    // angle +- outcomeSpreadTheta, in a fixed pattern): a state stands for
    // the real geometries near it, and a blow that lands from the mean alone
    // mostly misses from them (docs/IGRAPH.md). 0: the mean only (rule 1).
    int outcomeSamples = 4;
    double outcomeSpreadR = 0.1;       // m
    double outcomeSpreadTheta = 0.14;  // rad
    // Coverage: states visited by full tree expansion to this depth from
    // coverageStarts of the start states (0: not measured).
    int coverageDepth = 3;
    int coverageStarts = 12;
    bool parallel = true;          // TBB; results do not depend on it
};

// One edge: the chooser launched `action` in state `from`; the next decision
// is state `to`'s, by the same character (sameChooser) or the other one; the
// unblocked blows in between. Its reward's geometry is the state it leads to
// (W_ij of SPEC 3.4 depends on i and j). 8 bytes: blow speeds in 0.1 m/s.
struct Edge {
    std::int32_t to = 0;
    std::uint16_t actionBits = 0;  // the action, and 0x8000 when the same character chooses next
    std::uint8_t givenQ = 0, receivedQ = 0;  // blow speeds (m/s) landed by / on the chooser, x10, at most 25.5

    static constexpr int kMaxAction = 0x7fff;
    int action() const { return actionBits & 0x7fff; }
    bool sameChooser() const { return (actionBits & 0x8000) != 0; }
    double given() const { return givenQ * 0.1; }
    double received() const { return receivedQ * 0.1; }
    static Edge make(int action, int to, bool sameChooser, double given, double received);
};
static_assert(sizeof(Edge) == 8);

struct GraphStats {
    std::int64_t samples = 0, rounds = 0, simulated = 0;
    double coverage = -1;            // share of tree-expansion states within the graph (< 0: not measured)
    std::int64_t coverageVisited = 0;
};

class Graph {
public:
    std::vector<InteractionState> states;   // cluster means, grouped by (nextSet, actionB, frame bucket)
    std::vector<std::uint32_t> firstEdge;   // states.size() + 1 offsets into edges
    std::vector<Edge> edges;
    std::uint64_t libraryKey = 0, actionsKey = 0;
    std::vector<int> actions;               // the chosen actions it was built with
    // Per edge, the time from its decision to the next one in samples
    // (kSampleRate, at most 255): the chooser's action when it chooses again,
    // else what is left of B's action (a blow's reaction may make it longer).
    // Filled by timeEdges (buildGraph and readGraph/loadGraph with the rules
    // do; it follows from the states, the edges and the library, so it is not
    // in the file). Empty: not timed (RewardWeights::tau then has no effect).
    std::vector<std::uint8_t> edgeFrames;
    void timeEdges(const sim::ActionLibrary& lib);
    double edgeSeconds(std::size_t edge) const;
    // Per state, its nearest other states of the same group within
    // joinRadius (at most kNeighbours, nearest first; CSR): where a real
    // result near the state may fall instead (RewardWeights::blur). Filled
    // with edgeFrames; empty: none.
    static constexpr int kNeighbours = 4;
    std::vector<std::uint32_t> nearFirst, near;
    void findNeighbours();
    BuildOptions options;
    GraphStats stats;

    std::size_t stateCount() const { return states.size(); }
    std::size_t edgeCount() const { return edges.size(); }
    std::size_t memoryBytes() const;
    // The edges of a state.
    const Edge* edgesBegin(int s) const { return edges.data() + firstEdge[static_cast<std::size_t>(s)]; }
    const Edge* edgesEnd(int s) const { return edges.data() + firstEdge[static_cast<std::size_t>(s) + 1]; }
    // The state an interaction state falls in: the nearest within joinRadius
    // of its group (-1: none). withinOnly false: else the nearest state with
    // edges of the same Next set (B's action alike first), for a character
    // that has left the graph; -1 only when that Next set has none.
    int find(const InteractionState& s, bool withinOnly = true) const;
    // Builds the look-up index (done by buildGraph and loadGraph).
    void index();

private:
    struct Bucket {
        std::uint64_t key;
        std::uint32_t begin, end, withEdges = 0;
        std::uint32_t cells = kNoCells;  // its cells' offsets in cellStart_ (kNoCells: few states, scanned whole)
    };
    static constexpr std::uint32_t kNoCells = 0xffffffffu;
    std::vector<Bucket> buckets_;          // sorted by key
    std::vector<std::vector<std::uint32_t>> withEdges_;  // per Next set: its states with edges
    std::uint64_t bucketKey(int nextSet, int actionB, int frameBucket) const;
    int frameBucket(double frame) const;
    // The off-graph look-up's spatial index: per Next set, its states with
    // edges in cells of sigma_r x (2 pi / n) x (2 pi / n) over (r, theta_A,
    // theta_B) (n = floor(2 pi / sigma_theta): a cell at least a sigma wide),
    // searched in shells of cells outwards until no nearer state can remain.
    struct Grid {
        int nr = 0, nt = 0;   // r cells, theta cells (each angle)
        double tw = 0;        // a theta cell's width (rad)
        std::vector<std::uint32_t> start, items;  // CSR: cell -> its states, ascending
    };
    std::vector<Grid> grids_;  // per Next set
    // Each bucket's states by (theta_A, theta_B) cell (n x n, each two sigmas
    // wide), then r, packed together: a bucket is searched in the cells and
    // the window of r that can hold a state nearer than the best found (or
    // the limit).
    struct Packed {
        double r, thetaA, thetaB, frameB;
        std::uint32_t index, hasEdges;
    };
    std::vector<Packed> packed_;            // bucket ranges as in states, reordered
    std::vector<float> packedR_;            // their r, compact for the binary searches (a conservative start only)
    std::vector<std::uint32_t> cellStart_;  // per bucket with cells, n * n + 1 offsets into packed_
    int thetaCells_ = 1;                    // n
    void indexBuckets();
    void scanBucket(std::size_t bucket, const InteractionState& s, double limit, bool edgesOnlyWithFrames, int rank, double& bestD, int& best,
                    int& bestRank) const;
    void indexGrids();
    std::size_t gridBytes() const;
    int nearestAnyB(const InteractionState& s) const;
};

// Builds the graph (SPEC 3.2-3.3). Deterministic for the options' seed
// whatever the thread count; progress and cancel between rounds and stages.
Result<Graph> buildGraph(const Rules& rules, const BuildOptions& options, const ProgressFn& progress = {});

// The graph file: magic, version, rule, library and action-set keys, the
// graph, a CRC-32. A file of another version or rule, made from other
// actions, or damaged is refused with a message naming the file.
Result<std::string> graphBytes(const Graph& g);
Status saveGraph(const Graph& g, const std::filesystem::path& file);
Result<Graph> readGraph(std::string_view bytes, std::string_view fileName, const Rules& rules);
Result<Graph> loadGraph(const std::filesystem::path& file, const Rules& rules);
// Reads a graph without an action library (stats): checks everything but
// the library key.
Result<Graph> readGraphUnbound(std::string_view bytes, std::string_view fileName);

// ---- policies (SPEC 3.4) -------------------------------------------------

// W = -w_theta*theta^2 - w_d*(d - d_p)^2 + w_a*D_plus - w_r*D_minus, per edge,
// from the controlled character's side; D in m/s of unblocked blows.
struct RewardWeights {
    double wTheta = 1, wD = 1, dP = 0.8, wA = 2, wR = 2;
    double gamma = 1;
    // The opponent's edges (min nodes): true, as tree expansion scores its
    // min edges (SPEC 2.2): the opponent's own reward W (its facing, its
    // distance, its blows, the same weights) counted against the controlled
    // character, so the min is an opponent pursuing its own wishes. false:
    // the controlled character's W of that edge (its own facing and
    // distance): the min is an opponent that spoils them (rule 1's policies).
    bool opponentOwn = false;
    // tau (s) > 0: an edge's discount is gamma^(dt / tau), dt the edge's time
    // to the next decision (Graph::edgeFrames), so the discount counts
    // seconds, not decisions of either character; 0: gamma per decision.
    double tau = 0;
    // The opponent's reply at its states: (1 - mix) x the worst for the
    // controlled character (the min of SPEC 3.4) + mix x the mean over its
    // edges. 0: the min.
    double opponentMix = 0;
    // The value of the state an edge leads to: (1 - blur) x its own +
    // blur x the mean of its neighbours' (Graph::near), as a real result
    // falls near the state the edge stores, not on it. 0: its own (SPEC 3.4).
    double blur = 0;
    // The discount of an edge of `frames` samples to the next decision.
    double discount(int frames) const;
    friend bool operator==(const RewardWeights&, const RewardWeights&) = default;
};
// Every weight a finite number >= 0 (gamma in [0, 1]); the message names the field.
Status validate(const RewardWeights& w);
// Boxing styles: "general", "infighter", "outboxer".
Result<RewardWeights> stylePreset(std::string_view name);
const std::vector<std::string>& styleNames();
// Edits one weight by "name=value" (w_theta, w_d, d_p, w_a, w_r, gamma;
// opponent=own|mine for opponentOwn).
Status applyRewardEdit(RewardWeights& w, std::string_view edit);

struct Policy {
    RewardWeights weights;
    int depth = 0;
    // Per state, the controlled character choosing there: the chosen edge
    // (index into Graph::edges; -1 when the state has none) and V(i, depth).
    std::vector<std::int32_t> best;
    std::vector<double> value;
    // V(., depth - 1) at the controlled character's states and at the
    // opponent's: ranks any edge, W + gamma V(next) (user commands).
    std::vector<double> mineBelow, theirsBelow;
    double seconds = 0;               // wall-clock compute time
    // The value of taking edge e (W + gamma V below) for the controlled character.
    double edgeValue(const Graph& g, const Edge& e) const;
};

// Min-max over the graph to `depth` (>= 1): max where the controlled
// character chooses, min where the opponent does. Cancelled via progress.
Result<Policy> computePolicy(const Graph& g, const RewardWeights& w, int depth, const ProgressFn& progress = {});
// W of an edge for the controlled character; chooserIsMine: it chose there.
double edgeReward(const Graph& g, const Edge& e, const RewardWeights& w, bool chooserIsMine);

// A policy that is recomputed in a background thread when the weights or
// depth change, while the previous one stays in use until the new one is done.
class PolicyService {
public:
    PolicyService(std::shared_ptr<const Graph> graph, std::shared_ptr<const Policy> initial);
    ~PolicyService();  // waits for a computation in flight (cancelling it)
    PolicyService(const PolicyService&) = delete;
    PolicyService& operator=(const PolicyService&) = delete;
    // The policy in force now (never null).
    std::shared_ptr<const Policy> current() const;
    // Starts a recomputation; a request while one runs cancels the running one.
    // Refuses invalid weights or depth at once (the current policy stays).
    Status request(const RewardWeights& w, int depth);
    bool busy() const;
    // Waits until no computation runs; the last error (if any) of a finished one.
    Status wait();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace fray::igraph
