#pragma once
// The one-joint body kinds (rat, bag, box, ball), shared by the scene file's
// reader (scene_file.cpp) and the creatures' skeletons and keys (scene.cpp).
#include <string_view>

#include "fray/sim/scene.h"

namespace fray::sim::detail {

// The one-joint body kinds this build knows: length along +Z (the end site)
// and the root's height above the floor when the keys give none.
struct BodyKind {
    std::string_view name;
    float length, height;
};
// "box": the long box two carriers hold in the Interaction Graph's carrying
// (fray/igraph/carry.h): its root at one carrier's grip, 1.6 m (the demo
// pair's grip span) to the other's.
inline constexpr float kCarryBoxLength = 1.6f;
inline constexpr BodyKind kBodyKinds[] = {{"rat", kRatLength, kRatHeight},
                                   {"bag", kBagLength, 0.0f},
                                   {"box", kCarryBoxLength, 0.0f},
                                   {"ball", kBallLength, 1.0f}};

inline const BodyKind* bodyKind(std::string_view name) {
    for (const auto& k : kBodyKinds) {
        if (k.name == name) return &k;
    }
    return nullptr;
}

}  // namespace fray::sim::detail
