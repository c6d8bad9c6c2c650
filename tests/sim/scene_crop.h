#pragma once
// A window of a large composed scene, for the scene metrics (whose body test
// looks at every pair of characters, too slow for ten thousand): the
// characters that first stand inside the floor rectangle [lo, hi], and the
// hits between them, renumbered (or any subset of the characters). Catches
// and marks are left out.
#include <vector>

#include "fray/sim/action_library.h"
#include "fray/sim/scene.h"

namespace fray::test {

// The characters for which keep(index, character) holds, and the hits between them.
template <class Keep>
sim::Scene cropSceneTo(const sim::Scene& scene, Keep&& keep) {
    sim::Scene out;
    out.duration = scene.duration;
    out.seed = scene.seed;
    std::vector<int> index(scene.characters.size(), -1);
    for (std::size_t c = 0; c < scene.characters.size(); ++c) {
        const auto& ch = scene.characters[c];
        if (!keep(static_cast<int>(c), ch)) continue;
        index[c] = static_cast<int>(out.characters.size());
        out.characters.push_back(ch);
        out.characters.back().opponent = -1;
    }
    for (auto& ch : out.characters) {
        if (ch.holder >= 0) ch.holder = index[static_cast<std::size_t>(ch.holder)];  // a ball whose holder is left out: nobody's
    }
    for (const auto& h : scene.hits) {
        const int a = index[static_cast<std::size_t>(h.attacker)], d = index[static_cast<std::size_t>(h.defender)];
        if (a < 0 || d < 0) continue;
        sim::HitEvent k = h;
        k.attacker = a, k.defender = d;
        out.hits.push_back(k);
    }
    return out;
}

inline sim::Scene cropScene(const sim::Scene& scene, const sim::ActionLibrary& lib, glm::vec2 lo, glm::vec2 hi) {
    return cropSceneTo(scene, [&](int, const sim::SceneCharacter& ch) {
        if (ch.track.empty()) return false;  // creatures: keyed, not cropped
        const auto& first = ch.track.front();
        const glm::vec2 p = first.placementAt(lib, first.offset).pos;
        return p.x >= lo.x && p.y >= lo.y && p.x <= hi.x && p.y <= hi.y;
    });
}

}  // namespace fray::test
