#pragma once
// The thesis' table 5.1 (SPEC 3, docs/IGRAPH.md): seeded duels of a graph
// boxer against an opponent (a static target, or a boxer planned by temporal
// tree expansion), scored by unblocked blows landed minus received. The
// matches of a series run in parallel (TBB) and each is deterministic for its
// seed, so a series gives the same numbers whatever the thread count.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "fray/core/progress.h"
#include "fray/core/result.h"
#include "fray/igraph/igraph.h"
#include "fray/igraph/runtime.h"
#include "fray/prep/combos.h"
#include "fray/sim/planner.h"
#include "fray/sim/tree_decider.h"

namespace fray::igraph {

struct SeriesOptions {
    int matches = 20;         // seeds firstSeed..firstSeed + matches - 1
    int firstSeed = 1;        // the first match's seed
    double seconds = 30;      // per match
    double distance = 1.3;    // m between the two at the start (duelStarts)
    double jitter = 0.3;      // duelStarts' jitter
    std::string style = "general";  // the graph boxer's style, for the scene record
    bool parallel = true;     // matches in parallel (results do not depend on it)
    bool refine = false;      // the graph boxer refines its look-ups (MatchOptions::refine)
    bool measure = false;     // the graph boxer's predictions are measured (MatchOptions::measure)
};

struct SeriesResult {
    std::vector<int> scores;  // per match (seed order): landed by the graph boxer minus landed by the opponent
    std::vector<int> landed, received;
    double mean = 0;
    int min = 0, max = 0;
    std::int64_t lookups = 0, offGraph = 0, fallbacks = 0;  // the graph boxer's decisions
    sim::TreeDecisionStats tree;                              // the opponent's, when it plans by tree expansion
    PredictionStats prediction;                               // SeriesOptions::measure
    std::int64_t decisions = 0;                               // both characters' decisions
    double decideSeconds = 0;                                 // their time (MatchStats::decideSeconds)
    double standardError() const;                             // of the mean score (sample standard deviation / sqrt(n))
    double meanLanded() const;
    double meanReceived() const;
    double offGraphShare() const { return lookups > 0 ? static_cast<double>(offGraph) / static_cast<double>(lookups) : 0.0; }
};

// The graph boxer (side 0, `policy`) against `opponent` (side 1; its name,
// mind, policy or tree decider are used, its start is the series'): one
// duel per seed. Cancellable through progress.
Result<SeriesResult> playSeries(std::shared_ptr<const Rules> rules, std::shared_ptr<const Graph> graph, std::shared_ptr<const Policy> policy,
                                const FighterSpec& opponent, const SeriesOptions& options, const ProgressFn& progress = {});

// A boxer planned by tree expansion at `depth` with `weights` over the
// graph's actions (Rules::actions) and every reaction of the library, which
// models its opponent with the same weights inside its tree.
Result<std::shared_ptr<const sim::TreeDecider>> treeBoxer(const Rules& rules, const prep::ComboTable& combos, const sim::StyleWeights& weights,
                                                          int depth, const sim::SimOptions& options = {});

}  // namespace fray::igraph
