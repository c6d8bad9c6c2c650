#pragma once
// The control timeline of a take: keyframed body-level channels plus the
// footstep schedule of each foot. Actions author it; the solver turns it into
// joint rotations frame by frame (two-bone IK for arms and legs).
#include <array>
#include <vector>

#include <glm/vec3.hpp>

#include "curve.h"

namespace fray::demo::detail {

// Body channels. Frames used: world (W), heading frame H (x left, y up,
// z forward, rotated by Heading about Y), chest frame C (the Spine2 joint).
enum Ch : int {
    BaseX, BaseZ, Heading,              // W: where the body stands and faces (radians, unwrapped)
    ShiftX, ShiftZ,                     // H: pelvis offset from the base (weight shifts, leans)
    Height,                             // desired Hips height; the legs' reach may lower it
    PelvisYaw, PelvisPitch, PelvisRoll, // pelvis relative to H (pitch > 0 leans forward, roll > 0 to the right)
    SpinePitch, SpineYaw, SpineRoll,    // spread over Spine, Spine1, Spine2
    HeadPitch, HeadYaw, HeadRoll,       // spread over Neck and Head
    Gaze,                               // 0..1: how much the head undoes pelvis+spine angles (keeps looking ahead)
    LHandX, LHandY, LHandZ,             // C: wrist targets
    RHandX, RHandY, RHandZ,
    LPoleX, LPoleY, LPoleZ,             // C: direction the elbows point
    RPoleX, RPoleY, RPoleZ,
    LFree, RFree,                       // 0: foot follows its footstep schedule; 1: foot follows the free target
    LFootX, LFootY, LFootZ,             // H, relative to the Hips: free ankle targets
    RFootX, RFootY, RFootZ,
    LFootYaw, LFootPitch,               // free foot angle to the shin (pitch > 0 points the toes)
    RFootYaw, RFootPitch,
    LKneeX, LKneeY, LKneeZ,             // H: direction the knee points for a free leg
    RKneeX, RKneeY, RKneeZ,
    LFloor, RFloor,                     // 0..1: a free leg kneels / lies with its knee on the floor
    LFloorDir, RFloorDir,               // +1 thigh forward of the hip (kneeling), -1 behind (lying prone)
    kChannelCount
};

inline Ch handCh(int side, int axis) { return static_cast<Ch>((side == 0 ? LHandX : RHandX) + axis); }
inline Ch poleCh(int side, int axis) { return static_cast<Ch>((side == 0 ? LPoleX : RPoleX) + axis); }
inline Ch freeCh(int side) { return side == 0 ? LFree : RFree; }
inline Ch footCh(int side, int axis) { return static_cast<Ch>((side == 0 ? LFootX : RFootX) + axis); }
inline Ch footYawCh(int side) { return side == 0 ? LFootYaw : RFootYaw; }
inline Ch footPitchCh(int side) { return side == 0 ? LFootPitch : RFootPitch; }
inline Ch floorCh(int side) { return side == 0 ? LFloor : RFloor; }
inline Ch floorDirCh(int side) { return side == 0 ? LFloorDir : RFloorDir; }
inline Ch kneeCh(int side, int axis) { return static_cast<Ch>((side == 0 ? LKneeX : RKneeX) + axis); }

// Where a planted foot is: ankle position (world, flat foot) and yaw (world).
struct FootPlant {
    glm::dvec3 ankle{0.0};
    double yaw = 0.0;
};

// One foot moving from one plant to the next. Between swings the foot is planted.
struct FootSwing {
    double t0 = 0, t1 = 0;
    FootPlant from, to;
    double lift = 0.05;       // peak ankle lift (m)
    double toeOff = 0.0;      // peak toes-down pitch early in the swing (rad)
    double heelStrike = 0.0;  // peak toes-up pitch late in the swing (rad)
};

struct FootSample {
    glm::dvec3 ankle{0.0};
    double yaw = 0.0;
    double pitch = 0.0;
    bool planted = true;
};

class FootSchedule {
public:
    void setInitial(const FootPlant& p) { initial_ = p; }
    // Appends a swing from the current last plant; t0 must not precede the last swing's end.
    void swing(double t0, double t1, const FootPlant& to, double lift, double toeOff = 0, double heelStrike = 0);
    const FootPlant& last() const { return swings_.empty() ? initial_ : swings_.back().to; }
    double lastTime() const { return swings_.empty() ? 0.0 : swings_.back().t1; }
    FootSample at(double t) const;

private:
    FootPlant initial_;
    std::vector<FootSwing> swings_;
};

struct Timeline {
    Timeline();
    std::array<Curve, kChannelCount> ch;
    std::array<FootSchedule, 2> feet;
    Curve& operator[](Ch c) { return ch[static_cast<std::size_t>(c)]; }
    const Curve& operator[](Ch c) const { return ch[static_cast<std::size_t>(c)]; }
};

}  // namespace fray::demo::detail
