#include "rig.h"

#include <array>

#include <glm/geometric.hpp>

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

glm::vec3 sideColour(int side) {
    static constexpr std::array<glm::vec3, 4> kColours = {
        glm::vec3(0.80f, 0.12f, 0.10f), glm::vec3(0.10f, 0.25f, 0.80f), glm::vec3(0.12f, 0.60f, 0.18f),
        glm::vec3(0.85f, 0.62f, 0.10f)};
    const auto n = static_cast<int>(kColours.size());
    return kColours[static_cast<std::size_t>(((side % n) + n) % n)];
}

}  // namespace fray::exporter
