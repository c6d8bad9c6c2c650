// Google Benchmark: the action-level motion graph (SPEC 1.5) and transitions.
// Target: the graph of 300 actions in under 1 s on the 2-core CI machine.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <vector>

#include "fray/core/joint_guess.h"
#include "fray/demo/demo_actor.h"
#include "fray/io/import.h"
#include "fray/prep/motion_graph.h"
#include "fray/prep/transition.h"

namespace {

struct GraphInput {
    std::vector<fray::Motion> motions;
    std::vector<const fray::Motion*> ptrs;
    std::vector<fray::StandardJoints> joints;
    std::vector<fray::prep::ActionRef> actions;
    std::vector<fray::prep::FootContacts> contacts;
};

void finish(GraphInput& in) {
    for (auto& m : in.motions) {
        in.ptrs.push_back(&m);
        in.joints.push_back(fray::guessStandardJoints(m.skeleton()));
    }
}

// 300 ground-truth actions of the demo library, spread over all its takes.
const GraphInput& demoInput() {
    static const GraphInput input = [] {
        GraphInput in;
        fray::demo::LibraryOptions options;
        std::vector<fray::prep::ActionRef> all;
        for (const auto& spec : fray::demo::planLibrary(options)) {
            fray::demo::Take take = fray::demo::generateTake(spec, fray::demo::takeSeed(options.seed, spec.name));
            const int m = static_cast<int>(in.motions.size());
            for (const auto& a : take.truth.actions) all.push_back({m, a.firstFrame, a.lastFrame});
            in.contacts.push_back({take.truth.leftContact, take.truth.rightContact});
            in.motions.push_back(std::move(take.motion));
        }
        for (std::size_t i = 0; i < 300; ++i) in.actions.push_back(all[i * all.size() / 300]);
        finish(in);
        return in;
    }();
    return input;
}

// 300 one-second windows of real captures (LAFAN1), a harder case: the
// windows start and end mid-movement, so K grows much larger.
const GraphInput& lafanInput() {
    static const GraphInput input = [] {
        GraphInput in;
        const std::filesystem::path shared = FRAY_SHARED_DIR;
        for (const char* file : {"lafan1/walk4_subject1.bvh", "lafan1/multipleActions1_subject1.bvh",
                                 "lafan1/pushAndFall1_subject1.bvh"}) {
            auto m = fray::loadMotion(shared / "mocap" / file);
            if (m) in.motions.push_back(std::move(*m));
        }
        for (std::size_t i = 0; i < in.motions.size() && in.actions.size() < 300; ++i) {
            const int window = static_cast<int>(std::lround(in.motions[i].fps()));
            for (int f = 0; f + window <= in.motions[i].frameCount() && in.actions.size() < 300; f += window)
                in.actions.push_back({static_cast<int>(i), f, f + window - 1});
        }
        finish(in);
        return in;
    }();
    return input;
}

void runGraph(benchmark::State& state, const GraphInput& in) {
    if (in.actions.size() < 300) {
        state.SkipWithError("not enough actions (shared captures missing?)");
        return;
    }
    fray::prep::GraphOptions options;
    int nodes = 0;
    double scc = 0.0;
    for (auto _ : state) {
        auto g = fray::prep::buildMotionGraph(in.ptrs, in.joints, in.actions, options);
        if (!g) {
            state.SkipWithError(g.error().message.c_str());
            return;
        }
        nodes = g->stats.nodes;
        scc = g->stats.sccShare;
        benchmark::DoNotOptimize(g);
    }
    state.counters["actions"] = static_cast<double>(in.actions.size());
    state.counters["nodes"] = nodes;
    state.counters["scc_share"] = scc;
}

void BM_MotionGraph300Actions(benchmark::State& state) { runGraph(state, demoInput()); }
BENCHMARK(BM_MotionGraph300Actions)->Unit(benchmark::kMillisecond);

void BM_MotionGraph300RealWindows(benchmark::State& state) { runGraph(state, lafanInput()); }
BENCHMARK(BM_MotionGraph300RealWindows)->Unit(benchmark::kMillisecond);

// One transition (blend + foot locking) between two demo actions of ~1 s.
void BM_JoinActions(benchmark::State& state) {
    const GraphInput& in = demoInput();
    const auto& a = in.actions[10];
    const auto& b = in.actions[200];
    const auto ma = static_cast<std::size_t>(a.motion), mb = static_cast<std::size_t>(b.motion);
    for (auto _ : state) {
        auto j = fray::prep::joinActions(*in.ptrs[ma], in.joints[ma], a, &in.contacts[ma], *in.ptrs[mb],
                                         in.joints[mb], b, &in.contacts[mb]);
        benchmark::DoNotOptimize(j);
    }
    state.SetLabel(std::to_string(a.lastFrame - a.firstFrame + 1) + " + " +
                   std::to_string(b.lastFrame - b.firstFrame + 1) + " frames");
}
BENCHMARK(BM_JoinActions)->Unit(benchmark::kMicrosecond);

}  // namespace
