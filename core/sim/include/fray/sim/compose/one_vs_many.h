#pragma once
// One vs many (SPEC 4.5): the main character meets enemies one after another,
// each entering from outside, patch after patch. Its part of a compose spec (kind "one-vs-many").

namespace fray::sim {

struct OneVsManySpec {
    static constexpr const char* kKind = "one-vs-many";
    int enemies = 10;  // how many come in turn
    // Main characters, each fighting its own `enemies` (issue 27): the fights
    // are composed side by side, fight k with seed + k, named "fight-K/...".
    int mains = 1;
};

}  // namespace fray::sim
