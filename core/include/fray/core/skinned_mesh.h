#pragma once
// A skinned body that replaces the default capsules (fray/core/body_mesh.h):
// a mesh in bind space whose vertices follow up to four joints of a motion's
// skeleton, blended linearly. It is plain data, built by a rig loader
// (fray/io/rig_import.h) and drawn by the renderer; nothing here knows a file
// format or a GPU.
//
// Skinning: a vertex v (bind space) lands at sum_k w_k * (world_k * inverseBind_k)(v),
// where world_k is joint k's posed world transform from forward kinematics.
// Inverse binds are rigid (rotation + translation), so the renderer can keep
// its palette of one position and one quaternion per joint.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "fray/core/result.h"
#include "fray/core/skeleton.h"

namespace fray {

// p -> translation + rotation * p.
struct RigidTransform {
    glm::vec3 translation{0.0f};
    glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};
};

inline RigidTransform operator*(const RigidTransform& a, const RigidTransform& b) {
    return {a.translation + a.rotation * b.translation, a.rotation * b.rotation};
}
RigidTransform invert(const RigidTransform& t);

struct SkinnedVertex {
    glm::vec3 position;                  // bind space, skeleton units (metres)
    glm::vec3 normal;                    // bind space, unit length
    std::array<std::uint16_t, 4> joints; // skeleton joint indices (all in range); unused slots 0 with weight 0
    glm::vec4 weights;                   // descending, sum 1
};
static_assert(sizeof(SkinnedVertex) == 48);

inline constexpr int kMaxSkinnedJoints = 65535;  // joint indices are 16-bit

struct SkinnedMesh {
    std::vector<SkinnedVertex> vertices;
    std::vector<std::uint32_t> indices;  // triangles, counter-clockwise seen from outside
    // Per skeleton joint: bind-space -> joint-local transform (identity for
    // joints no vertex uses).
    std::vector<RigidTransform> inverseBind;
    // The skeleton it was bound to (skeletonFingerprint) and its joint count.
    std::uint64_t skeletonFingerprint = 0;
    int jointCount = 0;
    // Per skeleton joint: the rig bone it was matched to ("" when none).
    std::vector<std::string> boneOfJoint;
    // Furthest any vertex lies from the bind position of its heaviest joint
    // (metres): how far the body reaches beyond the joints, for culling.
    float reach = 0.0f;
    std::string source;                 // file it came from
    std::vector<std::string> warnings;  // what the loader fixed or could not check
};

// Checks a mesh against the skeleton it is drawn with: same fingerprint and
// joint count, a whole number of triangles, indices and joints in range,
// finite positions, weights that sum to 1. The message says what is wrong.
Status checkSkinnedMesh(const SkinnedMesh& mesh, const Skeleton& skeleton);

// Bind-space position of each joint (the inverse of its inverse bind).
std::vector<glm::vec3> jointBindPositions(const SkinnedMesh& mesh);

}  // namespace fray
