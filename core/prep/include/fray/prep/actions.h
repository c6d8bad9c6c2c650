#pragma once
// The actions of one motion as a document: the cuts that split it and the
// user-authored description of every action (SPEC 1.1, 1.4). Cut edits are
// values (CutEdit) that apply and invert exactly, so the editor wraps each in
// an undo command and the CLI applies the same operations.
#include <optional>
#include <string>
#include <vector>

#include "fray/core/result.h"

namespace fray::prep {

// Valid initial-condition range of an action (SPEC 1.4, thesis 6.2): where the
// opponent may stand, relative to this character, for the action to work.
struct InitialConditions {
    double minDistance = 0.0;   // m, pelvis to pelvis on the floor
    double maxDistance = 0.0;
    double minAngle = 0.0;      // rad, direction of the opponent in my heading frame (0 = in front, + = left)
    double maxAngle = 0.0;
    double minFacing = 0.0;     // rad, opponent's heading relative to mine (pi = facing me)
    double maxFacing = 0.0;
    double minTiming = 0.0;     // s, offset of the opponent's action start
    double maxTiming = 0.0;
    friend bool operator==(const InitialConditions&, const InitialConditions&) = default;
};

struct ActionInfo {
    std::string name;                        // e.g. "jab"; empty until named
    std::vector<std::string> annotations;    // confirmed, from the vocabulary
    std::vector<std::string> proposed;       // automatic proposals awaiting confirmation
    std::vector<std::string> joints;         // joints used (skeleton names)
    std::optional<std::string> attackDirection;  // attacks
    std::optional<std::string> defendedPart;     // blocks / avoids
    std::optional<InitialConditions> initialConditions;
    bool has(const std::string& annotation) const;
    friend bool operator==(const ActionInfo&, const ActionInfo&) = default;
};

// A motion split into actions. cuts[i] is the first frame of action i+1;
// action 0 starts at frame 0 and the last ends at frameCount-1. Invariant:
// 0 < cuts[0] < cuts[1] < ... < frameCount and actions.size() == cuts.size()+1.
struct MotionActions {
    int frameCount = 0;
    std::vector<int> cuts;
    std::vector<ActionInfo> actions;

    static MotionActions whole(int frameCount);  // one action, no cuts
    int actionCount() const { return static_cast<int>(actions.size()); }
    int firstFrame(int action) const { return action == 0 ? 0 : cuts[static_cast<std::size_t>(action - 1)]; }
    int lastFrame(int action) const {
        return action == static_cast<int>(cuts.size()) ? frameCount - 1 : cuts[static_cast<std::size_t>(action)] - 1;
    }
    int actionAt(int frame) const;  // action holding frame (clamped)
    std::optional<std::string> validate() const;
    friend bool operator==(const MotionActions&, const MotionActions&) = default;
};

// One edit of the cuts. Every edit records what it needs to be inverted.
struct CutEdit {
    enum class Kind { Add, Remove, Move };
    Kind kind = Kind::Add;
    int frame = 0;    // Add: the new cut; Remove: the cut removed; Move: the old position
    int toFrame = 0;  // Move: the new position
    // Remove: the two actions as they were around the cut (to restore them);
    // Add: the two actions after the split (both start as copies of the split one).
    ActionInfo left, right;
};

// Builders that check the edit against the document and fill what the inverse
// needs. Errors say which frame and why ("frame 1200 is already a cut").
Result<CutEdit> makeAddCut(const MotionActions& doc, int frame);       // split the action holding frame
Result<CutEdit> makeRemoveCut(const MotionActions& doc, int frame);    // merge the two actions at this cut
Result<CutEdit> makeMoveCut(const MotionActions& doc, int frame, int toFrame);
// Merging actions a and a+1 is removing the cut between them.
Result<CutEdit> makeMergeActions(const MotionActions& doc, int action);

Status apply(MotionActions& doc, const CutEdit& edit);
CutEdit inverse(const CutEdit& edit);

// Replaces all cuts (automatic segmentation). Actions whose start frame is
// kept (within tolerance frames) keep their info; the rest start empty.
MotionActions recut(const MotionActions& doc, const std::vector<int>& cuts, int tolerance = 3);

}  // namespace fray::prep
