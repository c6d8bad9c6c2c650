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
};

struct ChangeEvent {
    ChangeKind kind = ChangeKind::Name;
    std::string motionId;  // for motion-level kinds
    int index = -1;        // action or motion index, -1 when not relevant
    int count = 0;         // MotionsAdded / MotionsRemoved
    friend bool operator==(const ChangeEvent&, const ChangeEvent&) = default;
};

}  // namespace fray::authoring
