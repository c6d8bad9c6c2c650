#pragma once
// Temporal tree expansion (SPEC 2, thesis chapter 4): characters choose
// actions by expanding a min-max game tree with asynchronous turns. A node is
// the moment either character finishes its action; its children are that
// character's candidate actions (Next() of the motion graph, pruned); a hit
// forces the victim into a reaction (one edge, no choice). Leaves score the
// path sum of competitive and cooperative terms; the back-up rules are the
// SPEC 2.2 ones; alpha-beta applies when the scene has no cooperative terms.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "fray/core/progress.h"
#include "fray/core/result.h"
#include "fray/prep/combos.h"
#include "fray/sim/action_library.h"
#include "fray/sim/scene.h"

namespace fray::sim {

// Objective weights of one character (SPEC 2.3). Every one is editable and
// stored in the project (see presets.h).
struct StyleWeights {
    // Competitive: movement, scoring, action combination.
    double wTheta = 10, wR = 10, rD = 0.8;
    double wHitShort = 1000, wHitLong = 1000;  // damage given by punches (short) / kicks (long)
    double wDamage = 1000;                     // damage received
    double wCombo = 100;
    bool catches = false;                      // chaser/runaway: scoring counts catches, not blows
    // Cooperative: global movement to checkpoints, required actions.
    double wPsi = 0, wPath = 0, wReq = 0;
    // Recency penalty (thesis 4.6.2): an action used among the last few of this character.
    double wRecency = 10;
    // Pruning thresholds (SPEC 2.4).
    double attackRange = 1.3, defenceRange = 3.0;  // pelvis to pelvis: about 1 m between the bodies
    bool faceOpponent = true;                  // criterion 2 (off for a runaway)
    // Movement and path terms (f_mov1, f_mov2) weighted by the launched
    // action's duration (per 0.5 s), so a path's sum measures time spent away
    // from the wish rather than decisions taken. With the thesis' per-edge
    // sums one long action costs one penalty where short ones cost several,
    // and a min edge's movement term rewards the maximiser whenever the
    // opponent is off its own preferred distance, near or far: a depth-4
    // chaser idled 9 m from a runaway for 15 s. On for the chaser and runaway
    // presets; the boxers keep per-edge sums (their duel tests were tuned on
    // them). Scoring, combination and recency terms stay per event.
    bool perSecond = false;
    friend bool operator==(const StyleWeights&, const StyleWeights&) = default;
};

struct CharacterSpec {
    std::string name;
    int side = 0;                  // characters on one side are a team: their scores add up
    int group = 0;                 // characters interact (plan, hit, catch) within their group only
    std::string preset;
    StyleWeights weights;
    int depth = 3;                 // decision levels expanded (intelligence)
    std::vector<int> allowed;      // library actions it may choose, ascending
    std::vector<int> reactions;    // reactive actions it can be forced into, ascending
    RootXf start;
    int startAction = -1;          // -1: an idle action of its set
    std::vector<Checkpoint> path;
    bool loopPath = false;
    std::vector<int> required;     // A+ (ascending)
    std::vector<int> forbidden;    // A- (ascending)
    int opponent = -1;             // -1: the nearest enemy in its group
    friend bool operator==(const CharacterSpec&, const CharacterSpec&) = default;
};

struct SimOptions {
    double duration = 20;
    std::uint64_t seed = 1;
    bool pruning = true;
    bool alphaBeta = true;
    bool parallel = true;          // TBB over root children (results do not depend on it)
    // Inside the tree (not at the root), variants of one choice (same name,
    // same end node: e.g. the 30 captured jabs) are represented by one of
    // them. The root still weighs every variant.
    bool variants = true;
    // Within a decision, a frontier node the search meets again (different
    // actions ending in the same blow lead to the same state) replays what
    // its first visit found instead of running again. Results do not depend
    // on it (a test compares both); off only to check that.
    bool reuseNodes = true;
    // Pins (SceneSpec::pins) inside the search's look-ahead (the spec's
    // "pins_in_tree"): a pinned character's node at its pin's decision has
    // only the pinned actions, so the opponent's search expects them and the
    // character's own earlier searches plan towards them
    // (docs/TREE_EXPANSION.md "Pins"). Off by default: earlier decisions
    // change with it, so the pinned action can move off the time the user
    // gave it (the demo duel's pinned kick from 1.52 to 1.89 s).
    bool pinsInTree = false;
    // Leaves one decision may visit. Deeper levels are searched one at a time
    // (iterative deepening); when one would exceed the budget the last
    // complete depth decides (counted in PlannerStats::shallower).
    std::int64_t leafBudget = 2000000;
    // Root beam (the spec's "root_beam"; docs/TREE_EXPANSION.md "Root beam"):
    // under alpha-beta, a decision searched 4 or more levels deep gives its
    // last iterative-deepening pass only to the `rootBeam` root children that
    // came first in the pass before (and to every child whose value there
    // equals the best's); the others cannot be chosen. 0: every child is
    // searched at full depth, the exact min-max choice. The default 8 plans
    // the demo duel with about a third of the exact search's CPU time and
    // kept the deeper boxer's wins and hits within noise of 16 over 160
    // seeded matches (docs/BENCHMARKS.md "Duel speed pass 5" and "Duel
    // speed pass 7").
    int rootBeam = 8;
    double catchRadius = 0.6;      // m, pelvis to pelvis
    bool stopOnCatch = false;      // a group's simulation ends at its first catch
    double fallImpulse = 30;       // N s: a stronger hit knocks down, a weaker one pushes
    double checkpointRadius = 0.6; // m: a checkpoint is reached within this
    double startJitter = 0;        // m: seeded random offset of every start placement (for match series)
    double startJitterDegrees = 0; // degrees: same for the start heading
    // The stage, a disc on the floor (radius 0: unbounded; its inner edge is
    // 0.3 m inside). A choice is legal when the character could still turn
    // back within the inner edge (judged up to three clips ahead); when none
    // is, the ones that get least far out. Ending beyond the inner edge also
    // costs 1000 per m^2 in F_comp, so deeper searches turn earlier. A
    // running turn can overshoot the edge by about 2.5 m, and reactions
    // (pushed, knocked down) can carry a character out.
    Arena arena;
    friend bool operator==(const SimOptions&, const SimOptions&) = default;
};

// A pinned choice (an edited generated interaction, docs/TREE_EXPANSION.md "Pins"):
// character `character` launches one of `actions` (a library action name or
// an "@annotation" of its set, `key`) at its first decision at or after
// time - kPinEarly. Decisions before it are steered so that the motion graph
// reaches the pinned action there: a candidate whose end would bring that
// decision must have a pinned action among its successors, when some
// candidate qualifies. When the character has no decision in
// [time - kPinEarly, time + kPinLate] from which the motion graph reaches a
// pinned action (a hit forced a long reaction, say), simulate fails naming
// the pin ("/pins/N/action"). Everything else is planned as usual around it.
struct ActionPin {
    int character = 0;         // index in SceneSpec::characters
    double time = 0;
    std::string key;           // as written: an action name or "@annotation"
    std::vector<int> actions;  // the library actions it names within the character's set, ascending
    friend bool operator==(const ActionPin&, const ActionPin&) = default;
};
inline constexpr double kPinEarly = 1.0 / 30.0;  // s: a decision this much before the pin's time is its decision
inline constexpr double kPinLate = 1.0;          // s: the latest a pinned action may start after the pin's time

struct SceneSpec {
    std::vector<CharacterSpec> characters;
    SimOptions options;
    std::string text;  // the spec as written, kept in the scene
    std::vector<ActionPin> pins;  // by character, then time
};

// Limits of one group (the game tree holds every member).
inline constexpr int kMaxGroupSize = 4;

// Runs the planner over the whole scene duration. Groups are independent and
// are simulated one after another; within a decision the root children run
// in parallel when options.parallel. Deterministic for a spec and seed.
Result<Scene> simulate(const ActionLibrary& lib, const prep::ComboTable& combos, const SceneSpec& spec,
                       const ProgressFn& progress = {});

// Incremental re-planning (docs/TREE_EXPANSION.md "Re-planning after an
// edit"). A PlanCache keeps what one run of simulate() saw: its spec, the
// group states at every decision, and per decision the furthest scene time
// and checkpoint its searches read. Handed the next spec (an edited setup),
// simulate() resumes each group from its last decision that the edit cannot
// reach and plans only from there; the scene is the same, byte for byte, as
// simulate() without a cache makes. An edit it cannot bound (a weight, a
// preset, the seed, a start placement, a looped path...) plans from the
// start. Valid for one action library and combination table: clear() it when
// they change. Copies share the record; simulate() replaces it only when it
// succeeds (a cancelled or failed run leaves the last one).
struct PlanRecord;  // internal (planner_state.h)
struct PlanCache {
    std::shared_ptr<const PlanRecord> last;
    void clear() { last.reset(); }
    bool empty() const { return !last; }
};

// How a run with a PlanCache went.
struct ReplanInfo {
    bool incremental = false;        // resumed from a kept state in some group
    double resumedAt = 0;            // the earliest scene time a group resumed from (0: from the start)
    std::int64_t decisionsKept = 0;  // decisions taken over from the last run
    std::int64_t decisionsPlanned = 0;  // decisions searched in this run
    std::string reason;              // why it planned from the start, when it did ("" when it resumed)
};

Result<Scene> simulate(const ActionLibrary& lib, const prep::ComboTable& combos, const SceneSpec& spec, PlanCache& cache,
                       const ProgressFn& progress = {}, ReplanInfo* info = nullptr);

}  // namespace fray::sim
