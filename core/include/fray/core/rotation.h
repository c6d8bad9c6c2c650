#pragma once
// Euler angle <-> quaternion conversions for every BVH rotation order.
// Convention: an order "ZXY" means the channel values are applied as
// R = Rz(z) * Rx(x) * Ry(y) (intrinsic, the BVH convention).
#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include "fray/core/skeleton.h"

namespace fray {

// Angles in degrees, indexed by axis (x, y, z).
glm::quat eulerToQuat(const glm::dvec3& degreesXYZ, RotationOrder order);
// Same in single precision (about 1e-7 rad off); the BVH reader's hot path.
glm::quat eulerToQuatFast(const glm::dvec3& degreesXYZ, RotationOrder order);
// Inverse of eulerToQuat: returns degrees indexed by axis (x, y, z).
glm::dvec3 quatToEuler(const glm::dquat& q, RotationOrder order);
// Of the angle triples (degrees, indexed by axis) that give the same rotation
// as `degreesXYZ` in `order` (the triple and its mirror, first and last angle
// + 180 and the middle one 180 - itself, each angle plus any multiple of 360),
// the one nearest `previousXYZ` (smallest sum of differences). Frame-to-frame
// it keeps Euler channels continuous.
glm::dvec3 nearestEquivalentEuler(const glm::dvec3& degreesXYZ, const glm::dvec3& previousXYZ, RotationOrder order);

}  // namespace fray
