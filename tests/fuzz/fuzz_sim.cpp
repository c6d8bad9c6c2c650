// libFuzzer target for the planners' readers: the scene spec (fray-cli
// simulate --spec), the scene file, the project's PatternList section, the
// compose spec and the binary patch library, parsed against a small
// hand-made action library. The first input byte picks the parser. They must
// return an error, never crash, hang or leak; what loads must save (and a
// saved scene must load again to the same bytes).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include <cstring>
#include <string>

#include "fray/sim/compose.h"
#include "fray/sim/patches.h"
#include "fray/sim/patterns.h"
#include "fray/sim/scene.h"
#include "fray/sim/spec.h"

namespace {

const fray::sim::ActionLibrary& library() {
    static const fray::sim::ActionLibrary lib = [] {
        std::vector<fray::sim::LibraryAction> actions;
        struct A {
            const char* name;
            const char* annotation;
            std::uint32_t flags;
        };
        const A kinds[] = {{"jab", "punch", fray::sim::kPunch},
                           {"front_kick", "kick", fray::sim::kKick},
                           {"guard_idle", "idle", fray::sim::kIdle},
                           {"head_snap", "pushed", fray::sim::kPushed},
                           {"walk", "walk", fray::sim::kWalk}};
        int first = 0;
        for (const auto& k : kinds) {
            fray::sim::LibraryAction a;
            a.motionId = "take";
            a.name = k.name;
            a.annotations = {k.annotation};
            a.flags = k.flags;
            a.firstFrame = first;
            a.lastFrame = first + 29;
            a.duration = 0.5;
            first += 30;
            actions.push_back(a);
        }
        return fray::sim::ActionLibrary::catalogue(std::move(actions), {"punch", "kick", "idle", "pushed", "walk"});
    }();
    return lib;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    const std::string_view text(reinterpret_cast<const char*>(data + 1), size - 1);
    const auto& lib = library();
    switch (data[0] % 5) {
        case 0: (void)fray::sim::parseSceneSpec(text, "fuzz.json", lib, fray::sim::builtinPresets()); break;
        case 1: {
            // Bounded depth and size (prep::parseJson), bounded durations and
            // coordinates: what loads must save and load again, byte for byte.
            (void)fray::sim::sceneProjectPath(text, "fuzz.frayscene");
            auto scene = fray::sim::sceneFromJson(text, "fuzz.frayscene", lib);
            if (scene) {
                const std::string saved = fray::sim::sceneToJson(*scene, lib);
                auto again = fray::sim::sceneFromJson(saved, "again.frayscene", lib);
                if (!again || fray::sim::sceneToJson(*again, lib) != saved) __builtin_trap();
            }
            break;
        }
        case 2: {
            fray::prep::Project project;
            project.vocabulary = lib.vocabulary();
            project.laterSections[fray::sim::kPatternSection] = std::string(text);
            auto set = fray::sim::projectPatterns(project, "fuzz.frayproj");
            if (set) {
                fray::sim::setProjectPatterns(project, *set);
                if (!fray::sim::projectPatterns(project, "again")) __builtin_trap();  // what loads must save
            }
            break;
        }
        case 3: {
            (void)fray::sim::parseComposeSpec(text, "fuzz.json", fray::sim::defaultPatterns());
            break;
        }
        default: {
            // The header and checksum only: fuzz_patches reseals its inputs to
            // fuzz the rest of the format.
            (void)fray::sim::readPatchLibrary(text, "fuzz.patches", lib);
            break;
        }
    }
    return 0;
}
