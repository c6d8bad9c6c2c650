#pragma once
// What the skinned formats (glTF, FBX) share: the bind pose, the body mesh in
// bind space, and a colour per side.
#include <array>
#include <cstdint>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "fray/core/skeleton.h"
#include "fray/core/skinned_mesh.h"

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

// What the skinned writers draw for one character: its rig skin when it has
// one, else the capsules, with up to four joints per vertex and, per joint,
// its inverse bind matrix (bind space -> joint space; column-major, metres).
struct ExportBody {
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;
    std::vector<std::array<std::uint16_t, 4>> joints;  // per vertex
    std::vector<glm::vec4> weights;                    // per vertex, sum 1
    std::vector<std::uint32_t> indices;
    std::vector<glm::mat4> inverseBind;  // per skeleton joint
};
ExportBody exportBody(const Skeleton& skeleton, const SkinnedMesh* skin);

// A skin bound to `from` moved onto `to` by joint name (a root bone added
// above the rig's pelvis, ...). Joints of `to` that `from` lacks get no
// vertices and an identity inverse bind; false when a weighted joint of
// `from` is missing in `to`.
bool rebindSkin(const SkinnedMesh& skin, const Skeleton& from, const Skeleton& to, SkinnedMesh& out);

// Linear RGB tint of a side (team): red, blue, green, gold, then again.
glm::vec3 sideColour(int side);

}  // namespace fray::exporter
