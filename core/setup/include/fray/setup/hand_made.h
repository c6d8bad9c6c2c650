#pragma once
// Hand-made Interaction Patches (issue 23, the patch browser): the user picks
// character 1's and character 2's actions from the library in turn, the patch
// engine plays them from an initial configuration (sim::addHandMadePatch:
// hits, reactions, the pattern's rules) and the patch joins the library as
// kept. The project stores each as its recipe in its "hand_made_patches"
// section: the PatternList's name, the initial configuration and the action
// labels per character; the editor adds them after the generated patches
// whenever it builds the library, so an undo or a regenerate never loses one.
// Plain C++20, no Qt (core/setup).
#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "fray/core/result.h"
#include "fray/prep/project.h"
#include "fray/sim/action_library.h"
#include "fray/sim/patches.h"
#include "fray/sim/patterns.h"

namespace fray::setup {

inline constexpr const char* kHandMadeSection = "hand_made_patches";

struct HandMadePatch {
    std::string pattern;                           // a PatternList of the project (or a default one)
    sim::PatchConfig initial;                      // r (m), theta1, theta2 (rad), delay (s)
    std::array<std::vector<std::string>, 2> actions;  // action labels (ActionInfo::label), in the order played
    friend bool operator==(const HandMadePatch&, const HandMadePatch&) = default;
};

// The project's recipes (absent section: none). Errors name the file and the JSON path.
Result<std::vector<HandMadePatch>> projectHandMadePatches(const prep::Project& project, std::string_view fileName);
// Writes them (none: the section is removed).
void setProjectHandMadePatches(prep::Project& project, const std::vector<HandMadePatch>& patches);
std::string handMadePatchesToJson(const std::vector<HandMadePatch>& patches);

// The PatternList a recipe names: the project's, else a default one.
Result<sim::PatternList> handMadePattern(const sim::PatternSet& set, const std::string& name);
// Plays a recipe through the patch engine and appends the patch to `out`.
// Errors name the recipe's pattern and the action or rule that failed.
Status buildHandMadePatch(const sim::ActionLibrary& lib, const sim::PatternSet& set, const HandMadePatch& recipe, sim::PatchLibrary& out);

}  // namespace fray::setup
