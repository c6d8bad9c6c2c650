// libFuzzer target for the patch library file (docs/PATCHES.md, "Library
// file"). Each input is read twice: as it is (a damaged file must be refused
// by its checksum), and resealed: its library key set to this target's action
// library and its CRC-32 recomputed, so that mutations reach the patches and
// connection tables behind the checksum. Either must return an error, never
// crash, hang or leak; what loads must save, and load back to the same bytes.
// Seeds: files that `fray-cli patches generate` makes of a small demo
// library (.ci/run); any action index below kActions is valid here.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "fray/sim/patches.h"

namespace {

constexpr int kActions = 1024;  // more than the demo project has (633)
constexpr std::size_t kKeyAt = 16;  // magic (8), file version (4), link rule (4)

const fray::sim::ActionLibrary& library() {
    static const fray::sim::ActionLibrary lib = [] {
        const std::vector<std::string> vocabulary = {"punch", "idle", "pushed"};
        std::vector<fray::sim::LibraryAction> actions;
        for (int i = 0; i < kActions; ++i) {
            fray::sim::LibraryAction a;
            a.motionId = "take";
            a.name = "action" + std::to_string(i);
            a.annotations = {vocabulary[static_cast<std::size_t>(i % 3)]};
            a.flags = i % 3 == 0 ? fray::sim::kPunch : i % 3 == 1 ? fray::sim::kIdle : fray::sim::kPushed;
            a.firstFrame = 30 * i;
            a.lastFrame = 30 * i + 29;
            a.duration = 1.0;
            actions.push_back(a);
        }
        return fray::sim::ActionLibrary::catalogue(std::move(actions), vocabulary);
    }();
    return lib;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto& lib = library();
    fray::sim::PatchFileOptions refuse;
    refuse.staleTables = fray::sim::StaleTables::Refuse;  // rebuilding would trust the mutated patches' clips
    std::string bytes(reinterpret_cast<const char*>(data), size);
    (void)fray::sim::readPatchLibrary(bytes, "fuzz.patches", lib, refuse);
    if (bytes.size() < kKeyAt + 8 + 4) return 0;
    const std::uint64_t key = fray::sim::libraryFingerprint(lib);
    std::memcpy(bytes.data() + kKeyAt, &key, sizeof key);
    const std::uint32_t crc = fray::sim::patchFileChecksum(std::string_view(bytes).substr(0, bytes.size() - 4));
    std::memcpy(bytes.data() + bytes.size() - 4, &crc, sizeof crc);
    auto loaded = fray::sim::readPatchLibrary(bytes, "fuzz.patches", lib, refuse);
    if (!loaded) return 0;
    if (!loaded->complete()) __builtin_trap();  // a loaded library is complete
    auto saved = fray::sim::patchLibraryBytes(*loaded);
    if (!saved) __builtin_trap();  // what loads must save
    auto again = fray::sim::readPatchLibrary(*saved, "again.patches", lib, refuse);
    if (!again) __builtin_trap();
    auto resaved = fray::sim::patchLibraryBytes(*again);
    if (!resaved || *resaved != *saved) __builtin_trap();
    return 0;
}
