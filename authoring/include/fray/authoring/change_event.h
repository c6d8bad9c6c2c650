#pragma once
// What changed in a ProjectDocument. Views listen to ProjectDocument::changed
// and refresh only what the event names; nothing else tells them.
#include <string>

namespace fray::authoring {

enum class ChangeKind {
    Name,            // the project's name
    Settings,        // graph preset, graph threshold, segmentation factor
    Vocabulary,      // words added, renamed or removed; annotations of any action and combination keys may follow
    MotionsAdded,    // index .. index+count-1 of Project::motions are new
    MotionsRemoved,  // index .. index+count-1 were removed (motionId: the first)
    MotionPaths,     // motion paths re-expressed for a new project folder (Save As)
    Cuts,            // the cuts of motionId, hence its actions (index: first action touched)
    Action,          // the description of action `index` of motionId
    ContactLabels,   // the contact labels of motionId
    Combos,          // the combination table
    // Scene setups (issue 23); `setup` names the setup (the new name after a rename).
    SetupAdded,        // index: its position in the list
    SetupRemoved,      // index: where it was
    SetupRenamed,      // previousName: the old name
    SetupParameters,   // parameters (preset, depth, weights, seed, duration, density, kind-specific fields)
    SetupPlacement,    // start placements (characters; a team move: index = its side), domino starts
    SetupTrajectory,   // trajectories and checkpoints; `character` follows the trajectory
    SetupFloor,        // the floor bitmap; `pixels`: the changed rectangle (empty: all of it)
    SetupPaths,        // the rat's trajectory, football directions, timed commands
    SetupPins,         // pins of edited generated interactions
    SetupPatches,      // keep/reject verdicts on patches
    PatternLists,      // the project's PatternLists and initial-condition ranges
};

// A rectangle of floor pixels (x, y: column and row of the first one).
struct FloorRect {
    int x = 0, y = 0, width = 0, height = 0;
    bool empty() const { return width <= 0 || height <= 0; }
    friend bool operator==(const FloorRect&, const FloorRect&) = default;
};

struct ChangeEvent {
    ChangeKind kind = ChangeKind::Name;
    std::string motionId;  // for motion-level kinds
    int index = -1;        // action or motion index, -1 when not relevant
    int count = 0;         // MotionsAdded / MotionsRemoved
    std::string setup{};      // setup kinds: the setup's name; PatternLists: the pattern ("" : several or the ranges)
    std::string previousName{};  // SetupRenamed
    std::string character{};  // SetupTrajectory / SetupPlacement: the character, when one
    FloorRect pixels{};       // SetupFloor
    friend bool operator==(const ChangeEvent&, const ChangeEvent&) = default;
};

}  // namespace fray::authoring
