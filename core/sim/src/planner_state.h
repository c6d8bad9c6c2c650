#pragma once
// Tree expansion's state and rules (SPEC 2): the group of characters at a
// node, what happened between two nodes, the planning context shared by the
// search, and the rules that advance a group from one node to the next
// (hits and forced reactions through the interaction engine, catches,
// checkpoints). planner_search.cpp holds the rules and the min-max search,
// planner.cpp the legal choices and the scene loop. Internal to fray_sim.
#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cstdint>
#include <functional>
#include <string>
#include <limits>
#include <memory>
#include <vector>

#include "fray/sim/planner.h"
#include "interaction.h"

namespace fray::sim::planner {

inline constexpr int kRecent = 6;
inline constexpr double kPenetrationStep = 1.0 / 15.0;  // s between body tests when pruning
inline constexpr double kArenaMargin = 0.3;             // m: a pelvis this close to the arena's edge is outside
inline constexpr double kArenaWeight = 1000;            // per m^2 beyond the arena's inner edge (F_comp)
inline constexpr int kArenaLookAhead = 3;               // clips after a candidate searched for a way back in
inline constexpr std::size_t kArenaBeam = 3;            // clips followed per look-ahead step
inline constexpr double kMovementSeconds = 0.5;         // s: the action length whose movement terms weigh 1 (per-second scoring)
inline constexpr double kCatchStep = 1.0 / 15.0;
inline constexpr float kPenetrationShrink = 0.8f;       // grazing contact is not penetration
inline constexpr float kPenetrationReach = 0.8f;        // m: two torsos are never wider apart
inline constexpr double kReachMargin = 0.35;             // m beyond an attack's reach: the target's body depth and a lean

struct CharState {
    int action = 0;
    double start = 0, offset = 0, end = 0;
    RootXf root;
    int checkpoint = 0;
    bool attackDone = false;   // the current attack landed (one hit per attack)
    bool caught = false;       // a catch was scored during the current action
    bool reacting = false;     // in a forced reaction: cannot be hit again until it ends
    // The names (Context::nameId) of its last actions, newest first: recency()
    // is asked about every candidate of a node, an action starts once.
    std::array<std::int16_t, kRecent> recent{};
    std::int8_t recentCount = 0;
};

struct GroupState {
    double time = 0;
    int n = 0;
    std::array<CharState, kMaxGroupSize> c{};
};

// What happened while a state advanced from one node to the next.
struct Events {
    std::array<double, kMaxGroupSize> givenShort{}, givenLong{}, received{};
    std::array<int, kMaxGroupSize> catches{}, caught{};
};

struct Recorder {
    Scene* scene = nullptr;
    std::array<int, kMaxGroupSize> global{};
    bool stop = false;  // stopOnCatch fired
};

// A character's path as the path term follows it (docs/TREE_EXPANSION.md
// "Following a path"): the polyline through its checkpoints, measured along
// its length, and the schedule its timed checkpoints make.
struct PathPlan {
    bool active = false;                 // a path, w_path > 0 and no loop: the progress term applies
    std::vector<glm::vec2> points;       // the checkpoints' positions
    std::vector<double> along;           // per checkpoint: its distance from the first along the polyline
    std::vector<double> knotTime, knotAlong;  // the schedule: (0 s, 0 m), then each timed checkpoint
    // Where along the path the character should be at time t.
    double goal(double t) const;
    // The point of the polyline nearest to p among the segments around
    // checkpoint `next` (the next one to reach): its distance along the path
    // and p's distance from it.
    void project(glm::vec2 p, int next, double& s, double& lateral) const;
};
PathPlan makePathPlan(const CharacterSpec& spec);

struct Member {
    int global = 0;
    const CharacterSpec* spec = nullptr;
    // Per library action: its Next() within this character's allowed set,
    // reactive clips left out (SPEC 2.1's legal choices before pruning).
    std::vector<std::vector<int>> legal;
    // The same with one representative (the first) per variant class, for
    // inside the tree (SimOptions::variants).
    std::vector<std::vector<int>> folded;
    int pool = 0;  // its reactive clips (spec->reactions) in the interaction engine
    PathPlan path;  // set by simulate (makePathPlan)
};

// Per library action: its Next() within the character's allowed set, reactive clips left out.
std::vector<std::vector<int>> legalChoices(const ActionLibrary& lib, const CharacterSpec& spec);
// The same with one representative per variant class.
std::vector<std::vector<int>> foldVariants(const ActionLibrary& lib, const std::vector<std::vector<int>>& legal);

struct SearchMemory;

struct Context {
    const ActionLibrary* lib = nullptr;
    const std::vector<float>* combo = nullptr;  // combo[mine * n + theirs]
    int comboN = 0;
    const SimOptions* opt = nullptr;
    std::vector<Member> members;
    bool cooperative = false;  // any cooperative weight: alpha-beta does not apply
    const detail::InteractionEngine* engine = nullptr;  // hits and forced reactions
    std::vector<int> nameId;             // per library action: its name's number (unnamed: a number of its own)
    std::vector<RootXf> endAt;           // per library action: rootAt(action, duration)
    std::vector<glm::vec2> endFacing;    // per library action: headingVector of endAt's heading
    std::vector<double> maxHitSpeed;     // per library action: the fastest its effector lands (attacks; else 0)
    // Per library action, from testPelvisBegin[action]: its pelvis in the
    // clip's frame (rootAt(action, tau).pos) at the clip times the
    // penetration test steps through, tau = 0, kPenetrationStep, ... (summed
    // as that loop sums them) up to its duration. Every node tests its
    // candidates at these same times.
    std::vector<std::size_t> testPelvisBegin;
    std::vector<glm::vec2> testPelvis;
    // At the same index: its core boxes (kCoreSegments) at that clip time in
    // the clip's frame, shrunk by kPenetrationShrink, with their bounding
    // radii. Placing a box does not change its half extents, so these are
    // the shrunk placed boxes' radii, and a placed box is placed(local) of
    // these, bit for bit.
    struct TestBody {
        std::array<Obb, kCoreSegments.size()> boxes;
        std::array<float, kCoreSegments.size()> radii;
    };
    std::vector<TestBody> testBodies;
    // Per member: its next pin not yet honoured (nullptr: none); empty when
    // the scene has no pins or SimOptions::pinsInTree is off. Set before
    // each decision (PinGuide::inTree); the Pruner narrows the pin's node.
    std::vector<const ActionPin*> treePins;
    // What the searches read of the inputs an edit may change (paths, pins),
    // kept for incremental re-planning (PlanCache); nullptr: not kept.
    struct ReadMarks* reads = nullptr;
    bool duel = false;                   // two members on opposite sides: each one's opponent is the other
    bool boundedFrontier = false;        // a duel scored by blows: frontier edges can be bounded (boundedFrontier)
    // The searches' per-thread storage (children, keys, the frontier memo's
    // tables), kept from one decision of the group to the next so that it is
    // allocated once, not per decision; what it holds is cleared before each
    // decision. Null: each decision allocates its own.
    std::shared_ptr<SearchMemory> memory;
};
// A group's SearchMemory (Context::memory), empty.
std::shared_ptr<SearchMemory> makeSearchMemory();

// What one step of the scene loop (a decision's searches and the advance to
// the next node) read of the inputs an edit may change (docs/TREE_EXPANSION.md
// "Re-planning after an edit"): the latest scene time any path schedule, pin
// window or checkpoint time was read at, and per member the furthest
// checkpoint index any state reached (the path's points and lengths are read
// up to 3 beyond it). Searches of one decision run in parallel: atomics.
struct ReadMarks {
    std::atomic<double> reach{-std::numeric_limits<double>::infinity()};
    std::array<std::atomic<int>, kMaxGroupSize> checkpoint{};
    void reset() {
        reach.store(-std::numeric_limits<double>::infinity(), std::memory_order_relaxed);
        for (auto& c : checkpoint) c.store(0, std::memory_order_relaxed);
    }
    static void raise(std::atomic<double>& a, double v) {
        double cur = a.load(std::memory_order_relaxed);
        while (v > cur && !a.compare_exchange_weak(cur, v, std::memory_order_relaxed)) {
        }
    }
    static void raise(std::atomic<int>& a, int v) {
        int cur = a.load(std::memory_order_relaxed);
        while (v > cur && !a.compare_exchange_weak(cur, v, std::memory_order_relaxed)) {
        }
    }
};

// The suitability matrix (Context::combo) over the actions the characters may play or be forced into.
std::vector<float> comboMatrix(const ActionLibrary& lib, const prep::ComboTable& combos, const std::vector<CharacterSpec>& characters);
// A planning context without members: per-action tables built once per planning run.
Context baseContext(const ActionLibrary& lib, const SimOptions& opt, const std::vector<float>& combo,
                    const detail::InteractionEngine& engine);

struct Value {
    double comp = 0, coop = 0;
};

struct Stats {
    std::int64_t nodes = 0, leaves = 0, choices = 0, pruned = 0, cutoffs = 0;
    std::int64_t shallower = 0;  // decisions taken at a lower depth than asked (budget)
    std::int64_t budget = std::numeric_limits<std::int64_t>::max();  // leaves this search may visit
    bool exhausted = false;
    void add(const Stats& o) {
        nodes += o.nodes, leaves += o.leaves, choices += o.choices, pruned += o.pruned, cutoffs += o.cutoffs;
        shallower += o.shallower;
    }
};

inline const LibraryAction& act(const Context& ctx, int a) { return ctx.lib->actions()[static_cast<std::size_t>(a)]; }
inline const CharacterSpec& specOf(const Context& ctx, int i) { return *ctx.members[static_cast<std::size_t>(i)].spec; }

inline double clipTime(const CharState& s, double t) { return s.offset + (t - s.start); }

inline RootXf placement(const Context& ctx, const CharState& s, double t) {
    return s.root * ctx.lib->rootAt(s.action, clipTime(s, t));
}

inline int chooserOf(const GroupState& g) {
    int best = 0;
    for (int i = 1; i < g.n; ++i) {
        if (g.c[static_cast<std::size_t>(i)].end < g.c[static_cast<std::size_t>(best)].end) best = i;
    }
    return best;
}

inline bool enemies(const Context& ctx, int a, int b) { return specOf(ctx, a).side != specOf(ctx, b).side; }

inline int opponentOfInGroup(const Context& ctx, const GroupState& g, int who, double t);
// Whom `who` fights at time t: in a duel the other, else its explicit
// opponent or the nearest enemy (opponentOfInGroup).
inline int opponentOf(const Context& ctx, const GroupState& g, int who, double t) {
    if (ctx.duel) return 1 - who;
    return opponentOfInGroup(ctx, g, who, t);
}
inline int opponentOfInGroup(const Context& ctx, const GroupState& g, int who, double t) {
    const int explicitOpp = specOf(ctx, who).opponent;
    if (explicitOpp >= 0) {
        for (int i = 0; i < g.n; ++i) {
            if (ctx.members[static_cast<std::size_t>(i)].global == explicitOpp) return i;
        }
    }
    // One enemy in the group (a duel): no need to measure.
    int only = -1, enemiesFound = 0;
    for (int i = 0; i < g.n; ++i) {
        if (i != who && enemies(ctx, who, i)) only = i, ++enemiesFound;
    }
    if (enemiesFound <= 1) return only;
    const glm::vec2 p = placement(ctx, g.c[static_cast<std::size_t>(who)], t).pos;
    int best = -1;
    float bestD = std::numeric_limits<float>::max();
    for (int i = 0; i < g.n; ++i) {
        if (i == who || !enemies(ctx, who, i)) continue;
        const glm::vec2 d = placement(ctx, g.c[static_cast<std::size_t>(i)], t).pos - p;
        const float dd = glm::dot(d, d);
        if (dd < bestD) bestD = dd, best = i;
    }
    return best;
}

inline void pushRecent(const Context& ctx, CharState& s, int action) {
    std::copy_backward(s.recent.begin(), s.recent.end() - 1, s.recent.end());
    s.recent[0] = static_cast<std::int16_t>(ctx.nameId[static_cast<std::size_t>(action)]);
    if (s.recentCount < kRecent) ++s.recentCount;
}

// How recently an action with the same name was used: 1 for the last one,
// fading to 1/kRecent for the oldest remembered; 0 when not remembered.
inline double recency(const Context& ctx, const CharState& s, int action) {
    const int name = ctx.nameId[static_cast<std::size_t>(action)];
    for (int k = 0; k < s.recentCount; ++k) {
        if (s.recent[static_cast<std::size_t>(k)] == name) return 1.0 - static_cast<double>(k) / kRecent;
    }
    return 0.0;
}

inline void launch(const Context& ctx, GroupState& g, int who, int action, double t) {
    auto& s = g.c[static_cast<std::size_t>(who)];
    const RootXf endPlacement = s.root * act(ctx, s.action).end;
    s.action = action;
    s.start = t;
    s.offset = 0;
    s.end = t + act(ctx, action).duration;
    s.root = endPlacement;
    s.attackDone = false;
    s.caught = false;
    s.reacting = false;
    pushRecent(ctx, s, action);
}

// Marks what an edge "who launched action from before, reaching after" reads
// (Context::reads): the launch's nominal end (the pins' rule), the next node
// and the launcher's end (the path schedule), every member's checkpoint.
inline void noteReads(const Context& ctx, const GroupState& before, const GroupState& after, int who, int action) {
    if (!ctx.reads) return;
    ReadMarks& r = *ctx.reads;
    const double end = before.time + ctx.lib->actions()[static_cast<std::size_t>(action)].duration;
    ReadMarks::raise(r.reach, std::max({end, after.time, after.c[static_cast<std::size_t>(who)].end}));
    for (int i = 0; i < after.n; ++i) {
        ReadMarks::raise(r.checkpoint[static_cast<std::size_t>(i)], after.c[static_cast<std::size_t>(i)].checkpoint);
    }
}

inline detail::Playing playing(const CharState& s) { return {s.action, s.start, s.offset, s.root}; }

void updateCheckpoints(const Context& ctx, GroupState& g, double t);
// Advances the group from its node time to the next node (the next moment a
// character finishes its action), resolving hits (forced reactions) and catches.
void advance(const Context& ctx, GroupState& g, Events& ev, Recorder* rec);

// The real choice of the character due at g.time (min-max over `depth` decisions).
// `filter`, when given, edits the root's candidates after pruning (pins,
// planner_pins.cpp); nothing else changes.
using CandidateFilter = std::function<void(std::vector<int>& candidates)>;
int decide(const Context& ctx, const GroupState& g, int depth, Stats& stats, bool& fellBack,
           const CandidateFilter* filter = nullptr);

// Pins (SceneSpec::pins) of one group: the choice at a decision, steered or
// forced by the pins (planner_pins.cpp). `decided` is the plain choice;
// `redecide` decides again with a filter on the candidates.
class PinGuide {
public:
    PinGuide(const Context& ctx, const SceneSpec& spec);
    bool empty() const { return pins_.empty(); }
    Result<int> choose(const Context& ctx, const GroupState& g, int who, int decided,
                       const std::function<int(const CandidateFilter&)>& redecide);
    // After the group's last decision: a pin of the group never honoured.
    Status finish(const Context& ctx) const;
    // Context::treePins for the next decision: each member's first pin not yet honoured.
    void inTree(Context& ctx) const;
    // Whether node g is, inside the tree, the pin's decision of `who`: the
    // pin's window [time - kPinEarly, time + kPinLate] and its current action
    // began before the window (else a decision in it came first) or is a
    // reaction to a hit.
    static bool pinNode(const ActionPin& pin, const GroupState& g, int who);
    // Per member: how many of its pins fired (they fire in time order). For
    // resuming from a kept state (PlanCache).
    std::vector<int> firedCounts(int members) const;
    void restoreFired(const std::vector<int>& counts);

private:
    struct Entry {
        const ActionPin* pin = nullptr;
        int index = 0;    // in SceneSpec::pins
        int member = 0;   // in ctx.members
        bool fired = false;
    };
    Error missed(const Context& ctx, const Entry& e, const GroupState* g) const;
    std::vector<Entry> pins_;  // by member, then time
};

// One character's placement at one moment, kept for the next call with the
// same state and moment (compared bit for bit: the same inputs, the same
// value). A node's edges judge the opponent where its action ends whenever
// the candidate outlasts it, from the same state unless a blow changed it, so
// one per node saves most of those placements.
class PlacementMemo {
public:
    RootXf operator()(const Context& ctx, const CharState& s, double t) {
        if (!valid_ || s.action != action_ || !same(s.start, start_) || !same(s.offset, offset_) || !same(t, t_) ||
            !same(s.root.pos.x, root_.pos.x) || !same(s.root.pos.y, root_.pos.y) ||
            !same(s.root.heading, root_.heading)) {
            valid_ = true;
            action_ = s.action, start_ = s.start, offset_ = s.offset, root_ = s.root, t_ = t;
            value_ = placement(ctx, s, t);
        }
        return value_;
    }

private:
    static bool same(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }
    static bool same(float a, float b) { return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b); }
    bool valid_ = false;
    int action_ = 0;
    double start_ = 0, offset_ = 0, t_ = 0;
    RootXf root_;
    RootXf value_;
};

// F_comp and F_coop of the edge "who launched action" (SPEC 2.3), evaluated
// at the next node with the events of the interval. oppAt: the node's memo of
// the opponent's placement.
Value edgeScore(const Context& ctx, const GroupState& before, const GroupState& after, int who, int action,
                const Events& ev, PlacementMemo& oppAt);

}  // namespace fray::sim::planner

namespace fray::sim {

// One run of simulate() as a PlanCache keeps it (planner.cpp).
struct PlanSnapshot {
    planner::GroupState g;            // at the top of the scene loop, before a decision
    bool stop = false;
    std::vector<std::size_t> trackSize;     // per member: its track's length
    std::vector<ActionInstance> trackLast;  // per member: its last instance as it was then
    std::vector<std::int64_t> fallbacks;    // per member: SceneCharacter::fallbacks
    std::size_t hits = 0, catches = 0;      // recorded by the group so far
    std::int64_t decisions = 0, fallbackDecisions = 0, forced = 0;  // the group's PlannerStats so far
    planner::Stats search;                  // the group's search statistics so far
    std::vector<int> pinsFired;             // per member
    // What the step from here read (planner::ReadMarks); the last snapshot's
    // step never ran: it reads everything.
    double reach = std::numeric_limits<double>::infinity();
    std::array<int, kMaxGroupSize> checkpoint{};
};

struct PlanGroupRecord {
    double initReach = 0;                          // what the start and the first advance read
    std::array<int, kMaxGroupSize> initCheckpoint{};
    std::vector<PlanSnapshot> snaps;               // one per decision, then the state after the loop
    std::vector<std::vector<ActionInstance>> tracks;  // per member, as the loop left them
    std::vector<HitEvent> hits;                    // as recorded (before the scene's sort)
    std::vector<CatchEvent> catches;
};

struct PlanRecord {
    const ActionLibrary* lib = nullptr;
    int libActions = 0;
    std::vector<float> combo;  // planner::comboMatrix of the run
    SceneSpec spec;
    std::vector<PlanGroupRecord> groups;
};

}  // namespace fray::sim
