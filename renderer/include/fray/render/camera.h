#pragma once
// Viewport camera: an orbit camera around a target point, and the projection
// maths for Vulkan clip space (y down, depth 0..1). Pure GLM, no Vulkan, so it
// is unit-tested without a device.
#include <optional>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace fray::render {

// Axis-aligned box; empty until something is added.
struct Bounds {
    glm::vec3 min{1e30f};
    glm::vec3 max{-1e30f};

    bool empty() const { return min.x > max.x; }
    void add(glm::vec3 p);
    void add(const Bounds& other);
    glm::vec3 center() const { return (min + max) * 0.5f; }
    float radius() const;  // of the enclosing sphere; 0 when empty
};

// Right-handed perspective for Vulkan: camera looks down -Z, clip y points down
// (so world up is screen up), depth 0 at near and 1 at far.
glm::mat4 perspectiveVk(float fovY, float aspect, float nearPlane, float farPlane);
// Orthographic box for Vulkan (y down, depth 0..1 between nearPlane and farPlane).
glm::mat4 orthoVk(float left, float right, float bottom, float top, float nearPlane, float farPlane);

// World point -> pixel (x right, y down, origin at the top-left corner) and
// depth 0..1; nullopt when behind the camera.
std::optional<glm::vec3> projectToPixel(const glm::mat4& viewProj, glm::vec3 world, glm::vec2 viewportSize);

struct OrbitCamera {
    glm::vec3 target{0.0f, 1.0f, 0.0f};
    float yaw = 0.0f;          // radians about +Y; 0 puts the eye on +Z looking towards -Z
    float pitch = 0.35f;       // radians above the horizon (positive looks down on the target)
    float distance = 6.0f;     // eye to target, metres
    float fovY = 0.7854f;      // 45 degrees
    float nearPlane = 0.05f;
    float farPlane = 500.0f;

    static constexpr float kMaxPitch = 1.5533f;  // 89 degrees: never look straight down the up axis
    static constexpr float kMinDistance = 0.2f;
    static constexpr float kMaxDistance = 400.0f;

    glm::vec3 eye() const;
    glm::vec3 forward() const;  // unit vector from the eye to the target
    glm::vec3 right() const;    // unit, horizontal
    glm::vec3 up() const;       // unit, completes the view basis
    glm::mat4 view() const;
    glm::mat4 projection(float aspect) const;
    glm::mat4 viewProjection(float aspect) const { return projection(aspect) * view(); }

    // Mouse-style controls. Orbit turns about the target (pitch clamped);
    // pan moves the target in the view plane so that a point at the target's
    // depth under the cursor stays under the cursor when it moves by
    // (dx, dy) pixels; zoom multiplies the distance (factor < 1 moves closer).
    void orbit(float dYaw, float dPitch);
    void pan(float dxPixels, float dyPixels, float viewportHeight);
    void zoom(float factor);
    // Frames a box: the target moves to its centre and the distance makes its
    // enclosing sphere fit the view (both fields of view) with a margin.
    void frame(const Bounds& bounds, float aspect, float margin = 1.1f);
};

}  // namespace fray::render
