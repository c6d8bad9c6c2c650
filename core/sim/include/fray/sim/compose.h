#pragma once
// Scene composition from Interaction Patches (SPEC 4.4-4.5): patches are
// chained in time (temporal connections, or recycling through standard
// poses) and placed in space; a greedy collision-free locomotion engine
// brings characters to their patches, planned backward in time from each
// interaction, with newcomers entering from outside along radial directions.
// The output is the shared scene timeline.
#include <string>
#include <vector>

#include "fray/core/progress.h"
#include "fray/core/result.h"
#include "fray/sim/patches.h"
#include "fray/sim/scene.h"

namespace fray::sim {

// A timed user command: from `time` on, patches whose main-character actions
// carry `annotation` are preferred (s_u of SPEC 4.4).
struct UserCommand {
    double time = 0;
    std::string annotation;  // punch, kick, avoid, ... or a group (attack, defence)
};

enum class SceneKind { OneVsMany, OneVsOne };
const char* sceneKindName(SceneKind kind);

struct ComposeSpec {
    SceneKind kind = SceneKind::OneVsMany;
    double duration = 30;          // s (one-vs-one stops here; one-vs-many when the enemies are used up or here)
    std::uint64_t seed = 1;
    int enemies = 10;              // one-vs-many: how many come in turn
    double entryRadius = 8;        // m: newcomers enter from this far out
    std::vector<std::string> patterns;  // pattern names to use; empty: all in the library
    std::vector<UserCommand> commands;
    // Scores (SPEC 4.4).
    double wDensity = 10, wUsage = 1000, wUser = 10000, densityScale = 1.0;
    std::string text;              // the spec as written, kept in the scene
};

// Reads a compose spec (JSON). Errors name the file and the JSON path.
Result<ComposeSpec> parseComposeSpec(std::string_view text, std::string_view fileName, const PatchLibrary& patches);

struct ComposeStats {
    int patchesUsed = 0;
    int temporalLinks = 0, recycled = 0;   // how each next patch was found
    int locomotionSteps = 0;
    double maxJunctionError = 0;           // m: worst gap between where locomotion ended and where a patch starts
    double seconds = 0;
};

Result<Scene> compose(const ActionLibrary& lib, const PatchLibrary& patches, const ComposeSpec& spec,
                      ComposeStats* stats = nullptr, const ProgressFn& progress = {});

}  // namespace fray::sim
