#pragma once
// Per-frame signals of one motion that the data-preparation steps share
// (SPEC 1.2, 1.3): the joint-acceleration profile and the foot features
// (speed, height) used by the contact classifiers.
#include <array>
#include <vector>

#include "fray/core/joint_guess.h"
#include "fray/core/motion.h"
#include "fray/core/result.h"

namespace fray::prep {

enum class Foot : int { Left = 0, Right = 1 };

struct MotionSignals {
    double fps = 60.0;
    int frameCount = 0;
    // Sum over joints of the squared acceleration of the world joint
    // positions (m^2/s^4). Finite differences over a fixed 1/60 s step so the
    // profile does not depend on the capture rate.
    std::vector<float> acceleration;
    // Per foot ([0] left, [1] right), per frame. A foot is its ankle and, when
    // the skeleton has one, its toe: speed is the slower of the two points
    // (m/s), height the lower one above that point's own floor level (m), so
    // a heel-up toe contact still reads as supported.
    std::array<std::vector<float>, 2> footSpeed;
    std::array<std::vector<float>, 2> footHeight;
    // Floor level used for the heights (m, world Y), one per foot point:
    // the 2nd percentile of that point's height over the take.
    std::array<float, 2> ankleFloor{};
    std::array<float, 2> toeFloor{};
    // A coarse posture descriptor per frame, invariant to floor position and
    // heading: pelvis height, head height, horizontal head-pelvis distance,
    // left and right hand heights relative to the pelvis (m). Segmentation
    // uses it to prefer cuts at recurring postures. Empty when the skeleton
    // lacks a head or hands.
    std::vector<std::array<float, 5>> posture;
    // Size of the performer (m): the standing head height above the floor
    // (90th percentile of the head's height over the take; without a head,
    // 1.9 x the pelvis height). Speeds "in body heights per second" divide by
    // it, so thresholds carry over between skeletons, units and performers.
    double bodyHeight = 1.7;
    // Per frame, the fastest effector in body heights per second: each hand
    // relative to the pelvis, each foot (ankle) in the world. Empty when the
    // skeleton lacks a pelvis or hands. Segmentation uses it to find where an
    // action has come to rest (no effector moving visibly).
    std::vector<float> effectorSpeed;
};

// Computes the signals. Fails when the feet cannot be identified or the
// motion has fewer than 3 frames.
Result<MotionSignals> computeSignals(const Motion& motion, const StandardJoints& joints);

// Per-frame foot contacts: 1 when the foot supports the body.
struct FootContacts {
    std::vector<std::uint8_t> left;
    std::vector<std::uint8_t> right;
    const std::vector<std::uint8_t>& foot(Foot f) const { return f == Foot::Left ? left : right; }
    std::vector<std::uint8_t>& foot(Foot f) { return f == Foot::Left ? left : right; }
    int frameCount() const { return static_cast<int>(left.size()); }
};

enum class Support : std::uint8_t { None = 0, Left = 1, Right = 2, Double = 3 };
Support supportAt(const FootContacts& contacts, int frame);

}  // namespace fray::prep
