#pragma once
// Analytic two-bone IK (hip-knee-ankle, shoulder-elbow-wrist). The middle
// joint bends in the plane of the chain's current pose (the pole is the
// current middle joint), so a knee keeps pointing where it pointed.
#include <span>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include "fray/core/skeleton.h"

namespace fray {

// World-space rotations that solve a chain root -> mid -> end for a target:
// rotating everything below root by `upper` (about root) and then everything
// below mid by `lower` (about the moved mid) puts end on the target, or as
// close as the bone lengths allow (reached = false then).
struct TwoBoneSolution {
    glm::quat upper{1, 0, 0, 0};
    glm::quat lower{1, 0, 0, 0};
    bool reached = true;
};
TwoBoneSolution solveTwoBone(const glm::vec3& root, const glm::vec3& mid, const glm::vec3& end,
                             const glm::vec3& target);

// Applies solveTwoBone to one pose in place. world* hold the pose's forward
// kinematics (jointCount entries; read only). upper/mid/end are joints on one
// chain (intermediate joints such as twist bones are allowed). When
// endWorldRotation is given, end's local rotation is set so its world
// rotation equals it (keeps a planted foot's toe in place). Returns whether
// the target was reached.
bool applyTwoBoneIk(const Skeleton& skeleton, std::span<glm::quat> localRotations,
                    std::span<const glm::vec3> worldPositions, std::span<const glm::quat> worldRotations, int upper,
                    int mid, int end, const glm::vec3& target, const glm::quat* endWorldRotation = nullptr);

}  // namespace fray
