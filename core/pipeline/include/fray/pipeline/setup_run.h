#pragma once
// Running a scene setup (issue 23): plan a duel or chase by tree expansion,
// play an Interaction Graph kind (fray/pipeline/graph_setup.h), or compose
// the other kinds from the patch library less the setup's rejected patches. One path for `fray-cli simulate/compose --setup` and the
// editor's Generate, so both make the same scene bytes.
#include "fray/core/progress.h"
#include "fray/core/result.h"
#include "fray/pipeline/graph_setup.h"
#include "fray/pipeline/sim_session.h"
#include "fray/setup/scene_setup.h"
#include "fray/sim/compose.h"
#include "fray/sim/patches.h"
#include "fray/sim/planner.h"
#include "fray/sim/scene.h"

namespace fray::pipeline {

// Does running this setup read the project's patch library? (Tree kinds and
// the rat do not; a setup that cannot be converted says yes, so the run
// reports the setup's own error.)
bool setupNeedsPatches(const setup::SceneSetup& setup);

struct SetupRunStats {
    sim::PlannerStats planner;  // duel, chase
    sim::ComposeStats compose;  // the other kinds
    GraphRunStats graph;        // graph-duel, graph-teams, graph-carry
    sim::ReplanInfo replan;     // duel, chase planned with a PlanCache
};

// The scene of a setup. `patches` is the project's patch library when
// setupNeedsPatches (else it may be null). Errors name the setup and the
// JSON path of the bad parameter; cancel through `progress`. `plans` (duel,
// chase; may be null): the last run of the planner, resumed where an edit
// cannot reach (sim::PlanCache; the same bytes as without it), then updated.
Result<sim::Scene> runSetup(const SimSession& session, const setup::SceneSetup& setup, const sim::PatchLibrary* patches,
                            const ProgressFn& progress = {}, SetupRunStats* stats = nullptr, GraphCache* graphs = nullptr,
                            sim::PlanCache* plans = nullptr);

}  // namespace fray::pipeline
