#include "fray/sim/geometry.h"

#include <glm/geometric.hpp>

namespace fray::sim {

Obb Obb::placed(const RootXf& xf) const { return placed(xf, FloorRotation(xf.heading)); }

Obb Obb::placed(const RootXf& xf, const FloorRotation& rotate) const {
    Obb out;
    out.centre = placedCentre(xf, rotate);
    for (int i = 0; i < 3; ++i) out.axes[i] = rotate(axes[i]);
    out.half = half;
    return out;
}

bool overlaps(const Obb& a, const Obb& b) {
    const glm::vec3 d = b.centre - a.centre;
    const float ra0 = a.radius(), rb0 = b.radius();
    if (glm::dot(d, d) > (ra0 + rb0) * (ra0 + rb0)) return false;
    return overlapsBeyondSpheres(a, b);
}

bool overlapsBeyondSpheres(const Obb& a, const Obb& b) {
    return overlapsBeyondSpheresWith(a.centre, [&](int i) -> const glm::vec3& { return a.axes[i]; }, a.half, b);
}

Obb segmentBox(const glm::vec3& p0, const glm::vec3& p1, float halfSide, float halfDepth, float pad,
               const glm::vec3& side) {
    Obb box;
    glm::vec3 axis = p1 - p0;
    const float len = glm::length(axis);
    axis = len > 1e-6f ? axis / len : glm::vec3(0, 1, 0);
    glm::vec3 s = side - axis * glm::dot(side, axis);
    if (glm::dot(s, s) < 1e-8f) {
        s = std::fabs(axis.y) < 0.9f ? glm::cross(axis, glm::vec3(0, 1, 0)) : glm::cross(axis, glm::vec3(1, 0, 0));
    }
    s = glm::normalize(s);
    const glm::vec3 depth = glm::cross(axis, s);
    box.centre = 0.5f * (p0 + p1);
    box.axes = glm::mat3(axis, s, depth);
    box.half = {0.5f * len + pad, halfSide, halfDepth};
    return box;
}

}  // namespace fray::sim
