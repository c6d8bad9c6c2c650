#pragma once
// One entry point for loading any supported capture file: BVH through our own
// reader, everything else through Assimp; then normalised to metres and Y-up.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "fray/core/motion.h"
#include "fray/core/normalize.h"
#include "fray/core/result.h"

namespace fray {

struct LoadOptions {
    NormalizeOptions normalize;
    bool doNormalize = true;
    std::string animation;  // for multi-animation files (Assimp path)
    bool forceAssimp = false;
};

Result<Motion> loadMotion(const std::filesystem::path& path, const LoadOptions& options = {});
// Every skeleton of a file with several characters (fray::importAllWithAssimp;
// a BVH file has one), each normalised as loadMotion does.
Result<std::vector<Motion>> loadMotions(const std::filesystem::path& path, const LoadOptions& options = {});

}  // namespace fray
