// Table 5.1 series: seeded graph-boxer duels, in parallel over matches.
#include "fray/igraph/table.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>

#include <tbb/parallel_for.h>

namespace fray::igraph {

double SeriesResult::meanLanded() const {
    double s = 0;
    for (int x : landed) s += x;
    return landed.empty() ? 0.0 : s / static_cast<double>(landed.size());
}

double SeriesResult::meanReceived() const {
    double s = 0;
    for (int x : received) s += x;
    return received.empty() ? 0.0 : s / static_cast<double>(received.size());
}

double SeriesResult::standardError() const {
    const auto n = static_cast<double>(scores.size());
    if (scores.size() < 2) return 0.0;
    double ss = 0;
    for (int x : scores) ss += (x - mean) * (x - mean);
    return std::sqrt(ss / (n - 1) / n);
}

Result<SeriesResult> playSeries(std::shared_ptr<const Rules> rules, std::shared_ptr<const Graph> graph, std::shared_ptr<const Policy> policy,
                                const FighterSpec& opponent, const SeriesOptions& o, const ProgressFn& progress) {
    if (o.matches < 1) return makeError("a series needs at least one match");
    if (o.firstSeed < 1) return makeError("the first seed must be >= 1");
    if (!(o.seconds > 0 && o.seconds <= 600)) return makeError("match length must be in (0, 600] s");
    if (!policy) return makeError("the graph boxer has no policy");
    if (opponent.mind == Mind::Tree && !opponent.tree) return makeError("the tree-expansion opponent has no planner");
    if (opponent.mind == Mind::Graph && !opponent.policy) return makeError("the graph opponent has no policy");
    const auto n = static_cast<std::size_t>(o.matches);
    std::vector<int> landed(n), received(n);
    std::vector<MatchStats> stats(n);
    std::vector<std::string> errors(n);
    std::atomic<bool> stop{false};
    std::atomic<int> done{0};
    std::mutex reportMutex;
    auto play = [&](std::size_t m) {
        if (stop.load(std::memory_order_relaxed)) return;
        const auto seed = static_cast<std::uint64_t>(o.firstSeed) + static_cast<std::uint64_t>(m);
        const auto starts = duelStarts(o.distance, seed, o.jitter);
        std::vector<FighterSpec> f(2);
        f[0] = {"graph", 0, Mind::Graph, policy, o.style, starts[0], nullptr};
        f[1] = opponent;
        f[1].side = 1;
        f[1].start = starts[1];
        MatchOptions mo;
        mo.duration = o.seconds;
        mo.seed = seed;
        mo.refine = o.refine;
        mo.measure = o.measure;
        Match match(rules, graph, std::move(f), mo);
        if (auto st = match.run(); !st) {
            errors[m] = st.error().message;
            return;
        }
        const auto l = match.landed();
        landed[m] = l[0], received[m] = l[1];
        stats[m] = match.stats();
        const int k = ++done;
        std::lock_guard lock(reportMutex);
        if (!reportProgress(progress, static_cast<double>(k) / static_cast<double>(n), "matches")) stop = true;
    };
    if (o.parallel) {
        tbb::parallel_for(std::size_t{0}, n, play, tbb::simple_partitioner{});
    } else {
        for (std::size_t m = 0; m < n; ++m) play(m);
    }
    if (stop) return cancelled();
    for (const auto& e : errors) {
        if (!e.empty()) return makeError(e);
    }
    SeriesResult r;
    r.landed = landed, r.received = received;
    double sum = 0;
    for (std::size_t m = 0; m < n; ++m) {
        const int s = landed[m] - received[m];
        r.scores.push_back(s);
        sum += s;
        r.min = m == 0 ? s : std::min(r.min, s);
        r.max = m == 0 ? s : std::max(r.max, s);
        r.lookups += stats[m].lookups, r.offGraph += stats[m].offGraph, r.fallbacks += stats[m].fallbacks;
        const auto& t = stats[m].tree;
        r.tree.decisions += t.decisions, r.tree.nodes += t.nodes, r.tree.leaves += t.leaves, r.tree.shallower += t.shallower,
            r.tree.fallbacks += t.fallbacks;
        r.decisions += stats[m].decisions, r.decideSeconds += stats[m].decideSeconds;
        const auto& q = stats[m].prediction;
        auto& p = r.prediction;
        p.lookups += q.lookups, p.distanceSum += q.distanceSum, p.within += q.within, p.drSum += q.drSum, p.dThetaSum += q.dThetaSum;
        p.edges += q.edges, p.givenPredicted += q.givenPredicted, p.givenReal += q.givenReal, p.givenBoth += q.givenBoth;
        p.receivedPredicted += q.receivedPredicted, p.receivedReal += q.receivedReal, p.receivedBoth += q.receivedBoth;
        p.sameTarget += q.sameTarget, p.chosen += q.chosen, p.chosenGivenPredicted += q.chosenGivenPredicted;
        p.chosenGivenReal += q.chosenGivenReal, p.chosenReceivedPredicted += q.chosenReceivedPredicted, p.chosenReceivedReal += q.chosenReceivedReal;
    }
    r.mean = sum / static_cast<double>(n);
    return r;
}

Result<std::shared_ptr<const sim::TreeDecider>> treeBoxer(const Rules& rules, const prep::ComboTable& combos, const sim::StyleWeights& weights,
                                                          int depth, const sim::SimOptions& options) {
    const auto& lib = rules.library();
    std::vector<int> reactions;
    for (int a = 0; a < lib.size(); ++a) {
        if (lib.action(a).is(sim::kReactive)) reactions.push_back(a);
    }
    sim::CharacterSpec self;
    self.name = "tree expansion";
    self.side = 1;
    self.preset = "tree";
    self.weights = weights;
    self.depth = depth;
    self.allowed = rules.actions();
    self.reactions = reactions;
    sim::CharacterSpec model = self;
    model.name = "graph (as the tree sees it)";
    model.side = 0;
    auto d = sim::TreeDecider::make(lib, combos, std::move(self), std::move(model), options);
    if (!d) return d.error();
    return std::shared_ptr<const sim::TreeDecider>(std::move(*d));
}

}  // namespace fray::igraph
