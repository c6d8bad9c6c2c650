#include "rig_setup.h"

#include <algorithm>

#include "fray/core/body_mesh.h"
#include "fray/io/rig_import.h"

namespace fray::cli {

Result<SkeletonRigs> loadRigs(const std::filesystem::path& file, const std::vector<const Skeleton*>& skeletons) {
    SkeletonRigs out;
    std::vector<std::uint64_t> done;
    for (const Skeleton* sk : skeletons) {
        const std::uint64_t fp = skeletonFingerprint(*sk);
        if (std::find(done.begin(), done.end(), fp) != done.end()) continue;
        done.push_back(fp);
        auto rig = loadRig(file, *sk);
        if (!rig) return rig.error();
        for (const std::string& w : rig->warnings) {
            const std::string line = file.string() + ": " + w;
            if (std::find(out.warnings.begin(), out.warnings.end(), line) == out.warnings.end()) out.warnings.push_back(line);
        }
        out.rigs.emplace_back(sk, std::move(*rig));
    }
    return out;
}

Status applyRigs(const SkeletonRigs& rigs, render::Renderer& renderer) {
    for (const auto& [sk, rig] : rigs.rigs)
        if (Status s = renderer.setRig(*sk, rig); !s) return s;
    return {};
}

}  // namespace fray::cli
