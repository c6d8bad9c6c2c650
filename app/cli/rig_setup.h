#pragma once
// `--rig FILE` of fray-cli render and fray-play: the rig loaded once for each
// distinct skeleton on show (by content fingerprint), then handed to the
// renderer, which draws those characters with it instead of capsules.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "fray/core/result.h"
#include "fray/core/skeleton.h"
#include "fray/core/skinned_mesh.h"
#include "fray/render/renderer.h"

namespace fray::cli {

struct SkeletonRigs {
    std::vector<std::pair<const Skeleton*, SkinnedMesh>> rigs;  // one per distinct skeleton
    std::vector<std::string> warnings;                          // "<file>: <what>", each once
};

// Binds the rig file to every skeleton; the first that fails is the error
// (the file and what is missing: unreadable, no skinned mesh, unmatched bones...).
Result<SkeletonRigs> loadRigs(const std::filesystem::path& file, const std::vector<const Skeleton*>& skeletons);

Status applyRigs(const SkeletonRigs& rigs, render::Renderer& renderer);

}  // namespace fray::cli
