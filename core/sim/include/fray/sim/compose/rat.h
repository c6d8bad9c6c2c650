#pragma once
// The rat scene (SPEC 4.5): a rat runs along the user's trajectory through a
// crowd; people step out of its way and bump into their neighbours. Its part
// of a compose spec (kind "rat") and of the compose stats.
#include <vector>

#include <glm/vec2.hpp>

#include "fray/core/result.h"
#include "fray/sim/compose.h"

namespace fray::sim {

// The rat runs along the user's trajectory (x, z polyline) at ratSpeed from
// ratStart on, through a crowd standing within `band` of it, people `spacing`
// apart; those within `reach` of the trajectory must get out of its way, and
// bump into their neighbours doing so.
struct RatSpec {
    static constexpr const char* kKind = "rat";
    std::vector<glm::vec2> ratPath;
    double ratSpeed = 2.5;
    double ratStart = 1.0;
    int crowd = 30;
    double band = 2.5;
    double spacing = 0.9;
    double reach = 1.0;
    double bumps = 0.5;  // 0: stepping aside avoids bumping into neighbours; 1: prefers it
};

struct RatStats {
    int ratPatches = 0;       // {run, AVOID} patches generated for the scene's rat speed
    int ratNear = 0;          // people standing within reach of its trajectory
    int ratAvoided = 0;       // of those, who stepped out of its way
    int ratPushed = 0;        // of those, who were pushed by someone else first
    int ratStartled = 0;      // of those, who had no way out and reeled back as it ran into them
    int ratRunOver = 0;       // of those, who could not even reel back (stood as it ran past their feet)
    int bumps = 0;            // people pushed by someone stepping aside (a pushed one may push on)
    double ratClearance = -1; // closest the rat came to an avoider's feet and shins (m), -1 none
};

// The rat scene's {run, AVOID} patches (SPEC 4.5) for a rat spec's speed and
// reach, as the composer generates them: someone standing in the guard
// `lateral` m to the left of a straight rat's line (negative: to its right),
// turned `facing` rad from the rat's heading, plays `actions` from `lead` s
// before the rat's closest approach, and the rat keeps `clearance` m from
// their feet and shins. Best first within each (lateral, facing) cell.
// `spec` must be of kind "rat".
struct RatAvoidPatch {
    double lateral = 0, facing = 0;
    std::vector<int> actions;
    double lead = 0, clearance = 0;
};
Result<std::vector<RatAvoidPatch>> ratAvoidPatches(const ActionLibrary& lib, const ComposeSpec& spec);

}  // namespace fray::sim
