#pragma once
// Running an Interaction Graph setup (graph-duel, graph-teams, graph-carry;
// fray/setup/graph_setup.h): the match or the carry run that `fray-cli
// igraph play` makes from the same parameters, so `simulate --setup`, the
// editor's Generate and `igraph play` write the same scene bytes.
//
// The duel's graph: the graph file beside the project (P.frayproj.igraph,
// as `igraph build` writes it) when it exists and is valid for the
// project's actions; otherwise built in memory from the project's data
// (`graph_states`, sampling seed 1, as `igraph build --max-states N`), with a
// note saying why. The carry graph is built in memory (see carryGraphFor in
// graph_setup.cpp: the one place a carry graph file would be loaded).
// Building is slow: progress and cancel through `progress`; a GraphCache
// keeps built graphs for the next run (the editor's re-plans).
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>

#include "fray/core/progress.h"
#include "fray/core/result.h"
#include "fray/pipeline/sim_session.h"
#include "fray/setup/graph_setup.h"
#include "fray/sim/scene.h"

namespace fray::igraph {
class Graph;
struct CarryGraph;
}  // namespace fray::igraph

namespace fray::pipeline {

// Graphs built in memory by earlier runs, reused while the library and the
// build parameters are the same. Thread-safe (one job at a time uses it).
struct GraphCache {
    std::mutex mutex;
    std::uint64_t duelKey = 0;
    std::shared_ptr<const igraph::Graph> duel;
    std::uint64_t carryKey = 0;
    std::shared_ptr<const igraph::CarryGraph> carry;
};

struct GraphRunStats {
    std::string graphSource;  // "P.frayproj.igraph" or "built in memory (...)"
    std::string note;         // why a graph file beside the project was not used ("" when none)
    double buildSeconds = 0;  // graph built here (0: read or cached)
    std::int64_t states = 0, edges = 0;
    std::int64_t decisions = 0, offGraph = 0;
    int landedRed = 0, landedBlue = 0;                          // duel, teams: unblocked blows of side 0 / side 1
    double pathErrorMean = 0, pathErrorMax = 0, gripErrorMax = 0;  // carry
};

// The graph file of a project: P.frayproj -> P.frayproj.igraph.
std::filesystem::path graphFileOf(const std::filesystem::path& project);
// PROJECT.carry.igraph: the carry graph `fray-cli igraph build --kind carry` writes.
std::filesystem::path carryGraphFileOf(const std::filesystem::path& project);

// The scene of a graph setup. `projectFile` locates the graph file (the
// session's project file when empty). Errors name the setup and the field.
Result<sim::Scene> runGraphSetup(const SimSession& session, const setup::SceneSetup& setup, const ProgressFn& progress = {},
                                 GraphRunStats* stats = nullptr, GraphCache* cache = nullptr);

}  // namespace fray::pipeline
