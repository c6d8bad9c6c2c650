#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <utility>

#include "fray/core/rotation.h"

using namespace fray;

namespace {
float quatDistance(const glm::quat& a, const glm::quat& b) {
    return 1.0f - std::abs(glm::dot(glm::normalize(a), glm::normalize(b)));
}
}  // namespace

TEST(Rotation, EveryOrderRoundTrips) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> deg(-179.0, 179.0);
    for (auto order : {RotationOrder::XYZ, RotationOrder::XZY, RotationOrder::YXZ, RotationOrder::YZX, RotationOrder::ZXY,
                       RotationOrder::ZYX}) {
        for (int i = 0; i < 2000; ++i) {
            const glm::dvec3 e(deg(rng), deg(rng) * 0.5, deg(rng));
            const glm::quat q = eulerToQuat(e, order);
            const glm::dvec3 back = quatToEuler(glm::dquat(q), order);
            const glm::quat q2 = eulerToQuat(back, order);
            ASSERT_LT(quatDistance(q, q2), 1e-6f) << toString(order) << " " << e.x << " " << e.y << " " << e.z;
        }
    }
}

TEST(Rotation, OrderMatchesChannelSequence) {
    // ZXY: R = Rz * Rx * Ry. Check against explicit composition.
    const glm::quat rz = glm::angleAxis(glm::radians(30.0f), glm::vec3(0, 0, 1));
    const glm::quat rx = glm::angleAxis(glm::radians(40.0f), glm::vec3(1, 0, 0));
    const glm::quat ry = glm::angleAxis(glm::radians(50.0f), glm::vec3(0, 1, 0));
    EXPECT_LT(quatDistance(eulerToQuat({40, 50, 30}, RotationOrder::ZXY), rz * rx * ry), 1e-7f);
    EXPECT_LT(quatDistance(eulerToQuat({40, 50, 30}, RotationOrder::XYZ), rx * ry * rz), 1e-7f);
    EXPECT_LT(quatDistance(eulerToQuat({40, 50, 30}, RotationOrder::YZX), ry * rz * rx), 1e-7f);
}

TEST(Rotation, GimbalLockStillRoundTrips) {
    // The middle axis of each order at +-90 degrees is the lock; only a +- c is defined there.
    const std::pair<RotationOrder, int> middle[] = {{RotationOrder::XYZ, 1}, {RotationOrder::XZY, 2},
                                                    {RotationOrder::YXZ, 0}, {RotationOrder::YZX, 2},
                                                    {RotationOrder::ZXY, 0}, {RotationOrder::ZYX, 1}};
    for (const auto& [order, axis] : middle) {
        for (double lock : {90.0, -90.0}) {
            glm::dvec3 e(30, -20, 45);
            e[axis] = lock;
            const glm::quat q = eulerToQuat(e, order);
            const glm::dvec3 back = quatToEuler(glm::dquat(q), order);
            EXPECT_NEAR(std::abs(back[axis]), 90.0, 1e-3) << toString(order);
            const glm::dquat d = glm::inverse(glm::dquat(q)) * glm::dquat(eulerToQuat(back, order));
            const double angle = 2.0 * std::atan2(glm::length(glm::dvec3(d.x, d.y, d.z)), std::abs(d.w));
            EXPECT_LT(angle, 1e-5) << toString(order) << " lock " << lock;
        }
    }
}
