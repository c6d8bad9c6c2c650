#pragma once
// One vs many (SPEC 4.5): the main character meets enemies one after another,
// each entering from outside, patch after patch. Its part of a compose spec.

namespace fray::sim {

struct OneVsManySpec {
    int enemies = 10;  // how many come in turn
};

}  // namespace fray::sim
