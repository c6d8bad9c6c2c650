// A patch library less some of its patches (a scene setup's rejected ones):
// the links into the removed patches are dropped and the others renumbered,
// so the result is as complete as the library it came from.
#include <algorithm>
#include <string>

#include "fray/sim/patches.h"
#include "patch_library_builder.h"

namespace fray::sim {

Result<PatchLibrary> withoutPatches(const PatchLibrary& lib, std::vector<int> removed) {
    const int n = static_cast<int>(lib.patches().size());
    for (int id : removed) {
        if (id < 0 || id >= n) {
            return makeError("rejected patch " + std::to_string(id) + " is not in the patch library (it holds " + std::to_string(n) +
                             " patches; generated again since?)");
        }
    }
    if (removed.empty()) return lib;
    std::sort(removed.begin(), removed.end());
    std::vector<int> newIndex(static_cast<std::size_t>(n), -1);
    int next = 0;
    for (int i = 0; i < n; ++i) {
        if (!std::binary_search(removed.begin(), removed.end(), i)) newIndex[static_cast<std::size_t>(i)] = next++;
    }
    PatchLibrary out;
    PatchLibrary::Data& d = detail::built(out);
    d.patterns = lib.patterns();
    d.standardPoses = lib.standardPoses();
    d.stats = lib.stats();
    d.libraryKey = lib.libraryKey();
    const bool tables = lib.complete();
    for (int i = 0; i < n; ++i) {
        const auto ui = static_cast<std::size_t>(i);
        if (newIndex[ui] < 0) continue;
        d.patches.push_back(lib.patches()[ui]);
        if (!tables) continue;
        std::vector<TemporalLink> t;
        for (const auto& l : lib.temporal()[ui]) {
            if (const int to = newIndex[static_cast<std::size_t>(l.to)]; to >= 0) t.push_back({to, l.roles, l.shared});
        }
        d.temporal.push_back(std::move(t));
        std::vector<SpatialLink> sp;
        for (const auto& l : lib.spatial()[ui]) {
            if (const int to = newIndex[static_cast<std::size_t>(l.to)]; to >= 0) sp.push_back({to, l.sharedA, l.sharedB, l.offset, l.from});
        }
        d.spatial.push_back(std::move(sp));
        d.initialPose.push_back(lib.initialPose()[ui]);
        d.finalPose.push_back(lib.finalPose()[ui]);
    }
    return out;
}

}  // namespace fray::sim
