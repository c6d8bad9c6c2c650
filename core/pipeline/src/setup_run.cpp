#include "fray/pipeline/setup_run.h"

#include "fray/setup/convert.h"
#include "fray/setup/graph_setup.h"
#include "fray/sim/planner.h"
#include "fray/sim/spec.h"

namespace fray::pipeline {

bool setupNeedsPatches(const setup::SceneSetup& s) {
    if (setup::isSimulateKind(s.kind)) return false;
    auto text = setup::setupSpecJson(s);
    return !text || sim::composeNeedsPatches(*text);
}

Result<sim::Scene> runSetup(const SimSession& session, const setup::SceneSetup& s, const sim::PatchLibrary* patches,
                            const ProgressFn& progress, SetupRunStats* stats, GraphCache* graphs, sim::PlanCache* plans) {
    const std::string who = "setup '" + s.name + "'";
    if (setup::isGraphKind(s.kind)) return runGraphSetup(session, s, progress, stats ? &stats->graph : nullptr, graphs);
    if (setup::isTreeExpansion(s.kind)) {
        auto presets = sim::projectPresets(session.session.project, session.session.file.string());
        if (!presets) return presets.error();
        auto spec = setup::toSceneSpec(s, session.library, *presets);
        if (!spec) return spec.error();
        sim::ReplanInfo replan;
        auto scene = plans ? sim::simulate(session.library, session.session.project.combos, *spec, *plans, progress, &replan)
                           : sim::simulate(session.library, session.session.project.combos, *spec, progress);
        if (!scene) return makeError(who + ": " + scene.error().message);
        if (stats) stats->replan = replan;
        if (stats) stats->planner = scene->stats;
        return scene;
    }
    const sim::PatchLibrary none;
    Result<sim::PatchLibrary> kept = none;
    if (setupNeedsPatches(s)) {
        if (!patches) return makeError(who + ": composing a " + std::string(setup::setupKindName(s.kind)) + " setup needs the patch library");
        kept = setup::withoutRejected(*patches, s.patches.rejected);
        if (!kept) return makeError(who + ": " + kept.error().message);
    }
    auto spec = setup::toComposeSpec(s, *kept);
    if (!spec) return spec.error();
    sim::ComposeStats local;
    auto scene = sim::compose(session.library, *kept, *spec, stats ? &stats->compose : &local, progress);
    if (!scene) return makeError(who + ": " + scene.error().message);
    return scene;
}

}  // namespace fray::pipeline
