#pragma once
// Writes the demo library: one BVH and one ground-truth JSON per take.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "fray/core/result.h"
#include "fray/demo/demo_actor.h"

namespace fray::demo {

struct WrittenTake {
    std::string name;
    std::filesystem::path bvh;
    std::filesystem::path truth;
    int frames = 0;
    int actions = 0;
};

// Progress: (takes done, takes total, name of the take just written).
// Called after each take is written (done, total, the take), so callers can
// report on it without generating it again.
using ProgressFn = std::function<void(int, int, const Take&)>;

// Generates and writes every take of planLibrary(options) into outDir (created
// if missing). Files are written atomically (temporary + rename).
Result<std::vector<WrittenTake>> writeDemoLibrary(const std::filesystem::path& outDir, const LibraryOptions& options,
                                                  const ProgressFn& progress = {});

}  // namespace fray::demo
