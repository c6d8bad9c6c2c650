#pragma once
// The body-segment boxes of a posed body (SPEC 2.1), from world joint
// positions: what the action library stores per sample, for poses made
// elsewhere (the posture solver, posture metrics).
#include <array>
#include <span>

#include <glm/vec3.hpp>

#include "fray/core/joint_guess.h"
#include "fray/sim/action_library.h"

namespace fray::sim {

// The boxes of every segment of a body posed at these world joint positions
// (the skeleton's joints, roles from `joints`), in the same frame as `world`.
std::array<Obb, kSegmentCount> segmentBoxes(std::span<const glm::vec3> world, const StandardJoints& joints);

}  // namespace fray::sim
