#pragma once
// Floor placements and oriented boxes: the geometry the planners share
// (SPEC 2.1: per-body-segment bounding boxes for collision and hit tests).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace fray::sim {

// Wraps an angle to (-pi, pi].
inline double wrapAngle(double a) {
    constexpr double kTwoPi = 2.0 * std::numbers::pi;
    // fmod returns a unchanged inside (-2pi, 2pi): skip the call there (the
    // common case: sums of two wrapped angles), same result bit for bit.
    if (!(a > -kTwoPi && a < kTwoPi)) a = std::fmod(a, kTwoPi);
    if (a <= -std::numbers::pi) a += kTwoPi;
    if (a > std::numbers::pi) a -= kTwoPi;
    return a;
}

// Unit vector on the floor for a heading (rad about +Y, 0 = facing +Z), the
// convention of prep::headingOf.
inline glm::vec2 headingVector(double heading) {
    return {static_cast<float>(std::sin(heading)), static_cast<float>(std::cos(heading))};
}

// Heading of a floor direction (x, z): the inverse of headingVector.
inline double angleOf(glm::vec2 v) { return std::atan2(static_cast<double>(v.x), static_cast<double>(v.y)); }

// Distance on the floor from p to the segment a-b.
inline double distanceToSegment(glm::vec2 p, glm::vec2 a, glm::vec2 b) {
    const glm::vec2 ab = b - a;
    const float len2 = glm::dot(ab, ab);
    const float t = len2 > 0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0f, 1.0f) : 0.0f;
    return glm::length(p - (a + t * ab));
}

namespace detail {
// Cosine and sine of a heading. The planners place bodies at a few headings
// many times over (every candidate of a node against the same opponent), so
// the last ones are remembered per thread, keyed by the exact bits: the same
// values as computing them, at a fraction of the cost of sincos.
struct CosSin {
    std::uint64_t bits = ~std::uint64_t{0};  // a NaN pattern std::cos never caches
    float c = 1.0f, s = 0.0f;
};
inline const CosSin& cosSin(double heading) {
    thread_local std::array<CosSin, 256> cache;
    std::uint64_t bits;
    std::memcpy(&bits, &heading, sizeof bits);
    CosSin& e = cache[static_cast<std::size_t>((bits * 0x9E3779B97F4A7C15ull) >> 56)];
    if (e.bits != bits) e = {bits, static_cast<float>(std::cos(heading)), static_cast<float>(std::sin(heading))};
    return e;
}
}  // namespace detail

// A heading's rotation on the floor, its sine and cosine computed once.
struct FloorRotation {
    float c = 1.0f, s = 0.0f;
    explicit FloorRotation(double heading) {
        const auto& e = detail::cosSin(heading);
        c = e.c;
        s = e.s;
    }
    glm::vec2 operator()(glm::vec2 v) const { return {c * v.x + s * v.y, -s * v.x + c * v.y}; }
    glm::vec3 operator()(const glm::vec3& d) const {
        const glm::vec2 p = (*this)(glm::vec2(d.x, d.z));
        return {p.x, d.y, p.y};
    }
};

// Rotates a floor vector (x, z) by a heading.
inline glm::vec2 rotateFloor(glm::vec2 v, double heading) { return FloorRotation(heading)(v); }

// A placement on the floor: position (x, z) and heading. Actions are stored
// relative to their first frame's placement; a timeline places them in the
// world by composing.
struct RootXf {
    glm::vec2 pos{0.0f};
    double heading = 0.0;

    // this ∘ local: local is expressed in this placement's frame.
    RootXf operator*(const RootXf& local) const {
        return {pos + rotateFloor(local.pos, heading), wrapAngle(heading + local.heading)};
    }
    glm::vec2 apply(glm::vec2 local) const { return pos + rotateFloor(local, heading); }
    glm::vec3 apply(const glm::vec3& local) const {
        const glm::vec2 p = apply(glm::vec2(local.x, local.z));
        return {p.x, local.y, p.y};
    }
    glm::vec3 applyDirection(const glm::vec3& d) const {
        const glm::vec2 p = rotateFloor(glm::vec2(d.x, d.z), heading);
        return {p.x, d.y, p.y};
    }
    RootXf inverse() const {
        const double h = -heading;
        return {-rotateFloor(pos, h), wrapAngle(h)};
    }
    friend bool operator==(const RootXf&, const RootXf&) = default;
};

// Linear blend of placements (shortest way round for the heading).
inline RootXf lerp(const RootXf& a, const RootXf& b, double t) {
    return {a.pos + (b.pos - a.pos) * static_cast<float>(t), wrapAngle(a.heading + wrapAngle(b.heading - a.heading) * t)};
}

// Oriented box: centre, orthonormal axes (columns) and half extents along them.
struct Obb {
    glm::vec3 centre{0.0f};
    glm::mat3 axes{1.0f};
    glm::vec3 half{0.0f};
    // Radius of the bounding sphere, for a cheap first test.
    float radius() const { return std::sqrt(half.x * half.x + half.y * half.y + half.z * half.z); }
    Obb placed(const RootXf& xf) const;
    // The same with the placement's rotation already computed.
    Obb placed(const RootXf& xf, const FloorRotation& rotate) const;
    // placed(xf, rotate).centre alone: a bounding-sphere test needs no axes.
    glm::vec3 placedCentre(const RootXf& xf, const FloorRotation& rotate) const {
        return rotate(centre) + glm::vec3(xf.pos.x, 0.0f, xf.pos.y);
    }
    Obb shrunk(float factor) const { return {centre, axes, half * factor}; }
};

// Half extents (x, z) on the floor of the axis-aligned box around an oriented box.
inline glm::vec2 floorHalfExtents(const Obb& b) {
    glm::vec2 h(0.0f);
    for (int k = 0; k < 3; ++k) {
        h.x += std::fabs(b.axes[k].x) * b.half[k];
        h.y += std::fabs(b.axes[k].z) * b.half[k];
    }
    return h;
}

// Separating-axis test of two oriented boxes (15 axes). Touching counts.
bool overlaps(const Obb& a, const Obb& b);
// The same after the caller's own bounding-sphere test passed.
bool overlapsBeyondSpheres(const Obb& a, const Obb& b);
// overlapsBeyondSpheres with box a given by its centre, its half extents and
// axis(i) -> a's i-th axis, asked for only when a test needs it (a caller
// can place a's axes lazily). The axes are tried in the order that
// separates the planner's bodies soonest (a's third axis, the depth of a
// segment box, separates about half of them); each test is the same float
// computation in any order, so the answer is that of any order.
template <class AxisOfA>
bool overlapsBeyondSpheresWith(const glm::vec3& aCentre, AxisOfA&& axis, const glm::vec3& aHalf, const Obb& b) {
    const glm::vec3 d = b.centre - aCentre;
    // R[i][j] = a.axis i . b.axis j, in a's frame; epsilon guards parallel edges.
    float R[3][3], absR[3][3], t[3];
    constexpr float kEps = 1e-6f;
    const float ah[3] = {aHalf.x, aHalf.y, aHalf.z};
    const float bh[3] = {b.half.x, b.half.y, b.half.z};
    for (int i = 2; i >= 0; --i) {  // a's face axes, each with its row of R
        const glm::vec3& ai = axis(i);
        for (int j = 0; j < 3; ++j) {
            R[i][j] = glm::dot(ai, b.axes[j]);
            absR[i][j] = std::fabs(R[i][j]) + kEps;
        }
        t[i] = glm::dot(d, ai);
        const float rb = bh[0] * absR[i][0] + bh[1] * absR[i][1] + bh[2] * absR[i][2];
        if (std::fabs(t[i]) > ah[i] + rb) return false;
    }
    for (int j = 2; j >= 0; --j) {  // b's face axes
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

// Box around the segment p0 -> p1 with the given cross-section half sizes
// (side, depth) and pad added beyond both ends. `side` is a hint for the
// cross-section's first axis (e.g. the character's right), projected off the
// segment axis.
Obb segmentBox(const glm::vec3& p0, const glm::vec3& p1, float halfSide, float halfDepth, float pad,
               const glm::vec3& side);

}  // namespace fray::sim
