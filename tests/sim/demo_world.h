#pragma once
// The demo project as the planners see it, built in memory (no files): the
// demo takes of seed 1, their ground-truth cuts and annotations, true foot
// contacts, the motion graph and the action library. Built once per process
// (and the football set's, for the football scene).
// Shared by the tree-expansion tests and benchmarks.
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "fray/core/joint_guess.h"
#include "fray/demo/demo_actor.h"
#include "fray/demo/demo_project.h"
#include "fray/prep/motion_graph.h"
#include "fray/prep/pipeline.h"
#include "fray/sim/action_library.h"

namespace fray::test {

struct DemoWorld {
    prep::Project project;
    std::vector<prep::LoadedMotion> motions;
    prep::MotionGraph graph;
    sim::ActionLibrary library;
};

// The world of one demo library set ("default" or "football").
inline std::unique_ptr<DemoWorld> buildDemoWorld(const std::string& set) {
    auto w = std::make_unique<DemoWorld>();
    demo::LibraryOptions options;
    options.seed = 1;
    options.set = set;
    std::vector<demo::ProjectTake> takes;
    for (const auto& spec : demo::planLibrary(options)) {
        auto take = demo::generateTake(spec, demo::takeSeed(options.seed, spec.name));
        prep::LoadedMotion m;
        m.id = take.truth.take;
        m.joints = guessStandardJoints(take.motion.skeleton());
        m.contacts.left = take.truth.leftContact;
        m.contacts.right = take.truth.rightContact;
        m.motion = std::move(take.motion);
        takes.push_back({take.truth, spec.name + ".bvh"});
        w->motions.push_back(std::move(m));
    }
    w->project = demo::makeDemoProject(takes);
    std::vector<const Motion*> ptrs;
    std::vector<StandardJoints> joints;
    for (const auto& m : w->motions) ptrs.push_back(&m.motion), joints.push_back(m.joints);
    const auto refs = sim::projectActionRefs(w->project);
    prep::GraphOptions graphOptions;
    if (w->project.settings.graphThreshold) graphOptions.threshold = *w->project.settings.graphThreshold;
    auto graph = prep::buildMotionGraph(ptrs, joints, refs, graphOptions);
    if (!graph) throw std::runtime_error(graph.error().message);
    w->graph = std::move(*graph);
    auto lib = sim::buildActionLibrary(w->project, w->motions, w->graph);
    if (!lib) throw std::runtime_error(lib.error().message);
    w->library = std::move(*lib);
    return w;
}

inline const DemoWorld& demoWorld() {
    static const std::unique_ptr<DemoWorld> world = buildDemoWorld("default");
    return *world;
}

// The football set: runs, cuts and tackles (the football scene).
inline const DemoWorld& footballWorld() {
    static const std::unique_ptr<DemoWorld> world = buildDemoWorld("football");
    return *world;
}

}  // namespace fray::test
