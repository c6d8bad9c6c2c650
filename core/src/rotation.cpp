#include "fray/core/rotation.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace fray {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

// Axis indices (first, second, third) of an order, and whether it is an even
// permutation of XYZ.
struct OrderAxes {
    int i, j, k;
    double parity;  // +1 even (XYZ, YZX, ZXY), -1 odd
};

OrderAxes axesOf(RotationOrder order) {
    switch (order) {
        case RotationOrder::XYZ: return {0, 1, 2, 1.0};
        case RotationOrder::YZX: return {1, 2, 0, 1.0};
        case RotationOrder::ZXY: return {2, 0, 1, 1.0};
        case RotationOrder::XZY: return {0, 2, 1, -1.0};
        case RotationOrder::YXZ: return {1, 0, 2, -1.0};
        case RotationOrder::ZYX: return {2, 1, 0, -1.0};
    }
    return {2, 0, 1, 1.0};
}

glm::dquat axisQuat(int axis, double radians) {
    const double h = radians * 0.5;
    glm::dquat q(std::cos(h), 0.0, 0.0, 0.0);
    q[axis] = std::sin(h);  // glm::quat indexes x, y, z, w
    return q;
}

// Row-major 3x3 rotation matrix of a unit quaternion: m[row][col].
std::array<std::array<double, 3>, 3> toMatrix(const glm::dquat& q) {
    const double x = q.x, y = q.y, z = q.z, w = q.w;
    return {{{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
             {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
             {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}}};
}

}  // namespace

glm::quat eulerToQuat(const glm::dvec3& degreesXYZ, RotationOrder order) {
    const OrderAxes a = axesOf(order);
    const glm::dquat q = axisQuat(a.i, degreesXYZ[a.i] * kDeg) * axisQuat(a.j, degreesXYZ[a.j] * kDeg) *
                         axisQuat(a.k, degreesXYZ[a.k] * kDeg);
    return glm::quat(q);
}

glm::quat eulerToQuatFast(const glm::dvec3& degreesXYZ, RotationOrder order) {
    const OrderAxes a = axesOf(order);
    auto axis = [](int ax, double degrees) {
        const float h = static_cast<float>(degrees * (kDeg * 0.5));
        glm::quat q(std::cos(h), 0.0f, 0.0f, 0.0f);
        q[ax] = std::sin(h);
        return q;
    };
    return axis(a.i, degreesXYZ[a.i]) * axis(a.j, degreesXYZ[a.j]) * axis(a.k, degreesXYZ[a.k]);
}

glm::dvec3 quatToEuler(const glm::dquat& qIn, RotationOrder order) {
    // R = Ri(a) Rj(b) Rk(c). For an even permutation m[i][k] = sin(b); odd flips signs.
    const OrderAxes ax = axesOf(order);
    const glm::dquat q = glm::normalize(qIn);
    const auto m = toMatrix(q);
    const int i = ax.i, j = ax.j, k = ax.k;
    const double s = ax.parity;
    const double sb = std::clamp(s * m[i][k], -1.0, 1.0);
    double a = 0, b = std::asin(sb), c = 0;
    // The general formulas stay accurate until cos(b) is at rounding level.
    if (std::abs(sb) < 1.0 - 1e-12) {
        a = std::atan2(-s * m[j][k], m[k][k]);
        c = std::atan2(-s * m[i][j], m[i][i]);
    } else {
        // Gimbal lock: only a +- c is defined; put it all in a.
        const glm::dquat rest = q * glm::inverse(axisQuat(j, b));
        const auto n = toMatrix(rest);
        a = std::atan2(s * n[k][j], n[j][j]);
        c = 0.0;
    }
    glm::dvec3 out(0.0);
    out[i] = a / kDeg;
    out[j] = b / kDeg;
    out[k] = c / kDeg;
    return out;
}

glm::dvec3 nearestEquivalentEuler(const glm::dvec3& e, const glm::dvec3& previous, RotationOrder order) {
    const int middle = axesOf(order).j;
    auto near = [](double v, double target) { return v - 360.0 * std::round((v - target) / 360.0); };
    glm::dvec3 plain, mirrored;
    for (int a = 0; a < 3; ++a) {
        plain[a] = near(e[a], previous[a]);
        // Ri(a) Rj(b) Rk(c) = Ri(a + 180) Rj(180 - b) Rk(c + 180).
        mirrored[a] = near(a == middle ? 180.0 - e[a] : e[a] + 180.0, previous[a]);
    }
    auto distance = [&](const glm::dvec3& v) {
        const glm::dvec3 d = glm::abs(v - previous);
        return d.x + d.y + d.z;
    };
    return distance(mirrored) < distance(plain) ? mirrored : plain;
}

}  // namespace fray
