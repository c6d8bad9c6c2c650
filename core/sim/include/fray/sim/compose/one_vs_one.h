#pragma once
// One vs one (SPEC 4.5): two characters fight for the spec's duration, patch
// after patch. Its part of a compose spec (kind "one-vs-one"): nothing of its own.

namespace fray::sim {

struct OneVsOneSpec {
    static constexpr const char* kKind = "one-vs-one";
};

}  // namespace fray::sim
