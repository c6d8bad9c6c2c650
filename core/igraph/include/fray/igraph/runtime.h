#pragma once
// The Interaction Graph at run time (SPEC 3.5): characters in two teams,
// each fighting its closest enemy (switching opponents on the fly), every
// decision a table look-up in the graph and a policy. A character may be
// steered by the user with high-level commands (the best action of that
// category from the graph). A match writes an ordinary fray::sim::Scene.
//
// fray-play drives a Match frame by frame: command() when a key goes down,
// setPolicy() when a PolicyService has a recomputed policy, step(dt).
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "fray/core/result.h"
#include "fray/igraph/igraph.h"
#include "fray/sim/scene.h"
#include "fray/sim/tree_decider.h"

namespace fray::igraph {

enum class Command { None, Forward, Back, TurnLeft, TurnRight, Punch, Kick, Dodge, Avoid };
// "forward", "back", "turn-left", "turn-right", "punch", "kick", "dodge", "avoid".
Result<Command> parseCommand(std::string_view name);
const char* commandName(Command c);
// Would launching `action` in interaction state `s` carry out command c?
// forward/back: a movement that ends >= 0.15 m nearer/farther along the line
// to the opponent; turns: a movement turning >= 0.3 rad; punch, kick: those
// attacks; dodge: actions annotated dodge; avoid: those annotated avoid, and blocks.
bool fulfils(const sim::ActionLibrary& lib, int action, const InteractionState& s, Command c);

struct TimedCommand {
    double time = 0;
    int character = 0;
    Command command = Command::None;
};
// {"version": 1, "commands": [{"time": 2.0, "command": "punch", "character": 0}, ...]}
// (character defaults to 0). Errors name the file and the entry.
Result<std::vector<TimedCommand>> parseCommands(std::string_view json, std::string_view fileName);

enum class Mind {
    Graph,   // its policy's choice by look-up
    Static,  // a static target: idles (and guards) where it stands, never attacks
    Tree,    // temporal tree expansion (SPEC 2) from the match's state at each decision (FighterSpec::tree)
};

struct FighterSpec {
    std::string name;
    int side = 0;
    Mind mind = Mind::Graph;
    std::shared_ptr<const Policy> policy;  // Mind::Graph
    std::string style;                     // for the scene's record
    sim::RootXf start;
    // Mind::Tree: decides against its closest enemy (a duel: the planner
    // sees these two). May be shared by matches running in parallel.
    std::shared_ptr<const sim::TreeDecider> tree{};
};

struct MatchOptions {
    double duration = 30;
    double step = 1.0 / 60.0;  // s per simulation step (blows are found within a step, decisions are exact)
    double commandHold = 1.0;  // s a command waits for a decision that can carry it out (the next decision always sees it)
    std::uint64_t seed = 1;
    std::string record;        // the match's description, kept as the scene's spec text
    // Graph characters re-simulate the edges of the state they fall in from
    // the real bodies (one step, as the graph's edges were built from the
    // state's mean) and take the best by the policy's reward plus gamma V of
    // the state reached, instead of the state's stored choice. The graph's
    // states are up to sigma_r, sigma_theta from the real geometry, and a
    // blow predicted there can miss here. Costs a simulation per edge.
    bool refine = false;
    // Graph characters measure how well the graph predicts: every edge of
    // the state found is also simulated from the real bodies (as refine
    // does) and its stored outcome compared (MatchStats::prediction). Does
    // not change any choice; costs a simulation per edge.
    bool measure = false;
};

// How the graph's stored outcomes compare with the same actions simulated
// from the real bodies (MatchOptions::measure), over the graph characters'
// look-ups.
struct PredictionStats {
    std::int64_t lookups = 0;        // look-ups measured (a state with edges found)
    double distanceSum = 0;          // D from the real state to the state found, summed (within the graph)
    std::int64_t within = 0;         // look-ups that fell within joinRadius of a state
    double drSum = 0, dThetaSum = 0; // |r - r_state| (m) and |theta_A - theta_A,state| + |theta_B - ...| (rad), summed
    // Every edge of the state found: a blow given (landed by the chooser) /
    // received predicted by the graph, happening in the simulation, both.
    std::int64_t edges = 0, givenPredicted = 0, givenReal = 0, givenBoth = 0;
    std::int64_t receivedPredicted = 0, receivedReal = 0, receivedBoth = 0;
    std::int64_t sameTarget = 0;     // the simulated next decision falls in the edge's target state
    // The edge the policy chose: the same counts.
    std::int64_t chosen = 0, chosenGivenPredicted = 0, chosenGivenReal = 0, chosenReceivedPredicted = 0, chosenReceivedReal = 0;
};

struct MatchStats {
    std::int64_t decisions = 0, lookups = 0, offGraph = 0, fallbacks = 0, commands = 0, commandsTaken = 0, forced = 0;
    double decideSeconds = 0;  // time spent deciding (look-ups and choices)
    double enemySeconds = 0;   // of which in the closest-enemy search
    sim::TreeDecisionStats tree;  // decisions by tree expansion (Mind::Tree)
    PredictionStats prediction;   // MatchOptions::measure
};

class Match {
public:
    Match(std::shared_ptr<const Rules> rules, std::shared_ptr<const Graph> graph, std::vector<FighterSpec> fighters,
          MatchOptions options);
    ~Match();
    Match(const Match&) = delete;
    Match& operator=(const Match&) = delete;

    int size() const;
    double time() const;
    bool finished() const { return time() >= options_.duration - 1e-9; }
    // The user's command for a character, carried out at its next decision,
    // or a later one within commandHold s when the next cannot.
    void command(int character, Command c);
    // Swaps a character's policy (a recomputed one); taken from its next decision on.
    void setPolicy(int character, std::shared_ptr<const Policy> policy);
    // Advances by one step (options.step), or to the end.
    void step();
    // Runs to the end, applying the timed commands; cancellable.
    Status run(const std::vector<TimedCommand>& commands = {}, const ProgressFn& progress = {});
    const sim::Scene& scene() const;
    const MatchStats& stats() const;
    // Unblocked blows landed by each character.
    std::vector<int> landed() const;
    // The opponent a character fights now (-1: none).
    int opponent(int character) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    MatchOptions options_;
};

// Start placements: a duel face to face `distance` m apart, or two teams of
// n (total) in facing lines. Jitter (seeded): +-jitter m and degrees/20.
std::vector<sim::RootXf> duelStarts(double distance, std::uint64_t seed, double jitter);
std::vector<sim::RootXf> teamStarts(int n, std::uint64_t seed, double jitter);

}  // namespace fray::igraph
