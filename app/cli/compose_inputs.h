#pragma once
// What compose reads besides its spec, shared by compose and setup import:
// the project's patch library and a painted floor from a PNG.
#include <filesystem>
#include <string>

#include <glm/vec2.hpp>

#include "fray/core/result.h"
#include "fray/sim/action_library.h"
#include "fray/sim/patches.h"
#include "fray/sim/scene.h"

namespace fray::cli {

// PROJECT.patches unless `file` is given; an error names the file and how to make it.
Result<sim::PatchLibrary> openPatches(const std::string& project, const std::string& file, const sim::ActionLibrary& lib);
// A two-colour PNG: dark pixels painted, light or transparent ones not; errors name the file.
Result<sim::FloorBitmap> loadFloorBitmap(const std::filesystem::path& file, double metresPerPixel, glm::vec2 origin);

}  // namespace fray::cli
