#pragma once
// The action categories of annotations and a project's action catalogue:
// what a scene spec can be read against without building the action library
// (no motions loaded). The editor checks a setup's characters (presets,
// weights, actions, takes) with it as they are edited. Plain C++20.
#include <cstdint>
#include <string>
#include <vector>

#include "fray/prep/project.h"
#include "fray/sim/action_library.h"

namespace fray::sim {

// The ActionFlag bits of an action with these annotations (SPEC 1.4
// vocabulary: punch, kick, tackle attack; block, avoid, dodge defend; pushed,
// falling are reactions; ...). buildActionLibrary uses the same mapping.
std::uint32_t actionFlags(const std::vector<std::string>& annotations);

// Every action of the project (motion by motion, project order) with its
// motion id, name, annotations and flags; no tracks (ActionLibrary::catalogue).
ActionLibrary projectCatalogue(const prep::Project& project);

}  // namespace fray::sim
