#pragma once
// Import through Assimp (FBX, glTF/GLB, DAE, BVH, ...). Lives in the fray_io
// library, not fray_core, so the motion core stays free of third-party loaders.
#include <filesystem>
#include <string>

#include "fray/core/motion.h"
#include "fray/core/result.h"

namespace fray {

struct AssimpImportOptions {
    std::string animation;      // animation name; empty = the first one
    std::string skeletonRoot;   // node name of the skeleton root; empty = detect
    double fps = 0.0;           // sampling rate; 0 = from the animation's keys (fallback 30)
};

// Converts the chosen skeleton and animation to a Motion in file units/axes
// (Assimp's own unit conversion is not applied; normalise afterwards).
Result<Motion> importWithAssimp(const std::filesystem::path& path, const AssimpImportOptions& options = {});

}  // namespace fray
