// Camera maths: projection conventions, orbit/pan/zoom behaviour, framing.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/geometric.hpp>

#include "fray/render/camera.h"

namespace fray::render {
namespace {

constexpr float kPi = 3.14159265358979f;
const glm::vec2 kViewport(640.0f, 480.0f);

glm::vec3 pixelOf(const OrbitCamera& cam, glm::vec3 p) {
    auto px = projectToPixel(cam.viewProjection(kViewport.x / kViewport.y), p, kViewport);
    EXPECT_TRUE(px.has_value());
    return px.value_or(glm::vec3(-1e9f));
}

TEST(Camera, DefaultLooksDownMinusZFromAbove) {
    OrbitCamera cam;
    cam.pitch = 0.0f;
    EXPECT_NEAR(cam.eye().x, 0.0f, 1e-6f);
    EXPECT_NEAR(cam.eye().z, cam.distance, 1e-5f);
    EXPECT_NEAR(glm::dot(cam.forward(), glm::vec3(0, 0, -1)), 1.0f, 1e-6f);
    EXPECT_NEAR(glm::dot(cam.right(), glm::vec3(1, 0, 0)), 1.0f, 1e-6f);
    EXPECT_NEAR(glm::dot(cam.up(), glm::vec3(0, 1, 0)), 1.0f, 1e-6f);
}

TEST(Camera, BasisIsOrthonormalAtAnyAngle) {
    OrbitCamera cam;
    for (float yaw : {-2.5f, 0.0f, 0.7f, 3.0f})
        for (float pitch : {-1.2f, 0.0f, 0.4f, 1.5f}) {
            cam.yaw = yaw;
            cam.pitch = pitch;
            EXPECT_NEAR(glm::length(cam.forward()), 1.0f, 1e-5f);
            EXPECT_NEAR(glm::length(cam.right()), 1.0f, 1e-5f);
            EXPECT_NEAR(glm::length(cam.up()), 1.0f, 1e-5f);
            EXPECT_NEAR(glm::dot(cam.forward(), cam.right()), 0.0f, 1e-5f);
            EXPECT_NEAR(glm::dot(cam.forward(), cam.up()), 0.0f, 1e-5f);
            EXPECT_NEAR(glm::length(cam.eye() - cam.target), cam.distance, 1e-4f);
        }
}

TEST(Camera, TargetProjectsToTheCentreAndUpIsUpOnScreen) {
    OrbitCamera cam;
    cam.yaw = 0.6f;
    cam.pitch = 0.3f;
    const glm::vec3 c = pixelOf(cam, cam.target);
    EXPECT_NEAR(c.x, 320.0f, 1e-3f);
    EXPECT_NEAR(c.y, 240.0f, 1e-3f);
    EXPECT_GT(c.z, 0.0f);
    EXPECT_LT(c.z, 1.0f);
    // Vulkan pixels grow downwards: a point above the target is higher on screen.
    EXPECT_LT(pixelOf(cam, cam.target + glm::vec3(0, 0.5f, 0)).y, c.y);
    // Camera right is screen right.
    EXPECT_GT(pixelOf(cam, cam.target + cam.right() * 0.5f).x, c.x);
}

TEST(Camera, DepthIsZeroAtNearAndOneAtFar) {
    const glm::mat4 p = perspectiveVk(1.0f, 1.5f, 0.1f, 100.0f);
    auto depth = [&](float z) {
        const glm::vec4 c = p * glm::vec4(0, 0, -z, 1);
        return c.z / c.w;
    };
    EXPECT_NEAR(depth(0.1f), 0.0f, 1e-5f);
    EXPECT_NEAR(depth(100.0f), 1.0f, 1e-5f);
    EXPECT_LT(depth(1.0f), depth(2.0f));
    // Behind the camera: no pixel.
    OrbitCamera cam;
    EXPECT_FALSE(projectToPixel(cam.viewProjection(1.0f), cam.eye() - cam.forward(), kViewport).has_value());
}

TEST(Camera, OrthoMapsTheBoxToClipSpace) {
    const glm::mat4 o = orthoVk(-2, 2, -1, 1, 0.5f, 10.5f);
    const glm::vec4 a = o * glm::vec4(-2, -1, -0.5f, 1);
    const glm::vec4 b = o * glm::vec4(2, 1, -10.5f, 1);
    EXPECT_NEAR(a.x, -1.0f, 1e-6f);
    EXPECT_NEAR(a.y, 1.0f, 1e-6f);  // bottom of the box at the bottom of the image (y down)
    EXPECT_NEAR(a.z, 0.0f, 1e-6f);
    EXPECT_NEAR(b.x, 1.0f, 1e-6f);
    EXPECT_NEAR(b.y, -1.0f, 1e-6f);
    EXPECT_NEAR(b.z, 1.0f, 1e-6f);
}

TEST(Camera, OrbitTurnsAboutTheTargetAndClampsPitch) {
    OrbitCamera cam;
    cam.target = glm::vec3(1, 1, -2);
    const float d = cam.distance;
    cam.orbit(kPi * 0.5f, 0.0f);
    EXPECT_NEAR(glm::length(cam.eye() - cam.target), d, 1e-4f);
    EXPECT_NEAR(cam.eye().x - cam.target.x, d * std::cos(cam.pitch), 1e-4f);  // a quarter turn puts the eye on +X
    cam.orbit(0.0f, 10.0f);
    EXPECT_FLOAT_EQ(cam.pitch, OrbitCamera::kMaxPitch);
    cam.orbit(0.0f, -20.0f);
    EXPECT_FLOAT_EQ(cam.pitch, -OrbitCamera::kMaxPitch);
    cam.orbit(7.0f * kPi, 0.0f);  // yaw stays in (-pi, pi]
    EXPECT_LE(std::abs(cam.yaw), kPi + 1e-5f);
}

TEST(Camera, PanKeepsThePointUnderTheCursor) {
    OrbitCamera cam;
    cam.yaw = -0.4f;
    cam.pitch = 0.5f;
    cam.target = glm::vec3(2, 1, 3);
    // A point at the target's depth, 100 px right and 50 px below the centre.
    const glm::vec3 p = cam.target + cam.right() * 0.8f - cam.up() * 0.4f;
    const glm::vec3 before = pixelOf(cam, p);
    cam.pan(37.0f, -21.0f, kViewport.y);
    const glm::vec3 after = pixelOf(cam, p);
    EXPECT_NEAR(after.x - before.x, 37.0f, 0.05f);
    EXPECT_NEAR(after.y - before.y, -21.0f, 0.05f);
}

TEST(Camera, ZoomScalesDistanceWithinLimits) {
    OrbitCamera cam;
    cam.distance = 10.0f;
    cam.zoom(0.5f);
    EXPECT_FLOAT_EQ(cam.distance, 5.0f);
    cam.zoom(1e-6f);
    EXPECT_FLOAT_EQ(cam.distance, OrbitCamera::kMinDistance);
    cam.zoom(1e9f);
    EXPECT_FLOAT_EQ(cam.distance, OrbitCamera::kMaxDistance);
    const float d = cam.distance;
    cam.zoom(0.0f);   // ignored
    cam.zoom(-2.0f);  // ignored
    EXPECT_FLOAT_EQ(cam.distance, d);
}

TEST(Camera, FrameFitsTheBoxInBothDirections) {
    for (float aspect : {0.5f, 1.0f, 16.0f / 9.0f}) {
        OrbitCamera cam;
        cam.yaw = 0.9f;
        cam.pitch = 0.25f;
        Bounds b;
        b.add(glm::vec3(4, 0, -1));
        b.add(glm::vec3(7, 1.8f, 2));
        cam.frame(b, aspect);
        EXPECT_NEAR(glm::length(cam.target - b.center()), 0.0f, 1e-5f);
        const glm::vec2 vp(480.0f * aspect, 480.0f);
        const glm::mat4 vpm = cam.viewProjection(aspect);
        for (int i = 0; i < 8; ++i) {
            const glm::vec3 corner((i & 1) ? b.max.x : b.min.x, (i & 2) ? b.max.y : b.min.y, (i & 4) ? b.max.z : b.min.z);
            auto px = projectToPixel(vpm, corner, vp);
            ASSERT_TRUE(px.has_value());
            EXPECT_GE(px->x, 0.0f);
            EXPECT_LE(px->x, vp.x);
            EXPECT_GE(px->y, 0.0f);
            EXPECT_LE(px->y, vp.y);
        }
    }
    // An empty box leaves the camera alone.
    OrbitCamera cam;
    const OrbitCamera before = cam;
    cam.frame(Bounds{}, 1.0f);
    EXPECT_EQ(cam.target, before.target);
    EXPECT_EQ(cam.distance, before.distance);
}

TEST(Camera, BoundsCentreAndRadius) {
    Bounds b;
    EXPECT_TRUE(b.empty());
    EXPECT_EQ(b.radius(), 0.0f);
    b.add(glm::vec3(-1, 0, 0));
    b.add(glm::vec3(1, 2, 0));
    EXPECT_FALSE(b.empty());
    EXPECT_EQ(b.center(), glm::vec3(0, 1, 0));
    EXPECT_NEAR(b.radius(), std::sqrt(2.0f), 1e-6f);
}

}  // namespace
}  // namespace fray::render
