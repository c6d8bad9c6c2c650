#pragma once
// Which characters an edit of a setup can affect (issue 23, live re-plan):
// the editor re-plans and keeps the tracks of every other character of the
// previous scene unchanged. The rule is in docs/AUTHORING.md ("Affected").
#include <optional>
#include <string>
#include <vector>

#include "fray/setup/scene_setup.h"
#include "fray/sim/action_library.h"
#include "fray/sim/scene.h"

namespace fray::setup {

struct SetupEdit {
    enum class Kind {
        Stroke,      // floor paint: `lo`..`hi` (x, z, metres) changed from `time` on
        Checkpoint,  // a trajectory point or checkpoint of `character` moved, from `time` on
        Start,       // the start placement of `character` (or of its team) moved
        Other,       // anything else (weights, kind, duration...): everyone
    };
    Kind kind = Kind::Other;
    Point lo, hi;              // Stroke: bounding box on the floor
    double time = 0;           // Stroke/Checkpoint: the edit matters from here on (s)
    std::string character;     // Checkpoint/Start
    int side = -1;             // Start: >= 0 when a whole team (a scene side) moved
    std::vector<Point> points; // Checkpoint: old and new positions
};

// Reach (m) around a character's root beyond which an edit cannot touch it
// before a re-plan: an arm or leg's length plus a step.
inline constexpr double kAffectReach = 1.5;

// Indices of scene characters the edit can affect, ascending. Starts from
// those the edit touches directly and closes over interactions: anyone who
// hits, is hit by, catches or is caught by an affected character after the
// edit's time, or plays in the same group as one (tree expansion plans a group
// as one game tree), is affected too.
std::vector<int> affectedCharacters(const sim::Scene& previous, const sim::ActionLibrary& lib, const SetupEdit& edit);

}  // namespace fray::setup
