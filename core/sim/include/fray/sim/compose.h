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

enum class SceneKind { OneVsMany, OneVsOne, Domino, Luggage, Football, Rat };

// Where and when a domino chain starts: the person standing there falls first.
struct DominoStart {
    double time = 0;
    glm::vec2 pos{0.0f};
};
// Football: from `time` on the carrier runs toward this floor heading
// (rad, 0 = +Z, straight at the goal line; the arrow on the floor).
struct RunDirection {
    double time = 0;
    double heading = 0;
};
const char* sceneKindName(SceneKind kind);

struct ComposeSpec {
    SceneKind kind = SceneKind::OneVsMany;
    double duration = 30;          // s (one-vs-one stops here; one-vs-many when the enemies are used up or here)
    std::uint64_t seed = 1;
    int enemies = 10;              // one-vs-many: how many come in turn
    double entryRadius = 8;        // m: newcomers enter from this far out
    std::vector<std::string> patterns;  // pattern names to use; empty: all in the library
    std::vector<UserCommand> commands;
    // Domino: the painted area (the CLI reads the bitmap file), the chains' starts
    // (a letter each, with its own start time), people standing outside the area,
    // and a cap on the crowd.
    std::string floorFile;
    double metresPerPixel = 0.1;
    glm::vec2 floorOrigin{0.0f};
    FloorBitmap floor;
    std::vector<DominoStart> starts;
    int background = 20;
    int maxCharacters = 400;
    // Luggage: porters passing one item along, each recycled after handing it on.
    int porters = 4;
    int handoffs = 8;
    // Football: tacklers coming in turn, the goal line this far along +Z (m)
    // from the carrier's start, and the running direction over time.
    int tacklers = 5;
    double goal = 40;
    std::vector<RunDirection> directions;
    // Two tacklers at once where a second tackle patch connects spatially to
    // the chosen one (the carrier's very same run and cut, the two tacklers
    // never meeting).
    bool doubles = false;
    // Rat: the rat runs along the user's trajectory (x, z polyline) at ratSpeed
    // from ratStart on, through a crowd standing within `band` of it, people
    // `spacing` apart; those within `reach` of the trajectory must get out of
    // its way, and bump into their neighbours doing so.
    std::vector<glm::vec2> ratPath;
    double ratSpeed = 2.5;
    double ratStart = 1.0;
    int crowd = 30;
    double band = 2.5;
    double spacing = 0.9;
    double reach = 1.0;
    double bumps = 0.5;  // 0: stepping aside avoids bumping into neighbours; 1: prefers it
    // Scores (SPEC 4.4).
    double wDensity = 10, wUsage = 1000, wUser = 10000, densityScale = 1.0;
    std::string text;              // the spec as written, kept in the scene
};

// Does a compose spec of this kind draw on the patch library? (The rat scene
// generates its own patches for the rat's speed; it reads "kind" only, and says yes
// for anything it cannot read, so the full parser reports the error.)
bool composeNeedsPatches(std::string_view specText);

// Reads a compose spec (JSON). Errors name the file and the JSON path.
Result<ComposeSpec> parseComposeSpec(std::string_view text, std::string_view fileName, const PatchLibrary& patches);

struct ComposeStats {
    int patchesUsed = 0;
    int temporalLinks = 0, recycled = 0;   // how each next patch was found
    int graphJoined = 0;                   // football: joined where the carrier's run continues in the motion graph
    int secondTacklers = 0;                // football: second tacklers joined beside a patch by a spatial connection
    int tacklersPassed = 0;                // football: tackles the carrier got away from
    double goalReached = -1;               // football: when the carrier crossed the goal line (s), -1 never
    int locomotionSteps = 0;
    int chainFalls = 0;                    // domino: people knocked over by a falling body
    int spatialFalls = 0;                  // domino: of those, caused through a spatial connection of the faller's patch
    int ratPatches = 0;                    // rat: {run, AVOID} patches generated for the scene's rat speed
    int ratNear = 0;                       // rat: people standing within reach of its trajectory
    int ratAvoided = 0;                    // rat: of those, who stepped out of its way
    int ratPushed = 0;                     // rat: of those, who were pushed by someone else first
    int ratStartled = 0;                   // rat: of those, who had no way out and reeled back as it ran into them
    int ratRunOver = 0;                    // rat: of those, who could not even reel back (stood as it ran past their feet)
    int bumps = 0;                         // rat: people pushed by someone stepping aside (a pushed one may push on)
    double ratClearance = -1;              // rat: closest the rat came to an avoider's feet and shins (m), -1 none
    // domino: share of the painted area within kCoverRadius of where someone
    // stood and fell (sampled every 0.25 m); how much of the area the chains fill.
    double paintedCoverage = 0;
    static constexpr float kCoverRadius = 1.0f;
    double maxJunctionError = 0;           // m: worst gap between where locomotion ended and where a patch starts
    double seconds = 0;
};

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
