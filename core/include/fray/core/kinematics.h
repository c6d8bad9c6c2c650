#pragma once
// Forward kinematics: local joint transforms -> world positions/orientations.
#include <span>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include "fray/core/motion.h"

namespace fray {

// Computes world transforms for one pose. Output spans must hold jointCount entries.
void forwardKinematics(const Skeleton& skeleton, std::span<const glm::vec3> localTranslations,
                       std::span<const glm::quat> localRotations, std::span<glm::vec3> worldPositions,
                       std::span<glm::quat> worldRotations);

// World positions of one frame.
void worldPositions(const Motion& motion, int frame, std::span<glm::vec3> out);
// World positions of frames [first, last], frame-major [(f-first)*J + j].
std::vector<glm::vec3> worldPositions(const Motion& motion, int first, int last);
// World positions and orientations of one frame.
void worldTransforms(const Motion& motion, int frame, std::span<glm::vec3> positions,
                     std::span<glm::quat> rotations);

}  // namespace fray
