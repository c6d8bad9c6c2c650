#pragma once
// Internal constants of the demo skeleton (see makeDemoSkeleton).
#include <glm/vec3.hpp>

namespace fray::demo::detail {

enum Joint : int {
    kHips, kSpine, kSpine1, kSpine2, kNeck, kHead,
    kLClavicle, kLArm, kLForeArm, kLHand, kLIndex,
    kRClavicle, kRArm, kRForeArm, kRHand, kRIndex,
    kLUpLeg, kLLeg, kLFoot, kLToe,
    kRUpLeg, kRLeg, kRFoot, kRToe,
    kJointCount
};

// Side index: 0 left, 1 right. Left is +X in the rest pose (the actor faces +Z).
inline double sideSign(int side) { return side == 0 ? 1.0 : -1.0; }

struct RigDims {
    static constexpr double pelvisToSpine = 0.10, spine1 = 0.12, spine2 = 0.12, neck = 0.17, head = 0.10;
    static constexpr double clavicleX = 0.03, clavicleY = 0.10, clavicle = 0.15;
    static constexpr double upperArm = 0.29, foreArm = 0.26, hand = 0.09;
    static constexpr double hipX = 0.095, hipY = -0.07;
    static constexpr double thigh = 0.43, shin = 0.43;
    static constexpr double toeY = -0.055, toeZ = 0.14;
    static constexpr double ankleHeight = 0.08;  // ankle joint above the floor with the foot flat
    static constexpr double standHeight = 1.01;  // Hips height with straight legs and flat feet
    // Longest hip-to-ankle distance the solver lets a supporting leg reach.
    static constexpr double legReach = 0.985 * (thigh + shin);
    static constexpr double spineToChest = pelvisToSpine + spine1 + spine2;  // Hips -> Spine2 at rest
};

glm::dvec3 restOffset(int joint);
int parentOf(int joint);

}  // namespace fray::demo::detail
