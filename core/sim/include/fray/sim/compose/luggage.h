#pragma once
// Luggage (SPEC 4.5): porters passing one item along, each recycled after
// handing it on. Its part of a compose spec (kind "luggage").

namespace fray::sim {

struct LuggageSpec {
    static constexpr const char* kKind = "luggage";
    int porters = 4;
    int handoffs = 8;
};

}  // namespace fray::sim
