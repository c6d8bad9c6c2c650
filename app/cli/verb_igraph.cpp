// Interaction Graph verbs (SPEC 3): igraph build | stats | policy | play | table | bench.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <thread>

#include <nlohmann/json.hpp>

#include "fray/core/atomic_file.h"
#include "fray/igraph/carry.h"
#include "fray/igraph/igraph.h"
#include "fray/igraph/runtime.h"
#include "fray/igraph/table.h"
#include "fray/sim/geometry.h"
#include "fray/sim/spec.h"
#include "cli_session.h"
#include "verbs.h"

namespace fray::cli {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Peak resident memory of this process so far (MiB).
double peakMiB() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return static_cast<double>(u.ru_maxrss) / 1024.0;
}

// The graph of a project lives beside it: demo.frayproj -> demo.frayproj.igraph.
fs::path defaultGraphFile(const std::string& project) { return fs::path(project + ".igraph"); }
// What the build measured (time, memory): beside the graph, as the graph's
// bytes depend on the data and seed alone.
fs::path buildReportFile(const fs::path& graph) { return fs::path(graph.string() + ".build.json"); }

// The carry graph of a project (two carriers of a box) lives beside it too.
fs::path defaultCarryGraphFile(const std::string& project) { return fs::path(project + ".carry.igraph"); }
bool hasMagic(std::string_view bytes, std::string_view magic) { return bytes.size() >= magic.size() && bytes.substr(0, magic.size()) == magic; }

// A carry graph file may only replace a carry graph file.
Status checkCarryGraphOutput(const fs::path& out) {
    std::error_code ec;
    if (!fs::exists(out, ec)) return {};
    auto head = readWholeFile(out, "the output file");
    if (!head) return head.error();
    if (!hasMagic(*head, igraph::kCarryGraphMagic)) return makeError(out.string() + ": exists and is not a carry graph file: not overwriting it");
    return {};
}

// Reads a carry graph file for the project's library, with the time it took.
Result<igraph::CarryGraph> loadCarry(const fs::path& file, const sim::ActionLibrary& lib, double& seconds) {
    const auto t0 = Clock::now();
    auto g = igraph::loadCarryGraph(file, lib);
    seconds = since(t0);
    return g;
}

// A graph file may only replace a graph file.
Status checkGraphOutput(const fs::path& out) {
    std::error_code ec;
    if (!fs::exists(out, ec)) return {};
    auto head = readWholeFile(out, "the output file");
    if (!head) return head.error();
    if (head->size() < 8 || std::string_view(head->data(), 8) != igraph::kGraphMagic) {
        return makeError(out.string() + ": exists and is not an interaction graph file: not overwriting it");
    }
    return {};
}

struct Loaded {
    std::unique_ptr<SimSession> session;
    std::shared_ptr<const igraph::Rules> rules;
    std::shared_ptr<const igraph::Graph> graph;
};

Result<Loaded> openGraph(const std::string& project, const std::string& graphFile, bool quiet) {
    Loaded l;
    auto ss = openSimSession(project, stderrProgress(quiet));
    if (!ss) return ss.error();
    l.session = std::move(*ss);
    auto rules = igraph::Rules::make(l.session->library);
    if (!rules) return makeError(project + ": " + rules.error().message);
    l.rules = *rules;
    auto g = igraph::loadGraph(graphFile.empty() ? defaultGraphFile(project) : fs::path(graphFile), *l.rules);
    if (!g) return g.error();
    l.graph = std::make_shared<const igraph::Graph>(std::move(*g));
    return l;
}

Result<igraph::RewardWeights> weightsFor(const std::string& preset, const std::vector<std::string>& edits) {
    auto w = igraph::stylePreset(preset);
    if (!w) return w.error();
    for (const auto& e : edits) {
        if (auto st = igraph::applyRewardEdit(*w, e); !st) return st.error();
    }
    return w;
}

// ---- build ----------------------------------------------------------------------------
struct BuildArgs {
    std::string project, out, kind = "duel";
    std::int64_t maxStates = -1;  // the kind's default: 80,000 (duel), 20,000 (carry)
    std::uint64_t seed = 1;
    double fraction = 0.2;
    bool quiet = false;
};

// igraph build --kind carry: the pair's graph (docs/IGRAPH.md, "Carry graph file").
void runCarryBuild(const BuildArgs& a) {
    const fs::path out = a.out.empty() ? defaultCarryGraphFile(a.project) : fs::path(a.out);
    if (auto st = checkCarryGraphOutput(out); !st) return fail(st.error().message);
    const auto progress = stderrProgress(a.quiet);
    auto ss = openSimSession(a.project, progress);
    if (!ss) return fail(ss.error().message);
    igraph::CarryOptions o;
    o.seed = a.seed;
    if (a.maxStates > 0) o.maxSamples = a.maxStates;
    o.expandFraction = a.fraction;
    const auto t0 = Clock::now();
    auto g = igraph::buildCarryGraph((*ss)->library, o, progress);
    if (!g) return fail(a.project + ": " + g.error().message);
    const double seconds = since(t0);
    if (auto st = igraph::saveCarryGraph(*g, out); !st) return fail(st.error().message);
    nlohmann::ordered_json report;
    report["build_seconds"] = seconds;
    report["peak_mib"] = peakMiB();
    report["threads"] = std::thread::hardware_concurrency();
    if (auto st = writeFileAtomically(buildReportFile(out), report.dump(2) + "\n"); !st) return fail(st.error().message);
    std::printf("%s: carry graph, %zu states, %zu edges, %.1f MiB in memory, %lld samples in %lld rounds; %.1f s, peak %.0f MiB\n",
                out.string().c_str(), g->states.size(), g->edges.size(), static_cast<double>(g->memoryBytes()) / (1024.0 * 1024.0),
                static_cast<long long>(g->samples), static_cast<long long>(g->rounds), seconds, peakMiB());
}

void runBuild(const BuildArgs& a) {
    if (a.kind == "carry") return runCarryBuild(a);
    if (a.kind != "duel") return fail("--kind: '" + a.kind + "' is not duel or carry");
    const fs::path out = a.out.empty() ? defaultGraphFile(a.project) : fs::path(a.out);
    if (auto st = checkGraphOutput(out); !st) return fail(st.error().message);
    const auto progress = stderrProgress(a.quiet);
    auto ss = openSimSession(a.project, progress);
    if (!ss) return fail(ss.error().message);
    auto rules = igraph::Rules::make((*ss)->library);
    if (!rules) return fail(a.project + ": " + rules.error().message);
    igraph::BuildOptions o;
    o.seed = a.seed;
    if (a.maxStates > 0) o.maxSamples = a.maxStates;
    o.expandFraction = a.fraction;
    const auto t0 = Clock::now();
    auto g = igraph::buildGraph(**rules, o, progress);
    if (!g) return fail(a.project + ": " + g.error().message);
    const double seconds = since(t0);
    if (auto st = igraph::saveGraph(*g, out); !st) return fail(st.error().message);
    nlohmann::ordered_json report;
    report["build_seconds"] = seconds;
    report["peak_mib"] = peakMiB();
    report["threads"] = std::thread::hardware_concurrency();
    if (auto st = writeFileAtomically(buildReportFile(out), report.dump(2) + "\n"); !st) return fail(st.error().message);
    std::printf("%s: %zu states, %zu edges, %.1f MiB in memory, %lld samples in %lld rounds, coverage %.1f %% of %lld tree-expansion states; "
                "%.1f s, peak %.0f MiB\n",
                out.string().c_str(), g->stateCount(), g->edgeCount(), static_cast<double>(g->memoryBytes()) / (1024.0 * 1024.0),
                static_cast<long long>(g->stats.samples), static_cast<long long>(g->stats.rounds), 100.0 * g->stats.coverage,
                static_cast<long long>(g->stats.coverageVisited), seconds, peakMiB());
}

// ---- stats ------------------------------------------------------------------------------
struct StatsArgs {
    std::string graph;
    bool json = false;
};

// The build report beside a graph file: seconds and peak MiB (< 0: unknown).
std::pair<double, double> buildReport(const std::string& graph) {
    double seconds = -1, peak = -1;
    if (auto r = readWholeFile(buildReportFile(graph), "the build report")) {
        const auto j = nlohmann::json::parse(*r, nullptr, false);
        if (j.is_object() && j.contains("build_seconds") && j["build_seconds"].is_number()) seconds = j["build_seconds"].get<double>();
        if (j.is_object() && j.contains("peak_mib") && j["peak_mib"].is_number()) peak = j["peak_mib"].get<double>();
    }
    return {seconds, peak};
}

void runCarryStats(const StatsArgs& a, const std::string& bytes) {
    const auto t0 = Clock::now();
    auto g = igraph::readCarryGraphUnbound(bytes, a.graph);
    const double readSeconds = since(t0);
    if (!g) return fail(g.error().message);
    const auto [buildSeconds, buildPeak] = buildReport(a.graph);
    std::size_t withEdges = 0;
    for (std::size_t i = 0; i < g->states.size(); ++i) withEdges += g->firstEdge[i + 1] > g->firstEdge[i] ? 1 : 0;
    if (a.json) {
        nlohmann::ordered_json j;
        j["kind"] = "carry";
        j["states"] = g->states.size();
        j["edges"] = g->edges.size();
        j["states_with_edges"] = withEdges;
        j["memory_bytes"] = g->memoryBytes();
        j["file_bytes"] = bytes.size();
        j["samples"] = g->samples;
        j["rounds"] = g->rounds;
        j["actions"] = g->actions.size();
        j["box_length"] = g->options.boxLength;
        j["seed"] = g->options.seed;
        j["read_seconds"] = readSeconds;
        j["build_seconds"] = buildSeconds >= 0 ? nlohmann::ordered_json(buildSeconds) : nlohmann::ordered_json(nullptr);
        j["build_peak_mib"] = buildPeak >= 0 ? nlohmann::ordered_json(buildPeak) : nlohmann::ordered_json(nullptr);
        std::printf("%s\n", j.dump(2).c_str());
        return;
    }
    std::printf("%s: carry graph (two carriers of a %.2f m box, %zu carry-end actions)\n  states %zu (%zu with edges), edges %zu (%.1f per state)\n"
                "  memory %.1f MiB, file %.1f MiB (read in %.3f s)\n",
                a.graph.c_str(), g->options.boxLength, g->actions.size(), g->states.size(), withEdges, g->edges.size(),
                g->states.empty() ? 0.0 : static_cast<double>(g->edges.size()) / static_cast<double>(g->states.size()),
                static_cast<double>(g->memoryBytes()) / (1024.0 * 1024.0), static_cast<double>(bytes.size()) / (1024.0 * 1024.0), readSeconds);
    std::printf("  sampling: %lld samples in %lld rounds (seed %llu)\n", static_cast<long long>(g->samples), static_cast<long long>(g->rounds),
                static_cast<unsigned long long>(g->options.seed));
    if (buildSeconds >= 0) std::printf("  build: %.1f s, peak %.0f MiB\n", buildSeconds, buildPeak);
    else std::printf("  build: time unknown (no %s)\n", buildReportFile(a.graph).string().c_str());
}

void runStats(const StatsArgs& a) {
    auto bytes = readWholeFile(a.graph, "the interaction graph");
    if (!bytes) return fail(bytes.error().message);
    if (hasMagic(*bytes, igraph::kCarryGraphMagic)) return runCarryStats(a, *bytes);
    auto g = igraph::readGraphUnbound(*bytes, a.graph);
    if (!g) return fail(g.error().message);
    double buildSeconds = -1, buildPeak = -1;
    if (auto r = readWholeFile(buildReportFile(a.graph), "the build report")) {
        const auto j = nlohmann::json::parse(*r, nullptr, false);
        if (j.is_object() && j.contains("build_seconds") && j["build_seconds"].is_number()) buildSeconds = j["build_seconds"].get<double>();
        if (j.is_object() && j.contains("peak_mib") && j["peak_mib"].is_number()) buildPeak = j["peak_mib"].get<double>();
    }
    std::size_t withEdges = 0;
    for (std::size_t i = 0; i < g->stateCount(); ++i) withEdges += g->firstEdge[i + 1] > g->firstEdge[i] ? 1 : 0;
    if (a.json) {
        nlohmann::ordered_json j;
        j["states"] = g->stateCount();
        j["edges"] = g->edgeCount();
        j["states_with_edges"] = withEdges;
        j["memory_bytes"] = g->memoryBytes();
        j["file_bytes"] = bytes->size();
        j["samples"] = g->stats.samples;
        j["rounds"] = g->stats.rounds;
        j["coverage"] = g->stats.coverage;
        j["coverage_visited"] = g->stats.coverageVisited;
        j["seed"] = g->options.seed;
        j["build_seconds"] = buildSeconds >= 0 ? nlohmann::ordered_json(buildSeconds) : nlohmann::ordered_json(nullptr);
        j["build_peak_mib"] = buildPeak >= 0 ? nlohmann::ordered_json(buildPeak) : nlohmann::ordered_json(nullptr);
        std::printf("%s\n", j.dump(2).c_str());
        return;
    }
    std::printf("%s\n  states %zu (%zu with edges), edges %zu (%.1f per state)\n  memory %.1f MiB, file %.1f MiB\n",
                a.graph.c_str(), g->stateCount(), withEdges, g->edgeCount(),
                g->stateCount() ? static_cast<double>(g->edgeCount()) / static_cast<double>(g->stateCount()) : 0.0,
                static_cast<double>(g->memoryBytes()) / (1024.0 * 1024.0), static_cast<double>(bytes->size()) / (1024.0 * 1024.0));
    std::printf("  sampling: %lld samples in %lld rounds (seed %llu)\n", static_cast<long long>(g->stats.samples),
                static_cast<long long>(g->stats.rounds), static_cast<unsigned long long>(g->options.seed));
    if (g->stats.coverage >= 0) {
        std::printf("  coverage: %.1f %% of %lld states visited by tree expansion to depth %d\n", 100.0 * g->stats.coverage,
                    static_cast<long long>(g->stats.coverageVisited), g->options.coverageDepth);
    }
    if (buildSeconds >= 0) std::printf("  build: %.1f s, peak %.0f MiB\n", buildSeconds, buildPeak);
    else std::printf("  build: time unknown (no %s)\n", buildReportFile(a.graph).string().c_str());
}

// ---- policy -------------------------------------------------------------------------------
struct PolicyArgs {
    std::string graph, preset = "general";
    std::vector<std::string> set;
    int depth = 3;
    bool json = false;
};

// A carry graph: the eight direction policies (collaborative reward, --set: w_theta, w_d, w_v, speed, gamma).
void runCarryPolicy(const PolicyArgs& a, const std::string& bytes, bool presetGiven) {
    if (presetGiven) return fail("--preset: boxing styles are for a duel's graph; " + a.graph + " is a carry graph (--set w_v=... edits its reward)");
    igraph::CarryWeights w;
    for (const auto& e : a.set) {
        if (auto st = igraph::applyCarryEdit(w, e); !st) return fail("--set: " + st.error().message);
    }
    auto g = igraph::readCarryGraphUnbound(bytes, a.graph);
    if (!g) return fail(g.error().message);
    auto p = igraph::computeCarryPolicies(*g, w, a.depth);
    if (!p) return fail(p.error().message);
    std::size_t decided = 0;
    for (const auto& q : p->policies)
        for (auto e : q.best) decided += e >= 0 ? 1 : 0;
    if (a.json) {
        nlohmann::ordered_json j;
        j["kind"] = "carry";
        j["depth"] = a.depth;
        j["seconds"] = p->seconds;
        j["policies"] = p->policies.size();
        j["states_decided"] = decided;
        std::printf("%s\n", j.dump(2).c_str());
        return;
    }
    std::printf("%s: 8 carry policies depth %d over %zu states in %.3f s (w_theta %g, w_d %g, w_v %g, speed %g, gamma %g)\n", a.graph.c_str(),
                a.depth, g->states.size(), p->seconds, w.wTheta, w.wD, w.wV, w.speed, w.gamma);
}

void runPolicy(const PolicyArgs& a, bool presetGiven) {
    auto bytes = readWholeFile(a.graph, "the interaction graph");
    if (!bytes) return fail(bytes.error().message);
    if (hasMagic(*bytes, igraph::kCarryGraphMagic)) return runCarryPolicy(a, *bytes, presetGiven);
    auto w = weightsFor(a.preset, a.set);
    if (!w) return fail(w.error().message);
    // The edges' times come from the project's actions, which this verb does not read.
    if (w->tau > 0) return fail("--set tau: timing the edges needs the project's actions; igraph policy reads the graph alone (use igraph table PROJECT --set tau=...)");
    auto g = igraph::readGraphUnbound(*bytes, a.graph);
    if (!g) return fail(g.error().message);
    auto p = igraph::computePolicy(*g, *w, a.depth);
    if (!p) return fail(p.error().message);
    std::size_t decided = 0, attacks = 0;
    double mean = 0;
    for (std::size_t i = 0; i < g->stateCount(); ++i) {
        if (p->best[i] < 0) continue;
        ++decided;
        mean += p->value[i];
        const auto& e = g->edges[static_cast<std::size_t>(p->best[i])];
        attacks += e.given() > 0 ? 1 : 0;
    }
    if (decided) mean /= static_cast<double>(decided);
    if (a.json) {
        nlohmann::ordered_json j;
        j["preset"] = a.preset;
        j["depth"] = a.depth;
        j["seconds"] = p->seconds;
        j["states_decided"] = decided;
        j["mean_value"] = mean;
        j["states_choosing_a_landing_blow"] = attacks;
        std::printf("%s\n", j.dump(2).c_str());
        return;
    }
    std::printf("%s: policy %s depth %d over %zu states in %.3f s; mean value %.2f, %zu states choose a blow that lands\n",
                a.graph.c_str(), a.preset.c_str(), a.depth, decided, p->seconds, mean, attacks);
}

// ---- play -------------------------------------------------------------------------------
struct PlayArgs {
    std::string project, graph, kind = "duel", input, out, preset = "general", opponentPreset = "general", you = "graph", opponent = "graph";
    std::string path = "circle:3";           // --kind carry
    std::vector<std::string> carryEdits;     // --carry-set name=value
    int carryStates = 20000;
    bool carryStatesGiven = false;
    int characters = 2, depth = 3, opponentDepth = 3;
    double seconds = 20;
    std::uint64_t seed = 1;
    bool refine = false;
    bool quiet = false;
};

Result<igraph::Mind> mindOf(const std::string& s, const char* flag) {
    if (s == "graph") return igraph::Mind::Graph;
    if (s == "static") return igraph::Mind::Static;
    return makeError(std::string(flag) + ": '" + s + "' is not graph or static");
}

// --kind carry: two carriers of one long box following --path (SPEC 3.4-3.5, collaborative).
void runCarryPlay(const PlayArgs& a, const fs::path& outFile) {
    if (!a.input.empty()) return fail("--input: user commands steer a duel or team fight; two carriers follow --path");
    if (!(a.seconds > 0 && a.seconds <= sim::kMaxSceneSeconds)) return fail("--seconds must be in (0, 3600]");
    igraph::CarryWeights w;
    for (const auto& e : a.carryEdits) {
        if (auto st = igraph::applyCarryEdit(w, e); !st) return fail("--carry-set: " + st.error().message);
    }
    Result<igraph::CarryPath> path = makeError("");
    if (a.path.rfind("circle:", 0) == 0) {
        path = igraph::parseCarryPath(a.path);
    } else {
        auto text = readWholeFile(a.path, "the path file");
        if (!text) return fail(text.error().message);
        path = igraph::carryPathFromJson(*text, a.path);
    }
    if (!path) return fail("--path: " + path.error().message);
    const auto progress = stderrProgress(a.quiet);
    auto ss = openSimSession(a.project, progress);
    if (!ss) return fail(ss.error().message);
    const auto& lib = (*ss)->library;
    igraph::CarryOptions o;
    o.seed = a.seed;
    o.maxSamples = a.carryStates;
    // The carry graph: --graph G (refused when stale, foreign or damaged), else
    // PROJECT.carry.igraph when it is there and fits, else built in memory.
    Result<igraph::CarryGraph> g = makeError("");
    double loadSeconds = -1;
    const fs::path file = a.graph.empty() ? defaultCarryGraphFile(a.project) : fs::path(a.graph);
    std::error_code ec;
    if (!a.graph.empty()) {
        g = loadCarry(file, lib, loadSeconds);
        if (!g) return fail("--graph: " + g.error().message);
        if (a.carryStatesGiven && g->options.maxSamples != o.maxSamples)
            return fail("--carry-states " + std::to_string(a.carryStates) + ": " + file.string() + " was built with " +
                        std::to_string(g->options.maxSamples) + " (build it again with --max-states, or leave --carry-states out)");
    } else if (fs::exists(file, ec)) {
        g = loadCarry(file, lib, loadSeconds);
        if (!g) {
            std::fprintf(stderr, "fray-cli: %s; building the carry graph in memory\n", g.error().message.c_str());
        } else if (a.carryStatesGiven && g->options.maxSamples != o.maxSamples) {
            std::fprintf(stderr, "fray-cli: %s was built with %lld states at most, --carry-states asks %d: building the carry graph in memory\n",
                         file.string().c_str(), static_cast<long long>(g->options.maxSamples), a.carryStates);
            g = makeError("");
        }
    }
    if (!g) {
        loadSeconds = -1;
        g = igraph::buildCarryGraph(lib, o, progress);
        if (!g) return fail(a.project + ": " + g.error().message);
    }
    std::vector<igraph::CarryPolicy> policies;
    double policySeconds = 0;
    for (int k = 0; k < igraph::kCarryDirections; ++k) {
        auto p = igraph::computeCarryPolicy(*g, w, k, a.depth);
        if (!p) return fail(p.error().message);
        policySeconds += p->seconds;
        policies.push_back(std::move(*p));
    }
    nlohmann::ordered_json record;
    record["igraph"] = {{"kind", "carry"}, {"path", a.path}, {"seconds", a.seconds}, {"seed", a.seed}, {"depth", a.depth},
                        {"w_theta", w.wTheta}, {"w_d", w.wD}, {"w_v", w.wV}, {"speed", w.speed}, {"gamma", w.gamma}};
    igraph::CarryRunOptions ro;
    ro.duration = a.seconds;
    ro.seed = a.seed;
    ro.record = record.dump();
    const auto t0 = Clock::now();
    auto run = igraph::runCarry(lib, *g, policies, *path, ro, progress);
    if (!run) return fail(run.error().message);
    sim::Scene& scene = run->scene;
    scene.project = sceneProjectReference(outFile, a.project);
    scene.stats.seconds = since(t0);
    scene.stats.decisions = run->stats.decisions;
    if (auto st = sim::saveScene(scene, lib, outFile); !st) return fail(st.error().message);
    const auto& st = run->stats;
    char how[1200];
    if (loadSeconds >= 0) std::snprintf(how, sizeof how, "read from %s in %.3f s", file.string().c_str(), loadSeconds);
    else std::snprintf(how, sizeof how, "built in %.2f s", g->seconds);
    std::printf("carry graph: %zu states, %zu edges, %.1f MiB, %lld samples in %lld rounds, %s; 8 policies (depth %d) in %.3f s\n",
                g->states.size(), g->edges.size(), static_cast<double>(g->memoryBytes()) / (1024.0 * 1024.0), static_cast<long long>(g->samples),
                static_cast<long long>(g->rounds), how, a.depth, policySeconds);
    std::printf("%s: 2 carriers, %.1f s, %lld decisions (%lld off the graph, %lld holds); path error mean %.3f m, max %.3f m; "
                "hand-to-hand distance within %.2f %% of the box (%.2f m)\n",
                a.out.c_str(), a.seconds, static_cast<long long>(st.decisions), static_cast<long long>(st.offGraph),
                static_cast<long long>(st.holds), st.pathErrorMean, st.pathErrorMax, 100.0 * st.gripErrorMax, o.boxLength);
}

void runPlay(const PlayArgs& a) {
    const fs::path outFile(a.out);
    if (Status st = checkSceneOutput(outFile); !st) return fail(st.error().message);
    if (a.kind == "carry") return runCarryPlay(a, outFile);
    if (a.kind != "duel" && a.kind != "teams") return fail("--kind: '" + a.kind + "' is not duel, teams or carry");
    if (!(a.seconds > 0 && a.seconds <= sim::kMaxSceneSeconds)) return fail("--seconds must be in (0, 3600]");
    if (a.characters < 2 || a.characters > 10000) return fail("--characters must be between 2 and 10000");
    auto you = mindOf(a.you, "--you");
    if (!you) return fail(you.error().message);
    auto them = mindOf(a.opponent, "--opponent");
    if (!them) return fail(them.error().message);
    std::vector<igraph::TimedCommand> commands;
    if (!a.input.empty()) {
        auto text = readWholeFile(a.input, "the command file");
        if (!text) return fail(text.error().message);
        auto c = igraph::parseCommands(*text, a.input);
        if (!c) return fail(c.error().message);
        commands = std::move(*c);
    }
    auto wy = weightsFor(a.preset, {});
    if (!wy) return fail("--preset: " + wy.error().message);
    auto wt = weightsFor(a.opponentPreset, {});
    if (!wt) return fail("--opponent-preset: " + wt.error().message);
    auto l = openGraph(a.project, a.graph, a.quiet);
    if (!l) return fail(l.error().message);
    auto py = igraph::computePolicy(*l->graph, *wy, a.depth);
    if (!py) return fail(py.error().message);
    auto pt = igraph::computePolicy(*l->graph, *wt, a.opponentDepth);
    if (!pt) return fail(pt.error().message);
    const auto policyYou = std::make_shared<const igraph::Policy>(std::move(*py));
    const auto policyThem = std::make_shared<const igraph::Policy>(std::move(*pt));
    const int n = a.kind == "duel" ? 2 : a.characters;
    const auto starts = a.kind == "duel" ? igraph::duelStarts(1.3, a.seed, 0.3) : igraph::teamStarts(n, a.seed, 0.2);
    std::vector<igraph::FighterSpec> fighters;
    for (int c = 0; c < n; ++c) {
        igraph::FighterSpec f;
        const bool mine = c % 2 == 0;
        f.side = c % 2;
        f.name = (mine ? "red " : "blue ") + std::to_string(c / 2 + 1);  // side 0 is drawn red, side 1 blue
        if (n == 2) f.name = mine ? "you" : "opponent";
        f.mind = c == 0 ? *you : (mine ? igraph::Mind::Graph : *them);
        f.policy = mine ? policyYou : policyThem;
        f.style = mine ? a.preset : a.opponentPreset;
        f.start = starts[static_cast<std::size_t>(c)];
        fighters.push_back(std::move(f));
    }
    nlohmann::ordered_json record;
    record["igraph"] = {{"kind", a.kind}, {"characters", n}, {"seconds", a.seconds}, {"seed", a.seed}, {"preset", a.preset},
                        {"depth", a.depth}, {"opponent", a.opponent}, {"opponent_preset", a.opponentPreset},
                        {"opponent_depth", a.opponentDepth}, {"you", a.you}, {"input", a.input}};
    if (a.refine) record["igraph"]["refine"] = true;
    igraph::MatchOptions mo;
    mo.refine = a.refine;
    mo.duration = a.seconds;
    mo.seed = a.seed;
    mo.record = record.dump();
    igraph::Match match(l->rules, l->graph, std::move(fighters), mo);
    const auto t0 = Clock::now();
    if (auto st = match.run(commands, stderrProgress(a.quiet)); !st) return fail(st.error().message);
    const double wall = since(t0);
    sim::Scene scene = match.scene();
    scene.project = sceneProjectReference(outFile, a.project);
    scene.stats.seconds = wall;
    scene.stats.decisions = match.stats().decisions;
    if (auto st = sim::saveScene(scene, l->session->library, outFile); !st) return fail(st.error().message);
    const auto landed = match.landed();
    int side0 = 0, side1 = 0;
    for (int c = 0; c < n; ++c) (c % 2 == 0 ? side0 : side1) += landed[static_cast<std::size_t>(c)];
    const auto& st = match.stats();
    std::printf("%s: %d characters, %.1f s, %lld decisions (%lld off the graph, %lld fallbacks), %zu blows, landed %d (red) vs %d (blue), "
                "%lld of %lld commands carried out; %.2f s wall clock\n",
                a.out.c_str(), n, a.seconds, static_cast<long long>(st.decisions), static_cast<long long>(st.offGraph),
                static_cast<long long>(st.fallbacks), scene.hits.size(), side0, side1, static_cast<long long>(st.commandsTaken),
                static_cast<long long>(st.commands), wall);
}

// ---- table (thesis table 5.1) ----------------------------------------------------------------
struct TableArgs {
    std::string project, graph, preset = "general", treePreset = "general-boxer";
    int matches = 20;
    int firstSeed = 1;
    double seconds = 30;
    std::vector<int> depths = {1, 3, 5};
    std::vector<int> treeDepths = {2, 3};
    std::vector<std::string> edits;
    bool refine = false;  // kept for the old command lines: refined look-ups are the default
    bool plain = false;   // the graph boxer by look-up alone (the style's gamma unless --set gamma=)
    bool measure = false;
    bool quiet = false;
};

// The table's graph boxer by default (docs/IGRAPH.md, table 5.1): refined
// look-ups with gamma 0.5, the settings under which deeper policies score
// higher in every column. --plain keeps the style's own gamma (1).
constexpr double kTableGamma = 0.5;

std::string cell(const igraph::SeriesResult& r) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.1f +- %.1f (%d..%d)", r.mean, r.standardError(), r.min, r.max);
    return buf;
}

std::string detail(const igraph::SeriesResult& r) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.1f / %.1f / %.1f %%", r.meanLanded(), r.meanReceived(), 100.0 * r.offGraphShare());
    return buf;
}

std::string predictionRow(const igraph::PredictionStats& p) {
    auto pct = [](std::int64_t x, std::int64_t n) { return n > 0 ? 100.0 * static_cast<double>(x) / static_cast<double>(n) : 0.0; };
    const double n = p.lookups > 0 ? static_cast<double>(p.lookups) : 1.0;
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "%lld | %.2f | %.2f | %.2f | %lld | %.1f / %.1f / %.1f %% | %.1f / %.1f / %.1f %% | %.1f %% | %.1f / %.1f %% | %.1f / %.1f %%",
                  static_cast<long long>(p.lookups), p.within > 0 ? p.distanceSum / static_cast<double>(p.within) : 0.0, p.drSum / n,
                  p.dThetaSum / n, static_cast<long long>(p.edges), pct(p.givenPredicted, p.edges), pct(p.givenReal, p.edges),
                  pct(p.givenBoth, p.edges), pct(p.receivedPredicted, p.edges), pct(p.receivedReal, p.edges), pct(p.receivedBoth, p.edges),
                  pct(p.sameTarget, p.edges), pct(p.chosenGivenPredicted, p.chosen), pct(p.chosenGivenReal, p.chosen),
                  pct(p.chosenReceivedPredicted, p.chosen), pct(p.chosenReceivedReal, p.chosen));
    return buf;
}

void runTable(const TableArgs& a) {
    if (a.matches < 1 || !(a.seconds > 0 && a.seconds <= 600)) return fail("--matches must be >= 1 and --seconds in (0, 600]");
    for (int d : a.treeDepths) {
        if (d < 1 || d > 8) return fail("--tree-depths: " + std::to_string(d) + " is not a depth from 1 to 8");
    }
    if (a.plain && a.refine) return fail("--plain and --refine exclude each other (refined look-ups are the default)");
    const bool refine = !a.plain;
    auto w = weightsFor(a.preset, a.edits);
    if (!w) return fail(w.error().message);
    const bool gammaSet = std::any_of(a.edits.begin(), a.edits.end(), [](const std::string& e) { return e.rfind("gamma=", 0) == 0; });
    if (refine && !gammaSet) w->gamma = kTableGamma;
    auto l = openGraph(a.project, a.graph, a.quiet);
    if (!l) return fail(l.error().message);
    const auto& project = l->session->session.project;
    auto presets = sim::projectPresets(project, a.project);
    if (!presets) return fail(presets.error().message);
    const auto preset = std::find_if(presets->begin(), presets->end(), [&](const sim::Preset& p) { return p.name == a.treePreset; });
    if (preset == presets->end()) return fail("--tree-preset: no planner preset named '" + a.treePreset + "'");
    std::vector<igraph::FighterSpec> opponents;
    opponents.push_back({"static target", 1, igraph::Mind::Static, nullptr, "static", {}, nullptr});
    for (int d : a.treeDepths) {
        auto tree = igraph::treeBoxer(*l->rules, project.combos, preset->weights, d);
        if (!tree) return fail(tree.error().message);
        opponents.push_back({"tree expansion depth " + std::to_string(d), 1, igraph::Mind::Tree, nullptr, a.treePreset, {}, *tree});
    }
    std::string header = "| graph depth | vs static-target boxer";
    for (int d : a.treeDepths) header += " | vs tree expansion depth " + std::to_string(d);
    header += " |\n|---";
    for (std::size_t k = 0; k < opponents.size(); ++k) header += "|---";
    header += "|\n";
    igraph::SeriesOptions so;
    so.matches = a.matches;
    so.firstSeed = a.firstSeed;
    so.seconds = a.seconds;
    so.style = a.preset;
    so.refine = refine;
    so.measure = a.measure;
    const auto t0 = Clock::now();
    std::vector<sim::TreeDecisionStats> treeStats(opponents.size());
    std::string scores = header, details, prediction, timing;
    std::vector<std::vector<int>> cells;  // per (depth, opponent), the seeds' scores
    std::shared_ptr<const igraph::Policy> previous;
    int previousDepth = 0;
    std::string changes;
    for (int depth : a.depths) {
        auto p = igraph::computePolicy(*l->graph, *w, depth);
        if (!p) return fail(p.error().message);
        const auto policy = std::make_shared<const igraph::Policy>(std::move(*p));
        if (previous) {
            // How much the deeper policy changes: states whose chosen action differs from the previous depth's.
            std::int64_t with = 0, changed = 0;
            for (std::size_t i = 0; i < policy->best.size(); ++i) {
                const auto b = policy->best[i], c = previous->best[i];
                if (b < 0 || c < 0) continue;
                ++with;
                changed += l->graph->edges[static_cast<std::size_t>(b)].action() != l->graph->edges[static_cast<std::size_t>(c)].action();
            }
            char buf[160];
            std::snprintf(buf, sizeof buf, "depth %d chooses another action than depth %d in %.1f %% of the states with edges\n", depth,
                          previousDepth, with > 0 ? 100.0 * static_cast<double>(changed) / static_cast<double>(with) : 0.0);
            changes += buf;
        }
        previous = policy, previousDepth = depth;
        if (depth == a.depths.front() && !l->graph->nearFirst.empty()) {
            std::size_t withNear = 0;
            for (std::size_t i = 0; i + 1 < l->graph->nearFirst.size(); ++i) withNear += l->graph->nearFirst[i + 1] > l->graph->nearFirst[i];
            char buf[160];
            std::snprintf(buf, sizeof buf, "%.1f %% of the states have neighbours within D %.1f (%.2f each)\n",
                          100.0 * static_cast<double>(withNear) / static_cast<double>(l->graph->stateCount()), l->graph->options.joinRadius,
                          static_cast<double>(l->graph->near.size()) / static_cast<double>(l->graph->stateCount()));
            changes += buf;
        }
        if (!l->graph->edgeFrames.empty()) {
            // The horizon in seconds: the policy's chosen edges' time to the next decision, and every edge's.
            double chosen = 0, all = 0;
            std::int64_t nc = 0;
            for (const auto b : policy->best) {
                if (b >= 0) chosen += l->graph->edgeSeconds(static_cast<std::size_t>(b)), ++nc;
            }
            for (std::size_t k = 0; k < l->graph->edges.size(); ++k) all += l->graph->edgeSeconds(k);
            all /= static_cast<double>(std::max<std::size_t>(1, l->graph->edges.size()));
            chosen /= static_cast<double>(std::max<std::int64_t>(1, nc));
            char buf[200];
            std::snprintf(buf, sizeof buf, "depth %d: %.2f s a decision on the chosen edges, %.2f s on every edge: a horizon of about %.1f s\n", depth,
                          chosen, all, depth * all);
            changes += buf;
        }
        std::string row = "| " + std::to_string(depth), more = "| " + std::to_string(depth);
        for (std::size_t k = 0; k < opponents.size(); ++k) {
            auto r = igraph::playSeries(l->rules, l->graph, policy, opponents[k], so, stderrProgress(a.quiet));
            if (!r) return fail(r.error().message);
            cells.push_back(r->scores);
            row += " | " + cell(*r);
            more += " | " + detail(*r);
            if (k == 0) {
                char buf[160];
                std::snprintf(buf, sizeof buf, "depth %d vs the static target: %.1f us a decision (%lld decisions; the target's are a scan of its Next set)\n",
                              depth, r->decisions > 0 ? 1e6 * r->decideSeconds / static_cast<double>(r->decisions) : 0.0,
                              static_cast<long long>(r->decisions));
                timing += buf;
            }
            if (a.measure) prediction += "| " + std::to_string(depth) + " | " + opponents[k].name + " | " + predictionRow(r->prediction) + " |\n";
            treeStats[k].decisions += r->tree.decisions, treeStats[k].leaves += r->tree.leaves, treeStats[k].shallower += r->tree.shallower,
                treeStats[k].fallbacks += r->tree.fallbacks;
        }
        scores += row + " |\n";
        details += more + " |\n";
    }
    std::printf("%s\nlanded / received / graph boxer's decisions off the graph, per match:\n\n%s%s\n", scores.c_str(), header.c_str(), details.c_str());
    std::printf("(cells: mean score +- standard error (min..max) over %d seeded matches (seeds %d-%d) of %.0f s; graph style %s, %s, gamma %g; "
                "tree preset %s; score = unblocked blows landed by the graph boxer minus the opponent's)\n",
                a.matches, a.firstSeed, a.firstSeed + a.matches - 1, a.seconds, a.preset.c_str(), refine ? "refined look-ups" : "plain look-ups",
                w->gamma, a.treePreset.c_str());
    // Each depth against the one before, seed by seed (the same seeds: paired).
    std::string paired;
    const std::size_t cols = opponents.size();
    for (std::size_t d = 1; d < a.depths.size(); ++d) {
        paired += "| " + std::to_string(a.depths[d]) + " - " + std::to_string(a.depths[d - 1]);
        for (std::size_t k = 0; k < cols; ++k) {
            const auto& hi = cells[d * cols + k];
            const auto& lo = cells[(d - 1) * cols + k];
            const auto n = static_cast<double>(hi.size());
            double mean = 0, ss = 0;
            for (std::size_t m = 0; m < hi.size(); ++m) mean += hi[m] - lo[m];
            mean /= n;
            for (std::size_t m = 0; m < hi.size(); ++m) ss += (hi[m] - lo[m] - mean) * (hi[m] - lo[m] - mean);
            char buf[64];
            std::snprintf(buf, sizeof buf, " | %+.2f +- %.2f", mean, hi.size() > 1 ? std::sqrt(ss / (n - 1) / n) : 0.0);
            paired += buf;
        }
        paired += " |\n";
    }
    if (!paired.empty()) {
        std::printf("\neach depth minus the one before, seed by seed (mean +- standard error of the paired differences):\n\n%s%s",
                    header.c_str(), paired.c_str());
    }
    if (a.measure) {
        std::printf("\nthe graph boxer's look-ups (--measure): D to the state found (within the graph) | |dr| m | |dtheta_A|+|dtheta_B| rad | "
                    "every edge of the state: blow given predicted / simulated / both, received predicted / simulated / both, "
                    "same target state | the chosen edge: given predicted / simulated, received predicted / simulated\n\n"
                    "| depth | opponent | look-ups | D | dr | dtheta | edges | given p/s/both | received p/s/both | same target | chosen given p/s | chosen received p/s |\n"
                    "|---|---|---|---|---|---|---|---|---|---|---|---|\n%s",
                    prediction.c_str());
    }
    for (std::size_t k = 1; k < opponents.size(); ++k) {
        const auto& t = treeStats[k];
        std::printf("%s: %lld decisions, %.0f leaves each, %lld at a lower depth (budget), %lld fallbacks\n", opponents[k].name.c_str(),
                    static_cast<long long>(t.decisions), t.decisions > 0 ? static_cast<double>(t.leaves) / static_cast<double>(t.decisions) : 0.0,
                    static_cast<long long>(t.shallower), static_cast<long long>(t.fallbacks));
    }
    std::printf("%s%stable: %.1f s wall clock\n", changes.c_str(), timing.c_str(), since(t0));
}

// ---- bench ----------------------------------------------------------------------------------
struct BenchArgs {
    std::string project, graph;
    int characters = 1000;
    double seconds = 10;
    bool quiet = false;
};

void runBench(const BenchArgs& a) {
    auto l = openGraph(a.project, a.graph, a.quiet);
    if (!l) return fail(l.error().message);
    const auto& g = *l->graph;
    // Policy recompute at depth 5 (best of 3).
    double best5 = 1e9;
    std::shared_ptr<const igraph::Policy> policy;
    for (int k = 0; k < 3; ++k) {
        auto p = igraph::computePolicy(g, igraph::RewardWeights{}, 5);
        if (!p) return fail(p.error().message);
        best5 = std::min(best5, p->seconds);
        policy = std::make_shared<const igraph::Policy>(std::move(*p));
    }
    std::printf("policy depth 5 over %zu states, %zu edges: %.3f s (best of 3)\n", g.stateCount(), g.edgeCount(), best5);
    // A decision: look-up of a state and its policy's choice, over the states of the graph.
    {
        const std::size_t n = std::min<std::size_t>(g.stateCount(), 200000);
        const auto t0 = Clock::now();
        std::int64_t sum = 0;
        for (std::size_t i = 0; i < n; ++i) {
            igraph::InteractionState s = g.states[(i * 7919) % g.stateCount()];
            s.r += 0.05;  // not exactly a state
            const int k = g.find(s, false);
            if (k >= 0 && policy->best[static_cast<std::size_t>(k)] >= 0) sum += g.edges[static_cast<std::size_t>(policy->best[static_cast<std::size_t>(k)])].action();
        }
        const double us = 1e6 * since(t0) / static_cast<double>(n);
        std::printf("decision (look-up + policy): %.2f us mean over %zu look-ups (checksum %lld)\n", us, n, static_cast<long long>(sum));
    }
    // Off the graph: the same states moved 0.6 m and 0.5 rad in each angle, a
    // decision as a match takes it (the state it falls in, else the nearest).
    {
        const std::size_t n = std::min<std::size_t>(g.stateCount(), 200000);
        std::vector<igraph::InteractionState> queries(n);
        for (std::size_t i = 0; i < n; ++i) {
            igraph::InteractionState s = g.states[(i * 7919) % g.stateCount()];
            s.r += 0.6, s.thetaA = sim::wrapAngle(s.thetaA + 0.5), s.thetaB = sim::wrapAngle(s.thetaB - 0.5);
            queries[i] = s;
        }
        std::int64_t sum = 0, off = 0;
        const auto t0 = Clock::now();
        for (const auto& s : queries) {
            int k = g.find(s, true);
            if (k < 0) ++off, k = g.find(s, false);
            if (k >= 0 && policy->best[static_cast<std::size_t>(k)] >= 0) sum += g.edges[static_cast<std::size_t>(policy->best[static_cast<std::size_t>(k)])].action();
        }
        const double us = 1e6 * since(t0) / static_cast<double>(n);
        std::printf("decision off the graph (states moved 0.6 m, 0.5 rad): %.2f us mean over %zu look-ups, %.1f %% off the graph (checksum %lld)\n", us,
                    n, 100.0 * static_cast<double>(off) / static_cast<double>(n), static_cast<long long>(sum));
    }
    // Many characters in two teams: decisions, blows and posing every frame at 60 fps.
    const auto starts = igraph::teamStarts(a.characters, 1, 0.2);
    std::vector<igraph::FighterSpec> fighters;
    for (int c = 0; c < a.characters; ++c) {
        fighters.push_back({"c" + std::to_string(c), c % 2, igraph::Mind::Graph, policy, "general", starts[static_cast<std::size_t>(c)]});
    }
    igraph::MatchOptions mo;
    mo.duration = a.seconds;
    igraph::Match match(l->rules, l->graph, std::move(fighters), mo);
    sim::ScenePoser poser(match.scene(), l->session->library);
    Pose pose;
    double stepS = 0, poseS = 0, worst = 0;
    int frames = 0;
    while (!match.finished()) {
        const auto t0 = Clock::now();
        match.step();
        const double s1 = since(t0);
        const auto t1 = Clock::now();
        for (int c = 0; c < a.characters; ++c) poser.pose(c, match.time(), pose);
        const double s2 = since(t1);
        stepS += s1, poseS += s2, worst = std::max(worst, s1 + s2);
        ++frames;
    }
    const auto landed = match.landed();
    int total = 0;
    for (int x : landed) total += x;
    std::printf("%d characters, two teams, %.0f s at 60 steps/s: step (decisions + blows) %.2f ms, posing %.2f ms per frame; "
                "%.0f fps mean, worst frame %.1f ms; %lld decisions (%lld off the graph; %.1f us each with the closest-enemy search), "
                "%d blows landed\n",
                a.characters, a.seconds, 1e3 * stepS / frames, 1e3 * poseS / frames, frames / (stepS + poseS), 1e3 * worst,
                static_cast<long long>(match.stats().decisions), static_cast<long long>(match.stats().offGraph),
                1e6 * match.stats().decideSeconds / static_cast<double>(std::max<std::int64_t>(1, match.stats().decisions)), total);
    std::printf("of a decision in the fight: %.2f us in the closest-enemy search\n",
                1e6 * match.stats().enemySeconds / static_cast<double>(std::max<std::int64_t>(1, match.stats().decisions)));
}

}  // namespace

void registerIgraph(CLI::App& app) {
    auto* ig = app.add_subcommand("igraph", "Interaction Graph (SPEC 3): build, stats, policy, play, table, bench");
    ig->require_subcommand(1);
    {
        auto a = std::make_shared<BuildArgs>();
        auto* cmd = ig->add_subcommand("build", "Sample, cluster and connect the interaction graph of a project");
        cmd->add_option("project", a->project, "Project file (*.frayproj)")->required();
        cmd->add_option("-o,--out", a->out, "Graph file (default: PROJECT.igraph)");
        cmd->add_option("--max-states", a->maxStates, "Archive size limit (samples one sigma apart: about the states; default 80,000, carry 20,000)")
            ->check(CLI::Range(16, 10000000));
        cmd->add_option("--kind", a->kind, "duel (the duel's and team fight's graph, PROJECT.igraph) | carry (two carriers of a box, PROJECT.carry.igraph)");
        cmd->add_option("--seed", a->seed, "Sampling seed");
        cmd->add_option("--expand", a->fraction, "Share of a node's children expanded (0, 1]")->check(CLI::Range(0.001, 1.0));
        cmd->add_flag("-q,--quiet", a->quiet, "No progress on stderr");
        cmd->callback([a] { runBuild(*a); });
    }
    {
        auto a = std::make_shared<StatsArgs>();
        auto* cmd = ig->add_subcommand("stats", "States, edges, memory, build time and coverage of a graph file");
        cmd->add_option("graph", a->graph, "Graph file")->required();
        cmd->add_flag("--json", a->json, "JSON output");
        cmd->callback([a] { runStats(*a); });
    }
    {
        auto a = std::make_shared<PolicyArgs>();
        auto* cmd = ig->add_subcommand("policy", "Compute a min-max policy over a graph and report it");
        cmd->add_option("graph", a->graph, "Graph file")->required();
        cmd->add_option("--preset", a->preset, "Boxing style: general | infighter | outboxer");
        cmd->add_option("--depth", a->depth, "Min-max depth")->check(CLI::Range(1, 64));
        cmd->add_option("--set", a->set, "Reward edits name=value (w_theta, w_d, d_p, w_a, w_r, gamma, tau, blur, opponent_mix, opponent)");
        cmd->add_flag("--json", a->json, "JSON output");
        auto* preset = cmd->get_option("--preset");
        cmd->callback([a, preset] { runPolicy(*a, preset->count() > 0); });
    }
    {
        auto a = std::make_shared<PlayArgs>();
        auto* cmd = ig->add_subcommand("play", "A graph-driven duel or team fight, written as a scene");
        cmd->add_option("project", a->project, "Project file")->required();
        cmd->add_option("--graph", a->graph, "Graph file (default: PROJECT.igraph; carry: PROJECT.carry.igraph when there, else built in memory)");
        cmd->add_option("--kind", a->kind, "duel | teams | carry");
        cmd->add_option("--path", a->path, "carry: the path, circle:R or a JSON file {version: 1, loop, points: [[x, z], ...]}");
        cmd->add_option("--carry-set", a->carryEdits, "carry: reward edits name=value (w_theta, w_d, w_v, speed, gamma)");
        auto* cs = cmd->add_option("--carry-states", a->carryStates, "carry: the archive size limit of a carry graph built in memory")->check(CLI::Range(16, 1000000));
        cmd->add_option("--characters", a->characters, "Characters in a team fight (two teams)");
        cmd->add_option("--seconds", a->seconds, "Duration");
        cmd->add_option("--seed", a->seed, "Seed of the start placements");
        cmd->add_option("--input", a->input, "Timed user commands (JSON) for the controlled character(s)");
        cmd->add_option("--preset", a->preset, "Style of character 0 and its team");
        cmd->add_option("--depth", a->depth, "Policy depth of character 0 and its team")->check(CLI::Range(1, 64));
        cmd->add_option("--you", a->you, "Character 0 between commands: graph | static");
        cmd->add_option("--opponent", a->opponent, "The other side: graph | static (a static target)");
        cmd->add_option("--opponent-preset", a->opponentPreset, "Style of the other side");
        cmd->add_option("--opponent-depth", a->opponentDepth, "Policy depth of the other side")->check(CLI::Range(1, 64));
        cmd->add_option("-o,--out", a->out, "Scene file to write (*.frayscene)")->required();
        cmd->add_flag("--refine", a->refine, "Graph characters re-simulate their state's edges from the real bodies (MatchOptions::refine)");
        cmd->add_flag("-q,--quiet", a->quiet, "No progress on stderr");
        cmd->callback([a, cs] {
            a->carryStatesGiven = cs->count() > 0;
            runPlay(*a);
        });
    }
    {
        auto a = std::make_shared<TableArgs>();
        auto* cmd = ig->add_subcommand("table", "Thesis table 5.1: graph depths against a static-target boxer and tree-expansion boxers");
        cmd->add_option("project", a->project, "Project file")->required();
        cmd->add_option("--graph", a->graph, "Graph file (default: PROJECT.igraph)");
        cmd->add_option("--matches", a->matches, "Seeded matches per depth");
        cmd->add_option("--first-seed", a->firstSeed, "Seed of the first match (seeds --first-seed.. --first-seed + --matches - 1)")->check(CLI::Range(1, 1000000000));
        cmd->add_option("--seconds", a->seconds, "Seconds per match");
        cmd->add_option("--depths", a->depths, "Graph depths");
        cmd->add_option("--preset", a->preset, "Style of the graph boxer");
        cmd->add_option("--tree-depths", a->treeDepths, "Depths of the tree-expansion opponents");
        cmd->add_option("--tree-preset", a->treePreset, "Planner preset of the tree-expansion opponents");
        cmd->add_flag("--refine", a->refine, "Refined look-ups (the default): the graph boxer re-simulates its state's edges from the real bodies (MatchOptions::refine)");
        cmd->add_flag("--plain", a->plain, "The graph boxer by look-up alone, with the style's gamma (default: refined look-ups, gamma 0.5)");
        cmd->add_flag("--measure", a->measure, "Measure the graph boxer's predictions against the real bodies (MatchOptions::measure)");
        cmd->add_option("--set", a->edits, "Reward weight edit of the graph boxer, name=value (w_theta, w_d, d_p, w_a, w_r, gamma, tau, blur, opponent_mix, opponent)");
        cmd->add_flag("-q,--quiet", a->quiet, "No progress on stderr");
        cmd->callback([a] { runTable(*a); });
    }
    {
        auto a = std::make_shared<BenchArgs>();
        auto* cmd = ig->add_subcommand("bench", "Policy recompute, decision time and a many-character team fight");
        cmd->add_option("project", a->project, "Project file")->required();
        cmd->add_option("--graph", a->graph, "Graph file (default: PROJECT.igraph)");
        cmd->add_option("--characters", a->characters, "Characters in the team fight")->check(CLI::Range(2, 100000));
        cmd->add_option("--seconds", a->seconds, "Seconds of the team fight");
        cmd->add_flag("-q,--quiet", a->quiet, "No progress on stderr");
        cmd->callback([a] { runBench(*a); });
    }
}

}  // namespace fray::cli
