#pragma once
// The demo library as motion-graph input: every ground-truth action of the six
// demo takes (fighting preset), built once per test binary.
#include <gtest/gtest.h>

#include <vector>

#include "fray/prep/motion_graph.h"
#include "prep/prep_fixture.h"

namespace fray::test {

struct DemoGraphInput {
    std::vector<const DemoTake*> takes;       // by motion index
    std::vector<const Motion*> motions;
    std::vector<StandardJoints> joints;
    std::vector<prep::ActionRef> actions;     // take order, then time order
    std::vector<const prep::FootContacts*> contacts;  // truth, by motion index
};

inline const DemoGraphInput& demoGraphInput() {
    static const DemoGraphInput input = [] {
        DemoGraphInput in;
        for (const auto& [name, take] : demoTakes()) {
            const int m = static_cast<int>(in.motions.size());
            in.takes.push_back(&take);
            in.motions.push_back(&take.take.motion);
            in.joints.push_back(take.joints);
            in.contacts.push_back(&take.truthContacts);
            for (const auto& a : take.take.truth.actions) in.actions.push_back({m, a.firstFrame, a.lastFrame});
        }
        return in;
    }();
    return input;
}

// The graph of all demo actions with default options (built once).
inline const prep::MotionGraph& demoGraph() {
    static const prep::MotionGraph graph = [] {
        const DemoGraphInput& in = demoGraphInput();
        auto g = prep::buildMotionGraph(in.motions, in.joints, in.actions, prep::GraphOptions{});
        if (!g) ADD_FAILURE() << g.error().message;
        return g ? std::move(*g) : prep::MotionGraph{};
    }();
    return graph;
}

}  // namespace fray::test
