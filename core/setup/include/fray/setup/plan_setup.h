#pragma once
// Tree-expansion setups (duel, chase) checked against the project, and the
// action set a new duel starts with (docs/EDITOR.md "Setup box"). Plain
// C++20, no Qt (core/setup, target fray_setup).
#include <string>
#include <string_view>
#include <vector>

#include "fray/core/result.h"
#include "fray/prep/project.h"
#include "fray/setup/scene_setup.h"
#include "fray/sim/action_library.h"
#include "fray/sim/spec.h"

namespace fray::setup {

// What a character may choose: the spec's "motions" (takes) and "actions"
// ("@annotation" or action names).
struct ActionSet {
    std::vector<std::string> motions;
    std::vector<std::string> actions;
    friend bool operator==(const ActionSet&, const ActionSet&) = default;
};

// The action set of a new duel, derived from the project's data:
//   takes:   every take with an attack (an action annotated punch, kick or
//            tackle), and every take holding an action the combination table
//            names by name on the "mine" side (so its records can apply);
//   actions: "@word" for each vocabulary word (vocabulary order) that a
//            non-reactive action of those takes carries (reactions such as
//            pushed and falling are only forced by hits).
// Empty (both lists) when the project has no attack: the duel then allows
// every take's actions, as the planner does without the fields.
ActionSet defaultDuelActionSet(const prep::Project& project);

// Stores an action set on every character of a tree-expansion setup
// (nothing when it is empty).
Status applyActionSet(SceneSetup& setup, const ActionSet& set);

// The setup's spec read the way `fray-cli simulate --setup` reads it, against
// the project's actions (names, annotations, takes) and presets; the error
// names the setup and the field ("setup 'duel': /characters/0/weights/w_r:
// must be a finite number"). Not for the other kinds.
Status checkPlanSetup(const SceneSetup& setup, const prep::Project& project, std::string_view fileName);

// What checkPlanSetup reads a setup against: the project's presets and its
// action catalogue, built once so that an edit can check the setup before and
// after it against the same (the editor's Setup box does, docs/EDITOR.md).
struct PlanCheckContext {
    std::vector<sim::Preset> presets;
    sim::ActionLibrary catalogue;
};
Result<PlanCheckContext> planCheckContext(const prep::Project& project, std::string_view fileName);
Status checkPlanSetup(const SceneSetup& setup, const PlanCheckContext& context);

}  // namespace fray::setup
