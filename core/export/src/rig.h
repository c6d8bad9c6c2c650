#pragma once
// What the skinned formats (glTF, FBX) share: the bind pose, the body mesh in
// bind space, and a colour per side.
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "fray/core/skeleton.h"

namespace fray::exporter {

// The bind pose is the skeleton's rest pose: every joint at its rest offset,
// no rotation. World position of each joint in it (the root at its offset).
std::vector<glm::vec3> bindPositions(const Skeleton& skeleton);

// fray::buildBodyMesh (the renderer's capsules) moved from joint-local to
// bind space. Each vertex is rigidly skinned to one joint.
struct BindMesh {
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;
    std::vector<std::uint32_t> joints;   // per vertex, < skeleton.jointCount()
    std::vector<std::uint32_t> indices;  // triangles, counter-clockwise seen from outside
};
BindMesh bindMesh(const Skeleton& skeleton);

// Linear RGB tint of a side (team): red, blue, green, gold, then again.
glm::vec3 sideColour(int side);

}  // namespace fray::exporter
