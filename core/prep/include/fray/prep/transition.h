#pragma once
// Transitions between actions (SPEC 1.5, last point): action B played after
// action A, placed to continue A on the floor, blended over a short window,
// with planted feet held in place by two-bone leg IK.
//
// How a join works:
//  1. Placement. B is turned about Y and moved on the floor so that the frame
//     before its first (its own, or its first step run backwards) lies on
//     A's last frame: pelvis position on the floor and heading. B's first
//     frame then follows A's last the way it followed its own previous one.
//  2. Blend (inertialisation). The difference between A's last pose and that
//     frame (local rotations as slerp offsets, pelvis position including its
//     height, other local translations), and the difference of their
//     velocities, are added to B and decay to zero over blendSeconds along a
//     cubic with zero value and slope at the end. The seam keeps A's position
//     and velocity; B plays unchanged after the window; an action joined to
//     its own successor comes back unchanged.
//  3. Foot locking. A foot in contact at the seam, or touching down during the
//     blend, is held: its ankle follows B's own foot path (which is planted)
//     offset to where the foot actually was, instead of drifting with the
//     decaying offset, solved by two-bone leg IK (fray/core/ik.h). The lock
//     lasts until the contact ends, then is released over releaseSeconds
//     while the foot is in the air. Where a held foot would be out of the
//     leg's reach, the pelvis comes down (smoothly, at most a quarter leg).
#include <cstdint>

#include "fray/core/joint_guess.h"
#include "fray/core/motion.h"
#include "fray/core/result.h"
#include "fray/prep/motion_graph.h"
#include "fray/prep/signals.h"

namespace fray::prep {

struct TransitionOptions {
    double blendSeconds = 0.15;   // blend window; rounded to frames, at least 1
    bool footLocking = true;
    double releaseSeconds = 0.1;  // a lock fades out over this once its contact ends
};

struct JoinedActions {
    Motion motion;          // A's frames, then B's
    FootContacts contacts;  // per frame of motion: A's contacts, then B's
    int seam = 0;           // first frame that comes from B
    int blendFrames = 0;    // frames [seam, seam + blendFrames) carry a blend offset
    int lastAdjusted = 0;   // last frame the blend or a foot lock changed
    bool ikReached = true;  // false when some locked foot could not be reached
};

// Joins action A of motion a and action B of motion b. The motions must share
// a skeleton (names, hierarchy) and frame rate. Contacts are per frame of
// their whole motion; when null they are estimated (estimateContacts).
Result<JoinedActions> joinActions(const Motion& a, const StandardJoints& ja, ActionRef actionA,
                                  const FootContacts* contactsA, const Motion& b, const StandardJoints& jb,
                                  ActionRef actionB, const FootContacts* contactsB,
                                  const TransitionOptions& options = {});

// Simple contact guess for motions without labels: a foot (its ankle or toe,
// whichever is lower / slower) is planted when it is within 5 cm of its floor
// level and moves slower than 0.4 m/s (MotionSignals). All zero when the
// signals cannot be computed (no feet, fewer than 3 frames).
FootContacts estimateContacts(const Motion& motion, const StandardJoints& joints);

// Foot skate: for every frame f in (firstFrame, lastFrame] where a foot is in
// contact at f and f-1, the horizontal movement of that foot between them:
// the larger of its ankle's and its toe's (the toe when the skeleton has
// one). Metres per frame, over all (foot, frame) samples.
struct SkateStats {
    double maxPerFrame = 0;
    double meanPerFrame = 0;
    int frames = 0;  // (foot, frame) samples
};
SkateStats footSkate(const Motion& motion, const StandardJoints& joints, const FootContacts& contacts,
                     int firstFrame, int lastFrame);

}  // namespace fray::prep
