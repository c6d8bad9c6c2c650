#include "fray/render/camera.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

namespace fray::render {

void Bounds::add(glm::vec3 p) {
    min = glm::min(min, p);
    max = glm::max(max, p);
}

void Bounds::add(const Bounds& other) {
    if (other.empty()) return;
    add(other.min);
    add(other.max);
}

float Bounds::radius() const { return empty() ? 0.0f : glm::length(max - min) * 0.5f; }

glm::mat4 perspectiveVk(float fovY, float aspect, float nearPlane, float farPlane) {
    const float f = 1.0f / std::tan(fovY * 0.5f);
    glm::mat4 m(0.0f);
    m[0][0] = f / aspect;
    m[1][1] = -f;  // Vulkan clip y points down
    m[2][2] = farPlane / (nearPlane - farPlane);
    m[2][3] = -1.0f;
    m[3][2] = nearPlane * farPlane / (nearPlane - farPlane);
    return m;
}

glm::mat4 orthoVk(float left, float right, float bottom, float top, float nearPlane, float farPlane) {
    glm::mat4 m(1.0f);
    m[0][0] = 2.0f / (right - left);
    m[1][1] = -2.0f / (top - bottom);
    m[2][2] = -1.0f / (farPlane - nearPlane);
    m[3][0] = -(right + left) / (right - left);
    m[3][1] = (top + bottom) / (top - bottom);
    m[3][2] = -nearPlane / (farPlane - nearPlane);
    return m;
}

std::optional<glm::vec3> projectToPixel(const glm::mat4& viewProj, glm::vec3 world, glm::vec2 viewportSize) {
    const glm::vec4 clip = viewProj * glm::vec4(world, 1.0f);
    if (clip.w <= 1e-6f) return std::nullopt;
    const glm::vec3 ndc = glm::vec3(clip) / clip.w;
    return glm::vec3((ndc.x * 0.5f + 0.5f) * viewportSize.x, (ndc.y * 0.5f + 0.5f) * viewportSize.y, ndc.z);
}

glm::vec3 OrbitCamera::forward() const {
    const float cp = std::cos(pitch);
    return -glm::vec3(cp * std::sin(yaw), std::sin(pitch), cp * std::cos(yaw));
}

glm::vec3 OrbitCamera::eye() const { return target - forward() * distance; }

glm::vec3 OrbitCamera::right() const { return glm::vec3(std::cos(yaw), 0.0f, -std::sin(yaw)); }

glm::vec3 OrbitCamera::up() const { return glm::cross(right(), forward()); }

glm::mat4 OrbitCamera::view() const { return glm::lookAt(eye(), target, glm::vec3(0.0f, 1.0f, 0.0f)); }

glm::mat4 OrbitCamera::projection(float aspect) const {
    return perspectiveVk(fovY, aspect > 0.0f ? aspect : 1.0f, nearPlane, farPlane);
}

void OrbitCamera::orbit(float dYaw, float dPitch) {
    yaw = std::remainder(yaw + dYaw, 2.0f * 3.14159265358979f);
    pitch = std::clamp(pitch + dPitch, -kMaxPitch, kMaxPitch);
}

void OrbitCamera::pan(float dxPixels, float dyPixels, float viewportHeight) {
    if (viewportHeight <= 0.0f) return;
    // World size of one pixel at the target's depth.
    const float perPixel = 2.0f * distance * std::tan(fovY * 0.5f) / viewportHeight;
    // Dragging right moves the scene right, i.e. the target left; dragging
    // down (pixel y grows) moves the scene down, i.e. the target up.
    target += (-right() * dxPixels + up() * dyPixels) * perPixel;
}

void OrbitCamera::zoom(float factor) {
    if (!(factor > 0.0f)) return;
    distance = std::clamp(distance * factor, kMinDistance, kMaxDistance);
}

void OrbitCamera::frame(const Bounds& bounds, float aspect, float margin) {
    if (bounds.empty()) return;
    target = bounds.center();
    const float r = std::max(bounds.radius(), 0.1f) * margin;
    const float halfY = fovY * 0.5f;
    const float halfX = std::atan(std::tan(halfY) * (aspect > 0.0f ? aspect : 1.0f));
    const float half = std::min(halfX, halfY);
    distance = std::clamp(r / std::sin(half), kMinDistance, kMaxDistance);
    farPlane = std::max(farPlane, distance + 4.0f * r);
}

}  // namespace fray::render
