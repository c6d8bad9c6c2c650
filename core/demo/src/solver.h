#pragma once
// Per-frame solver: timeline channels -> joint rotations. Pelvis from the base,
// shift and heading channels; its height is the desired height softly capped
// by what the supporting legs can reach (so knees never over-extend and planted
// feet are always reached exactly); spine and head from angle channels; arms
// and legs by analytic two-bone IK with a pole vector.
#include <array>
#include <cstdint>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include "fray/core/motion.h"
#include "rig.h"
#include "timeline.h"

namespace fray::demo::detail {

glm::dquat rotX(double a);
glm::dquat rotY(double a);
glm::dquat rotZ(double a);
// R = Ry(yaw) * Rx(pitch) * Rz(roll).
glm::dquat yawPitchRoll(double yaw, double pitch, double roll);

// Orientation of the chest (Spine2) relative to the heading frame for given
// pelvis and spine angles, and the chest joint's offset from the Hips (also in H).
glm::dquat chestRotationH(double pelvisYaw, double pelvisPitch, double pelvisRoll, double spinePitch,
                          double spineYaw, double spineRoll);
glm::dvec3 chestOffsetH(double pelvisYaw, double pelvisPitch, double pelvisRoll, double spinePitch, double spineYaw,
                        double spineRoll);

struct SolvedFrame {
    glm::dvec3 root{0.0};
    std::array<glm::dquat, kJointCount> local;
    std::array<glm::dvec3, kJointCount> world;
    std::array<bool, 2> contact{};
};

void solveFrame(const Timeline& timeline, double t, SolvedFrame& out);

// Samples frames [0, frameCount) at 60 fps into a Motion on the demo skeleton.
Motion synthesize(const Timeline& timeline, int frameCount, std::vector<std::uint8_t>& leftContact,
                  std::vector<std::uint8_t>& rightContact);

}  // namespace fray::demo::detail
