#pragma once
// Guessing of the standard joints across naming conventions (CMU, Bandai,
// LAFAN1, Mixamo-like, ...). Later steps need the feet and hands.
#include <string>

#include "fray/core/skeleton.h"

namespace fray {

struct StandardJoints {
    int pelvis = -1;
    int spine = -1;  // lowest spine joint
    int chest = -1;  // highest spine joint below the neck
    int neck = -1;
    int head = -1;
    int leftShoulder = -1, rightShoulder = -1;  // upper arm
    int leftElbow = -1, rightElbow = -1;
    int leftHand = -1, rightHand = -1;
    int leftHip = -1, rightHip = -1;  // upper leg
    int leftKnee = -1, rightKnee = -1;
    int leftFoot = -1, rightFoot = -1;  // ankle
    int leftToe = -1, rightToe = -1;

    bool hasFeet() const { return leftFoot >= 0 && rightFoot >= 0; }
    bool hasHands() const { return leftHand >= 0 && rightHand >= 0; }
    bool complete() const { return pelvis >= 0 && head >= 0 && hasFeet() && hasHands(); }
    // Names the roles that could not be found, e.g. "leftToe, rightToe".
    std::string missing() const;
};

StandardJoints guessStandardJoints(const Skeleton& skeleton);

}  // namespace fray
