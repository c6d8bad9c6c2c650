#include "rig.h"

#include <array>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include "fray/core/body_mesh.h"

namespace fray::exporter {

std::vector<glm::vec3> bindPositions(const Skeleton& sk) {
    std::vector<glm::vec3> out(static_cast<std::size_t>(sk.jointCount()));
    for (std::size_t j = 0; j < out.size(); ++j) {
        const int p = sk.parents[j];
        out[j] = (p >= 0 ? out[static_cast<std::size_t>(p)] : glm::vec3(0.0f)) + sk.offsets[j];
    }
    return out;
}

BindMesh bindMesh(const Skeleton& sk) {
    const BodyMesh body = buildBodyMesh(sk);
    const auto bind = bindPositions(sk);
    BindMesh out;
    out.positions.reserve(body.vertices.size());
    out.normals.reserve(body.vertices.size());
    out.joints.reserve(body.vertices.size());
    for (const BodyVertex& v : body.vertices) {
        // Rest rotations are the identity: joint-local directions are bind-space directions.
        out.positions.push_back(bind[v.joint] + v.position);
        out.normals.push_back(glm::normalize(v.normal));
        out.joints.push_back(v.joint);
    }
    out.indices = body.indices;
    return out;
}

ExportBody exportBody(const Skeleton& sk, const SkinnedMesh* skin) {
    ExportBody out;
    const auto joints = static_cast<std::size_t>(sk.jointCount());
    if (skin) {
        for (const SkinnedVertex& v : skin->vertices) {
            out.positions.push_back(v.position);
            out.normals.push_back(v.normal);
            out.joints.push_back(v.joints);
            out.weights.push_back(v.weights);
        }
        out.indices = skin->indices;
        for (std::size_t j = 0; j < joints; ++j) {
            const RigidTransform t = j < skin->inverseBind.size() ? skin->inverseBind[j] : RigidTransform{};
            glm::mat4 m = glm::mat4_cast(t.rotation);
            m[3] = glm::vec4(t.translation, 1.0f);
            out.inverseBind.push_back(m);
        }
        return out;
    }
    const BindMesh body = bindMesh(sk);
    out.positions = body.positions;
    out.normals = body.normals;
    for (std::uint32_t j : body.joints) {
        out.joints.push_back({static_cast<std::uint16_t>(j), 0, 0, 0});
        out.weights.emplace_back(1.0f, 0.0f, 0.0f, 0.0f);
    }
    out.indices = body.indices;
    // The bind pose has no rotation: a translation by minus the bind position.
    for (const glm::vec3& p : bindPositions(sk)) {
        glm::mat4 m(1.0f);
        m[3] = glm::vec4(-p, 1.0f);
        out.inverseBind.push_back(m);
    }
    return out;
}

bool rebindSkin(const SkinnedMesh& skin, const Skeleton& from, const Skeleton& to, SkinnedMesh& out) {
    out = skin;
    std::vector<int> map(static_cast<std::size_t>(from.jointCount()), -1);
    for (int j = 0; j < from.jointCount(); ++j) map[static_cast<std::size_t>(j)] = to.find(from.names[static_cast<std::size_t>(j)]);
    for (SkinnedVertex& v : out.vertices) {
        for (std::size_t k = 0; k < 4; ++k) {
            if (v.weights[static_cast<glm::length_t>(k)] <= 0.0f) {
                v.joints[k] = 0;
                continue;
            }
            const int j = v.joints[k] < map.size() ? map[v.joints[k]] : -1;
            if (j < 0) return false;
            v.joints[k] = static_cast<std::uint16_t>(j);
        }
    }
    out.inverseBind.assign(static_cast<std::size_t>(to.jointCount()), RigidTransform{});
    out.boneOfJoint.assign(static_cast<std::size_t>(to.jointCount()), std::string());
    for (std::size_t j = 0; j < map.size(); ++j) {
        if (map[j] < 0) continue;
        if (j < skin.inverseBind.size()) out.inverseBind[static_cast<std::size_t>(map[j])] = skin.inverseBind[j];
        if (j < skin.boneOfJoint.size()) out.boneOfJoint[static_cast<std::size_t>(map[j])] = skin.boneOfJoint[j];
    }
    out.skeletonFingerprint = skeletonFingerprint(to);
    out.jointCount = to.jointCount();
    return true;
}

glm::vec3 sideColour(int side) {
    static constexpr std::array<glm::vec3, 4> kColours = {
        glm::vec3(0.80f, 0.12f, 0.10f), glm::vec3(0.10f, 0.25f, 0.80f), glm::vec3(0.12f, 0.60f, 0.18f),
        glm::vec3(0.85f, 0.62f, 0.10f)};
    const auto n = static_cast<int>(kColours.size());
    return kColours[static_cast<std::size_t>(((side % n) + n) % n)];
}

}  // namespace fray::exporter
