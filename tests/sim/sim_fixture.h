#pragma once
// The demo project as the planners see it: demo takes (generated once per
// test binary), their ground-truth cuts and annotations, true foot contacts,
// the motion graph and the action library.
#include <gtest/gtest.h>

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "fray/demo/demo_actor.h"
#include "fray/demo/demo_project.h"
#include "fray/prep/motion_graph.h"
#include "fray/prep/pipeline.h"
#include "fray/sim/action_library.h"
#include "fray/sim/planner.h"
#include "fray/sim/spec.h"
#include "sim/demo_world.h"

namespace fray::test {

inline Result<sim::SceneSpec> parseSpec(const std::string& json) {
    return sim::parseSceneSpec(json, "spec.json", demoWorld().library, sim::builtinPresets());
}

inline Result<sim::Scene> runSpec(const std::string& json) {
    auto spec = parseSpec(json);
    if (!spec) return spec.error();
    return sim::simulate(demoWorld().library, demoWorld().project.combos, *spec);
}

// Successful (unblocked) blows landed by characters 0 and 1 of a duel.
inline std::array<int, 2> landedHits(const sim::Scene& scene) {
    std::array<int, 2> hits{0, 0};
    for (const auto& h : scene.hits) {
        if (!h.blocked && h.attacker >= 0 && h.attacker < 2) ++hits[static_cast<std::size_t>(h.attacker)];
    }
    return hits;
}

// Two boxers from one capture facing each other.
inline std::string duelSpec(int depthA, int depthB, std::uint64_t seed, double duration, const std::string& presetA = "general-boxer",
                            const std::string& presetB = "general-boxer", const std::string& motionA = "shadowbox_energetic",
                            const std::string& motionB = "shadowbox_energetic") {
    const std::string actions = R"(["@punch", "@kick", "@block", "@avoid", "@step", "@idle", "@transition", "@turn"])";
    return R"({"version": 1, "duration": )" + std::to_string(duration) + R"(, "seed": )" + std::to_string(seed) +
           R"(, "start_jitter": {"distance": 0.3, "angle_deg": 20}, "characters": [
      {"name": "a", "side": 0, "depth": )" + std::to_string(depthA) + R"(, "preset": ")" + presetA + R"(", "motions": [")" +
           motionA + R"("], "actions": )" + actions + R"(, "start": {"x": 0, "z": 0, "heading_deg": 90}},
      {"name": "b", "side": 1, "depth": )" + std::to_string(depthB) + R"(, "preset": ")" + presetB + R"(", "motions": [")" +
           motionB + R"("], "actions": )" + actions + R"(, "start": {"x": 1.2, "z": 0, "heading_deg": -90}}]})";
}

}  // namespace fray::test
