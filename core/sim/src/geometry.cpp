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
    const glm::vec3 d = b.centre - a.centre;
    // R[i][j] = a.axis i . b.axis j, in a's frame; epsilon guards parallel edges.
    float R[3][3], absR[3][3];
    constexpr float kEps = 1e-6f;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            R[i][j] = glm::dot(a.axes[i], b.axes[j]);
            absR[i][j] = std::fabs(R[i][j]) + kEps;
        }
    }
    const float t[3] = {glm::dot(d, a.axes[0]), glm::dot(d, a.axes[1]), glm::dot(d, a.axes[2])};
    const float ah[3] = {a.half.x, a.half.y, a.half.z};
    const float bh[3] = {b.half.x, b.half.y, b.half.z};

    for (int i = 0; i < 3; ++i) {  // a's face axes
        const float rb = bh[0] * absR[i][0] + bh[1] * absR[i][1] + bh[2] * absR[i][2];
        if (std::fabs(t[i]) > ah[i] + rb) return false;
    }
    for (int j = 0; j < 3; ++j) {  // b's face axes
        const float ra = ah[0] * absR[0][j] + ah[1] * absR[1][j] + ah[2] * absR[2][j];
        const float tj = t[0] * R[0][j] + t[1] * R[1][j] + t[2] * R[2][j];
        if (std::fabs(tj) > ra + bh[j]) return false;
    }
    for (int i = 0; i < 3; ++i) {  // edge x edge
        const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
        for (int j = 0; j < 3; ++j) {
            const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
            const float ra = ah[i1] * absR[i2][j] + ah[i2] * absR[i1][j];
            const float rb = bh[j1] * absR[i][j2] + bh[j2] * absR[i][j1];
            const float tl = t[i2] * R[i1][j] - t[i1] * R[i2][j];
            if (std::fabs(tl) > ra + rb) return false;
        }
    }
    return true;
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
