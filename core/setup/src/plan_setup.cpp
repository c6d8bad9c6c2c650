#include "fray/setup/plan_setup.h"

#include <algorithm>
#include <set>

#include <nlohmann/json.hpp>

#include "fray/prep/json_reader.h"  // FRAY_TRY
#include "fray/setup/convert.h"
#include "fray/sim/action_catalogue.h"
#include "fray/sim/spec.h"

namespace fray::setup {

using json = nlohmann::ordered_json;

ActionSet defaultDuelActionSet(const prep::Project& project) {
    std::set<std::string> named;  // actions the combination table names on the "mine" side
    for (const auto& r : project.combos.records())
        if (!r.mine.empty() && r.mine[0] != '@') named.insert(r.mine);
    ActionSet out;
    std::set<std::string> words;
    for (const auto& m : project.motions) {
        bool attack = false, combo = false;
        for (const auto& a : m.actions.actions) {
            attack = attack || (sim::actionFlags(a.annotations) & sim::kAttack) != 0;
            combo = combo || (!a.name.empty() && named.contains(a.name));
        }
        if (!attack && !combo) continue;
        out.motions.push_back(m.id);
        for (const auto& a : m.actions.actions) {
            if (sim::actionFlags(a.annotations) & sim::kReactive) continue;
            words.insert(a.annotations.begin(), a.annotations.end());
        }
    }
    bool anyAttack = false;
    for (const auto& w : project.vocabulary) {
        if (!words.contains(w)) continue;
        out.actions.push_back("@" + w);
        anyAttack = anyAttack || (sim::actionFlags({w}) & sim::kAttack) != 0;
    }
    if (!anyAttack) return {};
    return out;
}

Status applyActionSet(SceneSetup& setup, const ActionSet& set) {
    if (set.motions.empty() && set.actions.empty()) return {};
    const auto n = characters(setup).size();
    for (std::size_t i = 0; i < n; ++i) {
        const std::string at = "/characters/" + std::to_string(i);
        if (auto st = setParameter(setup, at + "/motions", json(set.motions).dump()); !st) return st;
        if (auto st = setParameter(setup, at + "/actions", json(set.actions).dump()); !st) return st;
    }
    return {};
}

Result<PlanCheckContext> planCheckContext(const prep::Project& project, std::string_view fileName) {
    FRAY_TRY(presets, sim::projectPresets(project, fileName));
    return PlanCheckContext{std::move(presets), sim::projectCatalogue(project)};
}

Status checkPlanSetup(const SceneSetup& setup, const PlanCheckContext& context) {
    FRAY_TRY(spec, toSceneSpec(setup, context.catalogue, context.presets));
    (void)spec;
    return {};
}

Status checkPlanSetup(const SceneSetup& setup, const prep::Project& project, std::string_view fileName) {
    FRAY_TRY(context, planCheckContext(project, fileName));
    return checkPlanSetup(setup, context);
}

}  // namespace fray::setup
