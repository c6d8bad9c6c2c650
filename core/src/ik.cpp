#include "fray/core/ik.h"

#include <algorithm>
#include <cmath>

namespace fray {
namespace {

// Shortest rotation taking direction a to direction b.
glm::dquat rotationBetween(const glm::dvec3& a, const glm::dvec3& b) {
    const double la = glm::length(a), lb = glm::length(b);
    if (la < 1e-12 || lb < 1e-12) return {1, 0, 0, 0};
    const glm::dvec3 u = a / la, v = b / lb;
    const double c = glm::dot(u, v);
    if (c < -1.0 + 1e-12) {
        // Opposite: any axis perpendicular to u.
        glm::dvec3 axis = glm::cross(u, glm::dvec3(1, 0, 0));
        if (glm::length(axis) < 1e-6) axis = glm::cross(u, glm::dvec3(0, 1, 0));
        return glm::angleAxis(glm::pi<double>(), glm::normalize(axis));
    }
    const glm::dvec3 w = glm::cross(u, v);
    return glm::normalize(glm::dquat(1.0 + c, w.x, w.y, w.z));
}

}  // namespace

TwoBoneSolution solveTwoBone(const glm::vec3& rootF, const glm::vec3& midF, const glm::vec3& endF,
                             const glm::vec3& targetF) {
    const glm::dvec3 root(rootF), mid(midF), end(endF), target(targetF);
    const double l1 = glm::length(mid - root);
    const double l2 = glm::length(end - mid);
    TwoBoneSolution out;
    const glm::dvec3 toTarget = target - root;
    const double want = glm::length(toTarget);
    if (l1 < 1e-9 || l2 < 1e-9 || want < 1e-9) {
        out.reached = want < 1e-9 && std::abs(l1 - l2) < 1e-9;
        return out;
    }
    // Keep a sliver of bend so the knee direction stays defined.
    const double lo = std::abs(l1 - l2) + 1e-6, hi = (l1 + l2) * (1.0 - 1e-6);
    const double d = std::clamp(want, lo, hi);
    out.reached = std::abs(d - want) < 1e-5;
    const glm::dvec3 u = toTarget / want;
    // Bend plane: the current knee, taken perpendicular to the root-target line.
    glm::dvec3 pole = (mid - root) - glm::dot(mid - root, u) * u;
    if (glm::length(pole) < 1e-9) {
        // Straight chain along the target line: any perpendicular will do.
        pole = glm::cross(u, glm::dvec3(1, 0, 0));
        if (glm::length(pole) < 1e-6) pole = glm::cross(u, glm::dvec3(0, 0, 1));
    }
    pole = glm::normalize(pole);
    const double along = (l1 * l1 - l2 * l2 + d * d) / (2.0 * d);
    const double across = std::sqrt(std::max(0.0, l1 * l1 - along * along));
    const glm::dvec3 newMid = root + along * u + across * pole;
    const glm::dvec3 newEnd = root + d * u;
    const glm::dquat q1 = rotationBetween(mid - root, newMid - root);
    const glm::dquat q2 = rotationBetween(q1 * (end - mid), newEnd - newMid);
    out.upper = glm::quat(q1);
    out.lower = glm::quat(q2);
    return out;
}

bool applyTwoBoneIk(const Skeleton& skeleton, std::span<glm::quat> local, std::span<const glm::vec3> worldPos,
                    std::span<const glm::quat> worldRot, int upper, int mid, int end, const glm::vec3& target,
                    const glm::quat* endWorldRotation) {
    const auto u = static_cast<std::size_t>(upper), m = static_cast<std::size_t>(mid),
               e = static_cast<std::size_t>(end);
    const TwoBoneSolution s = solveTwoBone(worldPos[u], worldPos[m], worldPos[e], target);
    auto parentWorld = [&](std::size_t j) {
        const int p = skeleton.parents[j];
        return p < 0 ? glm::quat(1, 0, 0, 0) : worldRot[static_cast<std::size_t>(p)];
    };
    // upper's parent is not moved; mid's and end's parents are moved by upper
    // (and end's by lower too), since they lie below upper / mid.
    const glm::quat pu = parentWorld(u);
    local[u] = glm::normalize(glm::inverse(pu) * s.upper * worldRot[u]);
    const glm::quat pm = s.upper * parentWorld(m);
    local[m] = glm::normalize(glm::inverse(pm) * s.lower * s.upper * worldRot[m]);
    const glm::quat pe = s.lower * s.upper * parentWorld(e);
    const glm::quat endWorld = endWorldRotation ? *endWorldRotation : s.lower * s.upper * worldRot[e];
    local[e] = glm::normalize(glm::inverse(pe) * endWorld);
    return s.reached;
}

}  // namespace fray
