#pragma once
// What every Interaction Graph simulation shares: a body playing an action,
// the interaction state of a chooser against its opponent, and a duel
// advanced to its next decision with fray_sim's interaction engine deciding
// every blow, block and forced reaction. Internal to fray_igraph.
#include <cstdint>

#include "fray/igraph/igraph.h"
#include "interaction.h"  // fray_sim's interaction engine (core/sim/src)

namespace fray::igraph::detail {

struct Body {
    int action = 0;
    double start = 0, offset = 0, end = 0;
    sim::RootXf root;
    bool spent = false;     // its attack landed already (one blow per attack)
    bool reacting = false;  // in a forced reaction: cannot be hit until it ends
    sim::detail::Playing playing() const { return {action, start, offset, root}; }
    sim::RootXf placement(const sim::ActionLibrary& lib, double t) const {
        return root * lib.rootAt(action, offset + (t - start));
    }
    double clipTime(double t) const { return offset + (t - start); }
};

// Launches `action` at time t where the body's current action leaves it.
inline void launch(const sim::ActionLibrary& lib, Body& b, int action, double t) {
    b.root = b.root * lib.action(b.action).end;
    b.action = action;
    b.start = t;
    b.offset = 0;
    b.end = t + lib.action(action).duration;
    b.spent = false;
    b.reacting = false;
}

// The state of `me` about to choose at t against `other`.
InteractionState stateOf(const Rules& rules, const Body& me, const Body& other, double t);

// A body of action `action` at clip time `clip`, placed at `at` now (t).
Body bodyAt(const sim::ActionLibrary& lib, int action, double clip, const sim::RootXf& at, double t);

// What happened between two decisions of a duel, per body.
struct Outcome {
    std::array<float, 2> given{}, received{};
    std::array<int, 2> landed{}, suffered{}, blocked{};
};

// One blow found in an interval: used by the duel and by many-character matches.
struct Blow {
    double time = -1;
    int attacker = -1, defender = -1;
    sim::detail::HitCandidate hit;
};

// Applies a blow: the attack is spent; an unblocked one forces the victim
// into a reaction (Rules' pool). Returns the reaction (action -1 when none).
sim::detail::ForcedReaction applyBlow(const Rules& rules, Body& attacker, Body& victim, const sim::detail::HitCandidate& hit, double t);

// Advances a duel from t0 to its next decision (the earlier end), resolving
// blows in time order. Returns the decision time.
double advanceDuel(const Rules& rules, std::array<Body, 2>& b, double t0, Outcome& out);

// Who chooses next (the earlier end; body 0 on a tie).
inline int chooser(const std::array<Body, 2>& b) { return b[1].end < b[0].end ? 1 : 0; }

// splitmix64: the seeded random numbers of sampling and matches (portable).
struct Rng {
    std::uint64_t s;
    std::uint64_t next() {
        std::uint64_t z = (s += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    double uniform() { return static_cast<double>(next() >> 11) * (1.0 / 9007199254740992.0); }
    double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
    std::size_t below(std::size_t n) { return n == 0 ? 0 : static_cast<std::size_t>(next() % n); }
};

}  // namespace fray::igraph::detail
