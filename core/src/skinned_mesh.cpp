#include "fray/core/skinned_mesh.h"

#include <cmath>

#include "fray/core/body_mesh.h"

namespace fray {
namespace {

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

bool finite(const glm::quat& q) { return std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z) && std::isfinite(q.w); }

std::string vertexError(std::size_t v, const std::string& what) { return "vertex " + std::to_string(v) + ": " + what; }

Status checkVertex(const SkinnedVertex& v, std::size_t index, int jointCount) {
    if (!finite(v.position) || !finite(v.normal)) return makeError(vertexError(index, "position or normal is not finite"));
    float sum = 0.0f;
    for (std::size_t k = 0; k < 4; ++k) {
        const float w = v.weights[static_cast<glm::length_t>(k)];
        if (!std::isfinite(w) || w < 0.0f) return makeError(vertexError(index, "weight " + std::to_string(k) + " is not a finite non-negative number"));
        if (v.joints[k] >= jointCount)
            return makeError(vertexError(index, "joint " + std::to_string(v.joints[k]) + " is out of range (the skeleton has " +
                                                    std::to_string(jointCount) + " joints)"));
        sum += w;
    }
    if (std::abs(sum - 1.0f) > 1e-3f) return makeError(vertexError(index, "weights sum to " + std::to_string(sum) + ", not 1"));
    return {};
}

}  // namespace

RigidTransform invert(const RigidTransform& t) {
    const glm::quat r = glm::conjugate(t.rotation);
    return {-(r * t.translation), r};
}

Status checkSkinnedMesh(const SkinnedMesh& mesh, const Skeleton& skeleton) {
    const int joints = skeleton.jointCount();
    if (joints > kMaxSkinnedJoints)
        return makeError("the skeleton has " + std::to_string(joints) + " joints; a skinned mesh supports at most " +
                         std::to_string(kMaxSkinnedJoints));
    if (mesh.jointCount != joints || mesh.skeletonFingerprint != skeletonFingerprint(skeleton))
        return makeError("the skinned mesh" + (mesh.source.empty() ? std::string() : " from " + mesh.source) +
                         " was bound to another skeleton (" + std::to_string(mesh.jointCount) + " joints) than this one (" +
                         std::to_string(joints) + " joints)");
    if (mesh.inverseBind.size() != static_cast<std::size_t>(joints))
        return makeError("the skinned mesh has " + std::to_string(mesh.inverseBind.size()) + " inverse bind transforms for " +
                         std::to_string(joints) + " joints");
    for (const RigidTransform& t : mesh.inverseBind)
        if (!finite(t.translation) || !finite(t.rotation)) return makeError("the skinned mesh has a non-finite inverse bind transform");
    if (mesh.vertices.empty() || mesh.indices.empty()) return makeError("the skinned mesh has no triangles");
    if (mesh.indices.size() % 3 != 0)
        return makeError("the skinned mesh has " + std::to_string(mesh.indices.size()) + " indices, not a whole number of triangles");
    for (std::uint32_t i : mesh.indices)
        if (i >= mesh.vertices.size())
            return makeError("the skinned mesh has index " + std::to_string(i) + " for " + std::to_string(mesh.vertices.size()) + " vertices");
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
        if (Status s = checkVertex(mesh.vertices[v], v, joints); !s) return makeError("the skinned mesh's " + s.error().message);
    return {};
}

std::vector<glm::vec3> jointBindPositions(const SkinnedMesh& mesh) {
    std::vector<glm::vec3> out;
    out.reserve(mesh.inverseBind.size());
    for (const RigidTransform& t : mesh.inverseBind) out.push_back(invert(t).translation);
    return out;
}

}  // namespace fray
