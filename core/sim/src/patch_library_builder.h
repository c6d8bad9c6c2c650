#pragma once
// Write access to a PatchLibrary's data for the functions that build one
// (generation, hand-made patches, connection tables, the library file).
// Internal to fray_sim: nothing outside core/sim/src includes it.
#include "fray/sim/patches.h"

namespace fray::sim::detail {

struct PatchLibraryBuilder {
    static PatchLibrary::Data& data(PatchLibrary& lib) { return lib.d_; }
};

inline PatchLibrary::Data& built(PatchLibrary& lib) { return PatchLibraryBuilder::data(lib); }

}  // namespace fray::sim::detail
