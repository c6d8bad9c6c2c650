#pragma once
// Temporal tree expansion (SPEC 2) deciding for one character of a duel that
// something else runs (an Interaction Graph match, thesis table 5.1): at each
// of its decisions the caller hands over both characters as they are at that
// moment, and the planner searches the game tree from there exactly as
// `simulate` does, the other character's choices inside the tree being the
// min-max prediction under the opponent model given at make(). The match,
// not the planner, then plays what both sides chose.
#include <cstdint>
#include <memory>
#include <vector>

#include "fray/core/result.h"
#include "fray/prep/combos.h"
#include "fray/sim/action_library.h"
#include "fray/sim/planner.h"

namespace fray::sim {

// One character of the duel at the moment of a decision.
struct DuelSideState {
    int action = 0;                  // library action it plays
    double start = 0, offset = 0;    // scene time its clip started playing, at clip time `offset`
    double end = 0;                  // scene time its action ends
    RootXf root;                     // placement of the clip's frame
    bool attackDone = false;         // its current attack has landed or was blocked (one blow per attack)
    bool reacting = false;           // in a forced reaction (cannot be hit again until it ends)
    std::vector<int> recent;         // its last actions, newest first (the recency penalty reads up to six)
};

struct TreeDecisionStats {
    std::int64_t decisions = 0, nodes = 0, leaves = 0, shallower = 0, fallbacks = 0;
};

class TreeDecider {
public:
    // `self` decides (its depth, weights, allowed actions and reactions);
    // `opponent` is the planner's model of the other side inside the tree.
    // They must be on different sides. options: pruning, alpha-beta,
    // parallel, variants, leaf budget and fall impulse as in simulate
    // (duration, seed and jitter do not apply).
    static Result<std::unique_ptr<TreeDecider>> make(const ActionLibrary& lib, const prep::ComboTable& combos, CharacterSpec self,
                                                      CharacterSpec opponent, SimOptions options = {});
    ~TreeDecider();
    TreeDecider(const TreeDecider&) = delete;
    TreeDecider& operator=(const TreeDecider&) = delete;

    // The choice of `self` at time t, when its action ends (self.end <= t,
    // opponent.end >= t). Const and thread-safe: matches may share one
    // decider. Deterministic for the same states. `stats`, when given, is
    // added to.
    Result<int> decide(const DuelSideState& self, const DuelSideState& opponent, double t, TreeDecisionStats* stats = nullptr) const;
    int depth() const;

private:
    TreeDecider();
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace fray::sim
