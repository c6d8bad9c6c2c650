#include "fray/pipeline/graph_setup.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <nlohmann/json.hpp>

#include "fray/igraph/carry.h"
#include "fray/igraph/igraph.h"
#include "fray/igraph/runtime.h"
#include "fray/setup/convert.h"
#include "fray/sim/patches.h"

namespace fray::pipeline {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// A share [from, to] of a run's progress.
ProgressFn part(const ProgressFn& progress, double from, double to) {
    if (!progress) return {};
    return [=](double f, std::string_view stage) { return progress(from + (to - from) * std::clamp(f, 0.0, 1.0), stage); };
}

std::uint64_t mix(std::uint64_t h, std::uint64_t v) {
    h ^= v + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
    return h;
}

Error named(const setup::SceneSetup& s, const Error& e) {
    if (e.isCancelled()) return e;
    return Error{"setup '" + s.name + "': " + e.message, e.kind};
}

// The duel graph: the valid file beside the project, else one built in memory.
Result<std::shared_ptr<const igraph::Graph>> duelGraphFor(const SimSession& session, const igraph::Rules& rules,
                                                          const setup::GraphSetupParams& p, const ProgressFn& progress,
                                                          GraphRunStats& stats, GraphCache* cache) {
    const fs::path file = graphFileOf(session.session.file);
    std::error_code ec;
    if (fs::exists(file, ec)) {
        auto g = igraph::loadGraph(file, rules);
        if (g) {
            stats.graphSource = file.filename().string();
            return std::make_shared<const igraph::Graph>(std::move(*g));
        }
        stats.note = g.error().message + "; building the graph in memory instead (fray-cli igraph build rebuilds the file)";
    }
    igraph::BuildOptions o;  // as `igraph build --max-states N` (seed 1)
    o.maxSamples = p.graphStates;
    o.coverageDepth = 0;     // coverage is a measurement; the graph does not depend on it
    const std::uint64_t key = mix(mix(sim::libraryFingerprint(session.library), rules.key()), static_cast<std::uint64_t>(p.graphStates));
    if (cache) {
        std::lock_guard lock(cache->mutex);
        if (cache->duel && cache->duelKey == key) {
            stats.graphSource = "built in memory earlier (" + std::to_string(p.graphStates) + " states asked)";
            return cache->duel;
        }
    }
    const auto t0 = Clock::now();
    auto g = igraph::buildGraph(rules, o, progress);
    if (!g) return g.error();
    stats.buildSeconds = since(t0);
    stats.graphSource = "built in memory (" + std::to_string(p.graphStates) + " states asked, no valid " + file.filename().string() + ")";
    auto shared = std::make_shared<const igraph::Graph>(std::move(*g));
    if (cache) {
        std::lock_guard lock(cache->mutex);
        cache->duel = shared, cache->duelKey = key;
    }
    return shared;
}

// The carry graph: PROJECT.carry.igraph when it is there, valid for the
// project's library and built with the setup's number of states (as
// `igraph play --kind carry` takes it), else one built in memory.
Result<std::shared_ptr<const igraph::CarryGraph>> carryGraphFor(const SimSession& session, const setup::GraphSetupParams& p,
                                                                const ProgressFn& progress, GraphRunStats& stats, GraphCache* cache) {
    igraph::CarryOptions o;  // as `igraph play --kind carry --seed S --carry-states N`
    o.seed = p.seed;
    o.maxSamples = p.carryStates;
    const fs::path file = carryGraphFileOf(session.session.file);
    std::error_code ec;
    if (fs::exists(file, ec)) {
        auto g = igraph::loadCarryGraph(file, session.library);
        if (g && g->options.maxSamples == o.maxSamples) {
            stats.graphSource = file.filename().string();
            return std::make_shared<const igraph::CarryGraph>(std::move(*g));
        }
        stats.note = (g ? file.filename().string() + " was built with " + std::to_string(g->options.maxSamples) +
                              " states at most, the setup asks " + std::to_string(o.maxSamples)
                        : g.error().message) +
                     "; building the carry graph in memory instead (fray-cli igraph build --kind carry rebuilds the file)";
    }
    const std::uint64_t key = mix(mix(mix(sim::libraryFingerprint(session.library), 0xCA77ull), p.seed), static_cast<std::uint64_t>(p.carryStates));
    if (cache) {
        std::lock_guard lock(cache->mutex);
        if (cache->carry && cache->carryKey == key) {
            stats.graphSource = "carry graph built in memory earlier";
            return cache->carry;
        }
    }
    const auto t0 = Clock::now();
    auto g = igraph::buildCarryGraph(session.library, o, progress);
    if (!g) return g.error();
    stats.buildSeconds = since(t0);
    stats.graphSource = "carry graph built in memory (" + std::to_string(p.carryStates) + " states asked)";
    auto shared = std::make_shared<const igraph::CarryGraph>(std::move(*g));
    if (cache) {
        std::lock_guard lock(cache->mutex);
        cache->carry = shared, cache->carryKey = key;
    }
    return shared;
}

Result<sim::Scene> runCarrySetup(const SimSession& session, const setup::SceneSetup& s, const setup::GraphSetupParams& p,
                                 const ProgressFn& progress, GraphRunStats& stats, GraphCache* cache) {
    igraph::CarryWeights w;
    for (const auto& [name, value] : p.carryWeights) {
        if (name == "w_theta") w.wTheta = value;
        else if (name == "w_d") w.wD = value;
        else if (name == "w_v") w.wV = value;
        else if (name == "speed") w.speed = value;
        else if (name == "gamma") w.gamma = value;
    }
    if (auto st = igraph::validate(w); !st) return named(s, makeError("/weights: " + st.error().message));
    // The path: the box's trajectory; the spec text says it as igraph play's --path does.
    auto text = setup::setupSpecJson(s);
    if (!text) return text.error();
    const auto spec = nlohmann::ordered_json::parse(*text);
    std::string pathRecord;
    Result<igraph::CarryPath> path = makeError("no path");
    if (spec["path"].is_string()) {
        pathRecord = spec["path"].get<std::string>();  // circle:R, as `--path circle:R`
        path = igraph::parseCarryPath(pathRecord);
    } else {
        pathRecord = "setup '" + s.name + "'";
        igraph::CarryPath cp;
        cp.loop = spec["path"]["loop"].get<bool>();
        for (const auto& q : spec["path"]["points"]) cp.points.emplace_back(q[0].get<float>(), q[1].get<float>());
        path = std::move(cp);
    }
    if (!path) return named(s, path.error());
    auto g = carryGraphFor(session, p, part(progress, 0.0, 0.8), stats, cache);
    if (!g) return named(s, g.error());
    std::vector<igraph::CarryPolicy> policies;
    for (int k = 0; k < igraph::kCarryDirections; ++k) {
        if (!reportProgress(progress, 0.8 + 0.02 * k / igraph::kCarryDirections, "carry policies")) return cancelled();
        auto pol = igraph::computeCarryPolicy(**g, w, k, p.depth);
        if (!pol) return named(s, pol.error());
        policies.push_back(std::move(*pol));
    }
    nlohmann::ordered_json record;
    record["igraph"] = {{"kind", "carry"}, {"path", pathRecord}, {"seconds", p.duration}, {"seed", p.seed}, {"depth", p.depth},
                        {"w_theta", w.wTheta}, {"w_d", w.wD}, {"w_v", w.wV}, {"speed", w.speed}, {"gamma", w.gamma}};
    igraph::CarryRunOptions ro;
    ro.duration = p.duration;
    ro.seed = p.seed;
    ro.record = record.dump();
    auto run = igraph::runCarry(session.library, **g, policies, *path, ro, part(progress, 0.82, 1.0));
    if (!run) return named(s, run.error());
    stats.states = static_cast<std::int64_t>((*g)->states.size());
    stats.edges = static_cast<std::int64_t>((*g)->edges.size());
    stats.decisions = run->stats.decisions;
    stats.offGraph = run->stats.offGraph;
    stats.pathErrorMean = run->stats.pathErrorMean;
    stats.pathErrorMax = run->stats.pathErrorMax;
    stats.gripErrorMax = run->stats.gripErrorMax;
    sim::Scene scene = std::move(run->scene);
    scene.stats.decisions = run->stats.decisions;
    return scene;
}

}  // namespace

fs::path graphFileOf(const fs::path& project) { return fs::path(project.string() + ".igraph"); }
fs::path carryGraphFileOf(const fs::path& project) { return fs::path(project.string() + ".carry.igraph"); }

Result<sim::Scene> runGraphSetup(const SimSession& session, const setup::SceneSetup& s, const ProgressFn& progress, GraphRunStats* statsOut,
                                 GraphCache* cache) {
    auto p = setup::graphParams(s);
    if (!p) return p.error();
    GraphRunStats local;
    GraphRunStats& stats = statsOut ? *statsOut : local;
    if (s.kind == setup::SetupKind::GraphCarry) return runCarrySetup(session, s, *p, progress, stats, cache);

    // graph-duel, graph-teams: what `igraph play --kind duel|teams` does (app/cli/verb_igraph.cpp).
    auto wy = igraph::stylePreset(p->style);
    if (!wy) return named(s, makeError("/style: " + wy.error().message));
    auto wt = igraph::stylePreset(p->opponentStyle);
    if (!wt) return named(s, makeError("/opponent_style: " + wt.error().message));
    auto rules = igraph::Rules::make(session.library);
    if (!rules) return named(s, makeError(session.session.file.filename().string() + ": " + rules.error().message));
    auto g = duelGraphFor(session, **rules, *p, part(progress, 0.0, 0.75), stats, cache);
    if (!g) return named(s, g.error());
    const std::shared_ptr<const igraph::Graph> graph = *g;
    if (!reportProgress(progress, 0.76, "policies")) return cancelled();
    auto py = igraph::computePolicy(*graph, *wy, p->depth);
    if (!py) return named(s, py.error());
    auto pt = igraph::computePolicy(*graph, *wt, p->opponentDepth);
    if (!pt) return named(s, pt.error());
    const auto policyYou = std::make_shared<const igraph::Policy>(std::move(*py));
    const auto policyThem = std::make_shared<const igraph::Policy>(std::move(*pt));
    const bool duel = s.kind == setup::SetupKind::GraphDuel;
    const igraph::Mind you = p->you == "static" ? igraph::Mind::Static : igraph::Mind::Graph;
    const igraph::Mind them = p->opponent == "static" ? igraph::Mind::Static : igraph::Mind::Graph;
    // Placements: igraph play's, by the seed. Teams of other sizes take the
    // places of the larger team's lines (red 2k, blue 2k+1), so red = blue
    // (or red one more) is exactly `igraph play --characters red+blue`.
    std::vector<sim::RootXf> starts;
    std::vector<int> sides, ranks;
    if (duel) {
        starts = igraph::duelStarts(p->distance, p->seed, p->jitter);
        sides = {0, 1}, ranks = {0, 0};
    } else {
        const int per = std::max(p->red, p->blue);
        const auto all = igraph::teamStarts(2 * per, p->seed, p->jitter);
        for (int i = 0; i < 2 * per; ++i) {
            const int side = i % 2, k = i / 2;
            if (k >= (side == 0 ? p->red : p->blue)) continue;
            starts.push_back(all[static_cast<std::size_t>(i)]);
            sides.push_back(side), ranks.push_back(k);
        }
    }
    const int n = static_cast<int>(starts.size());
    std::vector<igraph::FighterSpec> fighters;
    for (int c = 0; c < n; ++c) {
        igraph::FighterSpec f;
        const bool mine = sides[static_cast<std::size_t>(c)] == 0;
        f.side = sides[static_cast<std::size_t>(c)];
        f.name = (mine ? "red " : "blue ") + std::to_string(ranks[static_cast<std::size_t>(c)] + 1);
        if (n == 2) f.name = mine ? "you" : "opponent";
        f.mind = c == 0 ? you : (mine ? igraph::Mind::Graph : them);
        f.policy = mine ? policyYou : policyThem;
        f.style = mine ? p->style : p->opponentStyle;
        f.start = starts[static_cast<std::size_t>(c)];
        fighters.push_back(std::move(f));
    }
    nlohmann::ordered_json record;
    record["igraph"] = {{"kind", duel ? "duel" : "teams"}, {"characters", n}, {"seconds", p->duration}, {"seed", p->seed},
                        {"preset", p->style}, {"depth", p->depth}, {"opponent", p->opponent}, {"opponent_preset", p->opponentStyle},
                        {"opponent_depth", p->opponentDepth}, {"you", p->you}, {"input", ""}};
    if (p->refine) record["igraph"]["refine"] = true;
    if (!duel && (p->red != (n + 1) / 2 || p->blue != n / 2)) record["igraph"]["teams"] = {p->red, p->blue};
    igraph::MatchOptions mo;
    mo.refine = p->refine;
    mo.duration = p->duration;
    mo.seed = p->seed;
    mo.record = record.dump();
    igraph::Match match(*rules, graph, std::move(fighters), mo);
    if (auto st = match.run({}, part(progress, 0.78, 1.0)); !st) return named(s, st.error());
    sim::Scene scene = match.scene();
    scene.stats.decisions = match.stats().decisions;
    const auto landed = match.landed();
    for (int c = 0; c < n; ++c) (sides[static_cast<std::size_t>(c)] == 0 ? stats.landedRed : stats.landedBlue) += landed[static_cast<std::size_t>(c)];
    stats.states = static_cast<std::int64_t>(graph->stateCount());
    stats.edges = static_cast<std::int64_t>(graph->edgeCount());
    stats.decisions = match.stats().decisions;
    stats.offGraph = match.stats().offGraph;
    return scene;
}

}  // namespace fray::pipeline
