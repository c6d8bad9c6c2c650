#pragma once
// Retargeting: a motion captured on one skeleton played by another (other
// joint names, hierarchy, proportions and rest pose). Used when a project
// mixes captures from several sources (every take is moved onto the project's
// skeleton) and when a scene is exported onto the user's rig.
//
// How (docs/DATA_PREP.md, "Mixed skeletons"):
// - Joint mapping: the standard joints of both skeletons (joint_guess.h):
//   pelvis, spine, chest, neck, head, upper arms, elbows, hands, upper legs,
//   knees, ankles, toes. A role is mapped when both skeletons have it (and it
//   is not a joint another role already took); other source joints drive
//   nothing (dropped), other target joints keep the reference pose.
// - Rest-pose alignment: each mapped joint gets an anatomical frame built
//   from joint positions only (bone direction, plus the body's left-right axis
//   or the limb's bending axis). The constant rotation between the target's
//   joint frame and its anatomical frame is measured once, in the target's
//   reference pose; every source frame then gives the anatomical frames and so
//   the target's world rotations. Rest poses are never assumed to be T-poses
//   (LAFAN1's rest pose has every bone along +X).
// - Scaling: the trajectory of the hip joints' midpoint, height included, is
//   scaled by the ratio of the leg lengths (hip-knee-ankle); the pelvis joint
//   is placed from it (sources put it at different heights above the hips);
//   bone lengths are the target's.
// - Feet: during each foot contact of the source (given, or detected from
//   ankle height and speed) the target's ankle is held at one place and a
//   two-bone IK (ik.h) on hip-knee-ankle reaches it; the ankle eases into and
//   out of the lock over a tenth of a second around the contact.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include "fray/core/joint_guess.h"
#include "fray/core/motion.h"
#include "fray/core/result.h"

namespace fray {

// The skeleton a motion is retargeted onto, with a reference pose (local
// translations and rotations per joint) in which its limbs are not all on one
// line: a motion's frame, or a rig's bind pose. Metres, Y up.
struct RetargetTarget {
    Skeleton skeleton;
    std::vector<glm::vec3> translations;
    std::vector<glm::quat> rotations;
    std::string name;  // for reports ("motion 'walk'", "rig.fbx")
};

// The target given by a motion's skeleton, its frame `frame` as the reference pose.
RetargetTarget retargetTargetFromMotion(const Motion& motion, int frame, std::string name);
// The target given by a skeleton's rest pose (offsets, no rotation).
RetargetTarget retargetTargetFromRest(const Skeleton& skeleton, std::string name);

// Per frame, 1 where the foot is planted.
struct FootContactTrack {
    std::vector<std::uint8_t> left, right;
};
// Ankle within 5 cm (scaled to the leg length) of its lowest height in the take
// and moving slower than 0.35 m/s (scaled likewise); runs shorter than 60 ms
// dropped, gaps shorter than 60 ms filled. Empty tracks without feet.
FootContactTrack detectFootContacts(const Motion& motion, const StandardJoints& joints);

// Mean and largest horizontal displacement of the ankle between consecutive
// frames that are both in contact (metres), over both feet.
struct FootSkate {
    double mean = 0.0, max = 0.0;
    int frames = 0;  // frame pairs measured
};
FootSkate measureFootSkate(const Motion& motion, const StandardJoints& joints, const FootContactTrack& contacts);

struct RetargetOptions {
    bool plantFeet = true;
    // The source's foot contacts (sized to its frames); detected when null.
    const FootContactTrack* contacts = nullptr;
};

struct RetargetMapping {
    std::string role, source, target;
};

struct RetargetReport {
    std::string source, target;
    std::vector<RetargetMapping> mapped;
    std::vector<std::string> droppedSource;  // source joints that drive nothing
    std::vector<std::string> heldTarget;     // target joints kept in the reference pose
    double scale = 1.0;                      // target leg length / source leg length
    int plantedFrames = 0;                   // foot-frames held by IK
    int unreachedFrames = 0;                 // of those, frames where the leg was too short
    // Several lines for the user: the mapping, what was dropped, the scale.
    std::string text() const;
};

// Same joint names and hierarchy (what the motion graph requires).
bool sameSkeleton(const Skeleton& a, const Skeleton& b);

// Whether a skeleton can be retargeted from or onto: it needs a pelvis, both
// upper legs, knees and ankles, and a joint above the pelvis. The error names
// `what` and the missing joints ("take 'x.bvh': no feet found (leftFoot,
// rightFoot); its joints are ...").
Status checkRetargetable(const Skeleton& skeleton, const std::string& what);

// The source motion played by the target skeleton: same frame count and fps,
// source info kept (with a warning saying it was retargeted).
Result<Motion> retarget(const Motion& source, const RetargetTarget& target, const RetargetOptions& options = {},
                        RetargetReport* report = nullptr);

}  // namespace fray
