#pragma once
// What one frame shows, as plain data the caller fills every frame: posed
// characters and overlays. Nothing here refers to a planner type: a motion
// player, the CLI or the scene timeline all fill the same description.
//
// Everything is a non-owning view (spans, string_views, pointers): the caller
// keeps the data alive until Renderer::render / Presenter::present returns.
// Reusing the caller's vectors from frame to frame keeps the steady state free
// of allocations.
#include <cstdint>
#include <span>
#include <string_view>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "fray/core/skeleton.h"
#include "fray/render/camera.h"

namespace fray::render {

// One posed character. World joint transforms in the skeleton's joint order
// (e.g. from fray::forwardKinematics); the body mesh is built once per distinct
// skeleton and skinned on the GPU.
struct CharacterInstance {
    const Skeleton* skeleton = nullptr;
    std::span<const glm::vec3> jointPositions;  // world, metres, Y-up
    std::span<const glm::quat> jointRotations;  // world orientations (unit)
    glm::vec3 tint{0.75f, 0.75f, 0.75f};        // display (sRGB) colour, e.g. the team colour
    std::string_view label;                     // drawn above the head when non-empty (e.g. the current action)
    bool selected = false;                      // outline glow and a ring on the floor
};

// A polyline on (or above) the floor, e.g. a trajectory the characters follow.
struct Polyline {
    std::span<const glm::vec3> points;
    glm::vec4 color{1.0f, 0.8f, 0.2f, 0.9f};  // display colour + alpha
    float width = 0.06f;                       // metres
};

// A checkpoint on a trajectory: a ring on the floor and a post, optional label.
struct Checkpoint {
    glm::vec3 position{0.0f};
    glm::vec4 color{1.0f, 0.8f, 0.2f, 1.0f};
    float radius = 0.35f;
    std::string_view label;
};

// A hit or contact flash: a glowing disc facing the camera, drawn over the bodies.
struct Flash {
    glm::vec3 position{0.0f};
    float radius = 0.15f;
    glm::vec4 color{1.0f, 0.35f, 0.1f, 0.9f};
};

// An RGBA8 image laid on the floor rectangle [min, max] (x, z). Image rows run
// from min.z to max.z and columns from min.x to max.x, so it reads upright
// from the default camera (on +Z looking towards -Z). The texture is uploaded
// again only when the pointer, size or revision changes.
struct FloorBitmap {
    const std::uint8_t* rgba = nullptr;  // width * height * 4 bytes, row-major
    int width = 0;
    int height = 0;
    glm::vec2 min{-1.0f, -1.0f};
    glm::vec2 max{1.0f, 1.0f};
    float opacity = 1.0f;
    std::uint64_t revision = 0;  // bump when the pixels change in place
};

struct RenderSettings {
    bool shadows = true;
    bool grid = true;
    bool labels = true;
    glm::vec3 lightDirection{-0.45f, -1.0f, -0.35f};  // direction the light travels
    glm::vec3 clearColor{0.62f, 0.68f, 0.75f};         // display colour; the floor fades into it
    glm::vec3 floorColor{0.56f, 0.57f, 0.58f};
    glm::vec3 highlightColor{1.0f, 0.85f, 0.25f};      // selection
    int textScale = 0;                                 // pixels per font pixel; 0 picks from the height
};

struct FrameDescription {
    OrbitCamera camera;
    std::span<const CharacterInstance> characters;
    std::span<const Polyline> trajectories;
    std::span<const Checkpoint> checkpoints;
    std::span<const Flash> flashes;
    const FloorBitmap* floorBitmap = nullptr;
    RenderSettings settings;
};

// Bounds of the characters' joints (for framing and the shadow volume).
Bounds characterBounds(std::span<const CharacterInstance> characters);

}  // namespace fray::render
