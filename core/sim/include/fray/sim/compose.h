#pragma once
// Scene composition from Interaction Patches (SPEC 4.4-4.5): patches are
// chained in time (temporal connections, or recycling through standard
// poses) and placed in space; a greedy collision-free locomotion engine
// brings characters to their patches, planned backward in time from each
// interaction, with newcomers entering from outside along radial directions.
// The output is the shared scene timeline.
//
// Each scene kind is a module of its own (core/sim/src/compose_<kind>.cpp,
// registered in compose.cpp) with its spec and stats types in
// fray/sim/compose/<kind>.h; ComposeSpec and ComposeStats gather them so that
// one spec file and one stats report serve every kind.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "fray/core/progress.h"
#include "fray/core/result.h"
#include "fray/sim/compose/domino.h"
#include "fray/sim/compose/football.h"
#include "fray/sim/compose/luggage.h"
#include "fray/sim/compose/one_vs_many.h"
#include "fray/sim/compose/rat.h"
#include "fray/sim/patches.h"
#include "fray/sim/scene.h"

namespace fray::sim {

// A timed user command: from `time` on, patches whose main-character actions
// carry `annotation` are preferred (s_u of SPEC 4.4).
struct UserCommand {
    double time = 0;
    std::string annotation;  // punch, kick, avoid, ... or a group (attack, defence)
};

enum class SceneKind { OneVsMany, OneVsOne, Domino, Luggage, Football, Rat };
const char* sceneKindName(SceneKind kind);

// What every kind reads: the scene, the patches it may use and how they are scored.
struct ComposeCommonSpec {
    SceneKind kind = SceneKind::OneVsMany;
    double duration = 30;          // s (one-vs-one stops here; one-vs-many when the enemies are used up or here)
    std::uint64_t seed = 1;
    double entryRadius = 8;        // m: newcomers enter from this far out
    std::vector<std::string> patterns;  // pattern names to use; empty: all in the library
    std::vector<UserCommand> commands;
    // Scores (SPEC 4.4).
    double wDensity = 10, wUsage = 1000, wUser = 10000, densityScale = 1.0;
    std::string text;              // the spec as written, kept in the scene
};

// A compose spec: the common part and every kind's own (one-vs-one has none);
// a kind reads the common part and its own.
struct ComposeSpec : ComposeCommonSpec, OneVsManySpec, DominoSpec, LuggageSpec, FootballSpec, RatSpec {};

// Does a compose spec of this kind draw on the patch library? (The rat scene
// generates its own patches for the rat's speed; it reads "kind" only, and says yes
// for anything it cannot read, so the full parser reports the error.)
bool composeNeedsPatches(std::string_view specText);

// Reads a compose spec (JSON). Errors name the file and the JSON path.
Result<ComposeSpec> parseComposeSpec(std::string_view text, std::string_view fileName, const PatchLibrary& patches);

struct ComposeCommonStats {
    int patchesUsed = 0;
    int temporalLinks = 0, recycled = 0;   // how each next patch was found
    int locomotionSteps = 0;
    double maxJunctionError = 0;           // m: worst gap between where locomotion ended and where a patch starts
    double seconds = 0;
};

// The stats of a composition: the common part and those of the kinds that keep their own.
struct ComposeStats : ComposeCommonStats, FootballStats, DominoStats, RatStats {};

// The rat scene's {run, AVOID} patches (SPEC 4.5) for a spec's rat speed and
// reach, as the composer generates them: someone standing in the guard
// `lateral` m to the left of a straight rat's line (negative: to its right),
// turned `facing` rad from the rat's heading, plays `actions` from `lead` s
// before the rat's closest approach, and the rat keeps `clearance` m from
// their feet and shins. Best first within each (lateral, facing) cell.
struct RatAvoidPatch {
    double lateral = 0, facing = 0;
    std::vector<int> actions;
    double lead = 0, clearance = 0;
};
Result<std::vector<RatAvoidPatch>> ratAvoidPatches(const ActionLibrary& lib, const ComposeSpec& spec);

Result<Scene> compose(const ActionLibrary& lib, const PatchLibrary& patches, const ComposeSpec& spec,
                      ComposeStats* stats = nullptr, const ProgressFn& progress = {});

}  // namespace fray::sim
