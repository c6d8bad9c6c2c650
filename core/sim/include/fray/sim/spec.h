#pragma once
// Style presets (SPEC 2.3 table) and the JSON scene spec that drives
// `fray-cli simulate`. Presets are editable and live in the project's
// "planner_presets" section (a project preset of the same name overrides the
// built-in one). Spec errors name the file, the JSON path and the problem:
// "duel.json: /characters/0/actions/2: no action has annotation 'kik'".
#include <string>
#include <string_view>
#include <vector>

#include "fray/core/result.h"
#include "fray/prep/project.h"
#include "fray/sim/action_library.h"
#include "fray/sim/planner.h"

namespace fray::sim {

struct Preset {
    std::string name;
    std::string description;
    StyleWeights weights;
    friend bool operator==(const Preset&, const Preset&) = default;
};

// general-boxer, infighter, outboxer, chaser, runaway, and a "-path" variant
// of each (w_p = 10, w_q = 1) for path following.
const std::vector<Preset>& builtinPresets();

// Built-ins overridden/extended by the project's presets, in a stable order
// (built-ins first, then project-only ones by name).
Result<std::vector<Preset>> projectPresets(const prep::Project& project, std::string_view fileName);
// Adds or replaces a preset in the project (an undoable edit for the editor:
// it returns the previous value, if any).
std::optional<Preset> setProjectPreset(prep::Project& project, const Preset& preset);
// Removes a project preset (built-ins come back); returns it.
std::optional<Preset> removeProjectPreset(prep::Project& project, std::string_view name);

// Weights as JSON and back; unknown keys are errors ("w_tehta": typo).
std::string weightsToJson(const StyleWeights& w);
Result<StyleWeights> applyWeightsJson(StyleWeights base, std::string_view json, std::string_view what);
// One "key=value" edit (fray-cli presets set NAME key=value).
Status applyWeightEdit(StyleWeights& w, std::string_view edit);
// Names of the weight keys, for help and errors.
const std::vector<std::string>& weightKeys();

// Parses a scene spec against the library and presets.
Result<SceneSpec> parseSceneSpec(std::string_view text, std::string_view fileName, const ActionLibrary& lib,
                                 const std::vector<Preset>& presets);

}  // namespace fray::sim
