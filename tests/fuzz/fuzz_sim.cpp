// libFuzzer target for the planners' readers: the scene spec (fray-cli
// simulate --spec), the scene file, the project's PatternList section, the
// compose spec and the binary patch library, parsed against a small
// hand-made action library (names and flags only); and the scene file once
// more against a library with captured motion (one short synthetic walking
// take), so that a held body's keys are made from its holder's pose as a read
// makes them (placeHeldBalls). The first input byte picks the parser. They
// must return an error, never crash, hang or leak; what loads must save (and a
// saved scene must load again to the same bytes).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include <cstring>
#include <string>

#include "fray/core/joint_guess.h"
#include "fray/demo/demo_actor.h"
#include "fray/demo/demo_project.h"
#include "fray/prep/motion_graph.h"
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

// One walking take of the demo actor, 4 s (its first cut actions; built once).
// The seed scene_motion.seed names its actions by motion and frames.
const fray::sim::ActionLibrary& motionLibrary() {
    static const fray::sim::ActionLibrary lib = [] {
        fray::demo::TakeSpec spec;
        spec.name = "walk";
        spec.kind = fray::demo::TakeKind::Walking;
        spec.seconds = 4.0;
        auto take = fray::demo::generateTake(spec, 1);
        std::vector<fray::prep::LoadedMotion> motions(1);
        motions[0].id = take.truth.take;
        motions[0].joints = fray::guessStandardJoints(take.motion.skeleton());
        motions[0].contacts.left = take.truth.leftContact;
        motions[0].contacts.right = take.truth.rightContact;
        motions[0].motion = std::move(take.motion);
        const auto project = fray::demo::makeDemoProject({{take.truth, "walk.bvh"}});
        const std::vector<const fray::Motion*> ptrs{&motions[0].motion};
        const std::vector<fray::StandardJoints> joints{motions[0].joints};
        auto graph = fray::prep::buildMotionGraph(ptrs, joints, fray::sim::projectActionRefs(project), {});
        if (!graph) __builtin_trap();
        auto built = fray::sim::buildActionLibrary(project, motions, *graph);
        if (!built) __builtin_trap();
        return std::move(*built);
    }();
    return lib;
}

// What loads must save and load again, byte for byte.
void sceneRoundTrip(std::string_view text, const fray::sim::ActionLibrary& lib) {
    auto scene = fray::sim::sceneFromJson(text, "fuzz.frayscene", lib);
    if (scene) {
        const std::string saved = fray::sim::sceneToJson(*scene, lib);
        auto again = fray::sim::sceneFromJson(saved, "again.frayscene", lib);
        if (!again || fray::sim::sceneToJson(*again, lib) != saved) __builtin_trap();
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    const std::string_view text(reinterpret_cast<const char*>(data + 1), size - 1);
    const auto& lib = library();
    switch (data[0] % 6) {
        case 0: (void)fray::sim::parseSceneSpec(text, "fuzz.json", lib, fray::sim::builtinPresets()); break;
        case 1: {
            // Bounded depth and size (prep::parseJson), bounded durations and
            // coordinates: what loads must save and load again, byte for byte.
            (void)fray::sim::sceneProjectPath(text, "fuzz.frayscene");
            sceneRoundTrip(text, lib);
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
        case 5: sceneRoundTrip(text, motionLibrary()); break;
        default: {
            // The header and checksum only: fuzz_patches reseals its inputs to
            // fuzz the rest of the format.
            (void)fray::sim::readPatchLibrary(text, "fuzz.patches", lib);
            break;
        }
    }
    return 0;
}
