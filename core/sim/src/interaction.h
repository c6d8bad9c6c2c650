#pragma once
// Interaction primitives shared by the planners (tree expansion now,
// Interaction Patches too): the earliest hit of an attack on a defender, the
// forced reaction that best matches a victim's posture and the hit direction
// (SPEC 2.1, 4.2), and the impulse of a blow. Internal to fray_sim.
#include <array>
#include <optional>
#include <utility>
#include <vector>

#include "fray/sim/action_library.h"

namespace fray::sim::detail {

// One action being played: which clip, when it started in scene time, how far
// into the clip it started, and where its first frame is placed.
struct Playing {
    int action = 0;
    double start = 0, offset = 0;
    RootXf root;
    double clipTime(double t) const { return offset + (t - start); }
    RootXf placement(const ActionLibrary& lib, double t) const { return root * lib.rootAt(action, clipTime(t)); }
    Obb box(const ActionLibrary& lib, double t, int segment) const {
        return lib.boxesAt(action, lib.sampleAt(action, clipTime(t)))[segment].placed(root);
    }

};

// A body in a clip at clip time tau, the clip's first frame placed at root.
struct BodyPose {
    int action = 0;
    double tau = 0;
    RootXf root;
};

// Do the core segments (SPEC 2.4: pelvis, torso, head, thighs) of two bodies
// overlap, boxes shrunk by `shrink` (grazing contact is not penetration)?
// Bodies whose pelvises are more than pelvisReach apart never do.
bool coreBodiesOverlap(const ActionLibrary& lib, const BodyPose& a, const BodyPose& b, float shrink, float pelvisReach = 1.2f);

// The same test in two halves, for callers that test one body against many:
// a body's pelvis on the floor and its core boxes placed and shrunk, the
// boxes only when asked (they cost ten times the pelvis).
class CoreBody {
public:
    CoreBody(const ActionLibrary& lib, const BodyPose& pose, float shrink)
        : CoreBody(lib, pose, FloorRotation(pose.root.heading), shrink) {}
    // With the rotation of pose.root already computed.
    CoreBody(const ActionLibrary& lib, const BodyPose& pose, const FloorRotation& rotate, float shrink)
        : CoreBody(lib, pose, rotate, lib.rootAt(pose.action, pose.tau).pos, shrink) {}
    // And with the pelvis in the clip's frame, lib.rootAt(pose.action, pose.tau).pos, already known.
    CoreBody(const ActionLibrary& lib, const BodyPose& pose, const FloorRotation& rotate, glm::vec2 clipPelvis,
             float shrink);
    glm::vec2 pelvis() const { return pelvis_; }
    const std::array<Obb, kCoreSegments.size()>& boxes() const;
    // Their bounding-sphere radii (valid after boxes()).
    const std::array<float, kCoreSegments.size()>& radii() const { return radii_; }

private:
    const ActionLibrary* lib_;
    BodyPose pose_;
    FloorRotation rotate_;
    float shrink_;
    glm::vec2 pelvis_;
    // Empty until asked for (an empty optional costs no initialisation).
    mutable std::optional<std::array<Obb, kCoreSegments.size()>> boxes_;
    mutable std::array<float, kCoreSegments.size()> radii_;
};
bool coreBodiesOverlap(const CoreBody& a, const CoreBody& b, float pelvisReach);
inline BodyPose bodyAt(const Playing& p, double t) { return {p.action, p.clipTime(t), p.root}; }

// Earliest hit in [t0, t1] of one attacker on one defender; time < 0 if none.
struct HitCandidate {
    double time = -1;
    int target = 0;
    int effector = 0;
    double speed = 0;
    bool blocked = false;
};
HitCandidate findHit(const ActionLibrary& lib, const Playing& att, const Playing& def, double t0, double t1);

// Effective mass (kg) behind a blow with this segment: impulse = speed x mass.
double effectiveMass(int effector);

// Per library action: the initial floor travel direction of reactive clips
// (unit, in the clip's frame), zero for the rest.
std::vector<glm::vec2> reactionDirections(const ActionLibrary& lib);

// The reactive clip and start sample that best match the victim's posture at
// t, the push direction (in the victim's heading frame) and whether the blow
// knocks down (strong) or pushes. Only clips in pool (ascending) are used;
// {-1, 0} when the pool has none. Cached per pool and thread.
std::pair<int, int> chooseReaction(const ActionLibrary& lib, const std::vector<glm::vec2>& reactionDir,
                                   const Playing& victim, double t, glm::vec2 pushLocal, bool strong,
                                   const std::vector<int>& pool);

// The push direction of a blow in the victim's heading frame, from the two placements at contact.
glm::vec2 pushDirection(const RootXf& victim, const RootXf& attacker);

}  // namespace fray::sim::detail
