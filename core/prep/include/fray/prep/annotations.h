#pragma once
// Annotation vocabulary and automatic proposals (SPEC 1.4). Proposals are
// cheap guesses the user confirms in the inspector: they land in
// ActionInfo::proposed, never in ActionInfo::annotations.
#include <string>
#include <vector>

#include "fray/core/joint_guess.h"
#include "fray/core/motion.h"
#include "fray/prep/actions.h"
#include "fray/prep/signals.h"

namespace fray::prep {

// The defaults used by the experiments: punch, kick, avoid, dodge, block,
// step, transition, falling, pushed, run, jump, tackle, carry, walk, hand,
// receive, turn, idle. Projects may add their own words.
const std::vector<std::string>& defaultVocabulary();
// Lower-case letters, digits, '_' and '-', 1..32 characters.
bool isValidAnnotation(const std::string& word);

// Speeds are in body heights per second (MotionSignals::bodyHeight), lengths
// in body heights or shares of the take's own standing height, so the same
// values hold for a synthetic actor, a karateka in inches and a LAFAN1 take.
struct ProposalParams {
    // An attack is a fast effector that reaches a target: a hand faster than
    // attackSpeed (relative to the pelvis) whose stroke ends (where it slows
    // to half its peak speed) no lower than punchHeight below the shoulder
    // and at least punchReach of the arm's length from the shoulder proposes
    // "punch" (a low block ends down by the thigh, its wind-up by the head); a foot
    // faster than attackSpeed that rises kickHeight above the floor, with its
    // knee raised to kickKnee of the standing pelvis height and the pelvis up,
    // proposes "kick" (steps stay low; falls, crawls and runs keep the knee down
    // or the pelvis low).
    double attackSpeed = 1.2;      // H/s
    double punchHeight = 0.15;     // H below the shoulder
    double punchReach = 0.6;       // share of the arm's length (shoulder-elbow-hand)
    double kickHeight = 0.2;       // H above the foot's floor level
    double kickKnee = 0.75;        // share of the standing pelvis height
    double fallHeightRatio = 0.45; // pelvis below this share of its standing height proposes "falling"
    double fallHeadRatio = 0.5;    // ... or the head below this share of its standing height
    double walkSpeed = 0.5;        // m/s pelvis speed on the floor: "walk"
    double runSpeed = 2.2;         // m/s: "run"
    double turnDegrees = 60.0;     // heading change over the action: "turn"
    double idleSpeed = 0.15;       // m/s: no joint faster than this on average: "idle"
};

struct Proposal {
    std::vector<std::string> annotations;
    std::vector<std::string> joints;  // joints used (the effector that triggered "punch"/"kick")
};

// Proposes annotations for frames [first, last] of the motion.
Proposal proposeAnnotations(const Motion& motion, const StandardJoints& joints, const MotionSignals& signals,
                            int first, int last, const ProposalParams& params = {});

// Fills ActionInfo::proposed (and joints when empty) for every action of doc,
// leaving confirmed annotations alone. Proposals equal to confirmed
// annotations are not repeated.
void proposeAll(MotionActions& doc, const Motion& motion, const StandardJoints& joints, const MotionSignals& signals,
                const ProposalParams& params = {});

}  // namespace fray::prep
