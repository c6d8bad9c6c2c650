#pragma once
// Domino (SPEC 4.5): falling bodies knock the next people over inside a
// painted floor area. Its part of a compose spec (kind "domino") and of the compose stats.
#include <string>
#include <vector>

#include "fray/sim/scene.h"

namespace fray::sim {

// Where and when a domino chain starts: the person standing there falls first.
struct DominoStart {
    double time = 0;
    glm::vec2 pos{0.0f};
};

// The painted area (the CLI reads the bitmap file), the chains' starts (a
// letter each, with its own start time), people standing outside the area,
// and a cap on the crowd.
struct DominoSpec {
    static constexpr const char* kKind = "domino";
    std::string floorFile;
    double metresPerPixel = 0.1;
    glm::vec2 floorOrigin{0.0f};
    FloorBitmap floor;
    std::vector<DominoStart> starts;
    int background = 20;
    int maxCharacters = 400;
};

struct DominoStats {
    int chainFalls = 0;    // people knocked over by a falling body
    int spatialFalls = 0;  // of those, caused through a spatial connection of the faller's patch
    // Share of the painted area within kCoverRadius of where someone stood
    // and fell (sampled every 0.25 m); how much of the area the chains fill.
    double paintedCoverage = 0;
    // m: how far from the painted area bystanders stand (the longest fall
    // of a chain patch from where its person stood, plus the body's box).
    double bystanderClearance = 0;
    int bystanders = 0;  // of the spec's `background`, those standing (fewer when few cells are clear of every fall)
    static constexpr float kCoverRadius = 1.0f;
};

}  // namespace fray::sim
