#pragma once
// CPU side of the overlays: every overlay kind becomes triangles in one of
// three groups, drawn in order after the bodies:
//   Depth   world space, depth-tested (trajectories, checkpoints, selection rings)
//   OnTop   world space, drawn over everything (hit/contact flashes)
//   Screen  pixels, drawn over everything (labels)
// Vectors are reused from frame to frame, so the steady state does not allocate.
#include <array>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "fray/render/frame.h"

namespace fray::render {

struct OverlayVertex {
    glm::vec3 position;
    glm::vec2 uv;
    std::uint32_t color;  // RGBA8, display colour
    std::uint32_t mode;   // OverlayMode
};
static_assert(sizeof(OverlayVertex) == 28);

enum class OverlayMode : std::uint32_t { Solid = 0, Disc = 1, Glyph = 2, Blob = 3 };
enum class OverlayGroup : int { Depth = 0, OnTop = 1, Screen = 2 };

std::uint32_t packColor(glm::vec4 c);

// A character's label waiting for its place (buildOverlays stacks labels
// that would cover each other): anchored above the head at (x, anchorY); y
// is where the box's bottom edge goes.
struct PendingLabel {
    float x = 0, y = 0, anchorY = 0;
    float halfWidth = 0, height = 0;  // of the box, padding included
    std::string_view text;
    bool selected = false;
    int index = 0;  // order of arrival (character order), for a deterministic sort
};

// Moves labels up until none covers another: the selected one keeps its
// place, then the others from the bottom of the screen up, each above any
// placed box it would cover. Past kMaxStackedLabels they are only sorted.
inline constexpr std::size_t kMaxStackedLabels = 256;
void stackLabels(std::vector<PendingLabel>& labels);

class OverlayBuilder {
public:
    void clear();
    // Reused storage for buildOverlays' labels (no allocation in steady state).
    std::vector<PendingLabel>& scratchLabels() { return labels_; }
    const std::vector<OverlayVertex>& group(OverlayGroup g) const { return groups_[static_cast<std::size_t>(g)]; }
    std::size_t vertexCount() const;

    void ribbon(OverlayGroup g, std::span<const glm::vec3> points, float width, glm::vec4 color, float lift);
    void ring(OverlayGroup g, glm::vec3 center, float inner, float outer, glm::vec4 color, int segments = 40);
    // Quad centred at c spanned by halfRight and halfUp; uv from (-1,-1) to (1,1).
    void quad(OverlayGroup g, glm::vec3 c, glm::vec3 halfRight, glm::vec3 halfUp, glm::vec4 color, OverlayMode mode);
    void triangle(OverlayGroup g, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec4 color);
    // Appends `count` quads' vertices (6 each) for the caller to fill with
    // writeQuad, from several threads if it likes; returns the first.
    OverlayVertex* appendQuads(OverlayGroup g, std::size_t count);
    static void writeQuad(OverlayVertex* at, glm::vec3 c, glm::vec3 halfRight, glm::vec3 halfUp, glm::vec4 color,
                          OverlayMode mode);
    // Screen group, pixels (x right, y down).
    void rect(float x0, float y0, float x1, float y1, glm::vec4 color);
    void text(float x, float y, std::string_view text, int scale, glm::vec4 color);

private:
    std::vector<OverlayVertex>& out(OverlayGroup g) { return groups_[static_cast<std::size_t>(g)]; }
    std::array<std::vector<OverlayVertex>, 3> groups_;
    std::vector<PendingLabel> labels_;
};

// Text scale used for a viewport height when the settings leave it to the renderer.
int autoTextScale(int viewportHeight);

// Builds every overlay of a frame (the selection rings and labels come from
// the characters). blobShadows: a soft dark disc on the floor under each
// character, offset away from the sun (the Fast quality's shadows).
// characterBounds: each character's joint bounds when the caller has them
// (the renderer computes them for culling), else empty.
void buildOverlays(const FrameDescription& frame, const glm::mat4& viewProj, glm::vec2 viewport, bool blobShadows,
                   OverlayBuilder& out, std::span<const Bounds> characterBounds = {});

}  // namespace fray::render
