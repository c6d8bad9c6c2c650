// Data-preparation benchmarks (issue targets in docs/BENCHMARKS.md):
// import + segment 7 min of 120 fps capture <= 2 s.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <filesystem>
#include <vector>

#include "fray/core/joint_guess.h"
#include "fray/io/import.h"
#include "fray/prep/contacts.h"
#include "fray/prep/segmentation.h"

namespace {

namespace fs = std::filesystem;

// The 120 fps CMU karate takes, sorted.
std::vector<fs::path> karateFiles() {
    std::vector<fs::path> out;
    const fs::path dir = fs::path(FRAY_SHARED_DIR) / "mocap" / "cmu135_karate";
    if (!fs::is_directory(dir)) return out;
    for (const auto& e : fs::directory_iterator(dir)) {
        if (e.path().extension() == ".bvh") out.push_back(e.path());
    }
    std::sort(out.begin(), out.end());
    return out;
}

// Reads the karate takes in turn (cycling) and concatenates them until 7 min
// at 120 fps, then computes signals, heuristic contacts and the segmentation.
// Reading is inside the timing: the target is "import + segment".
void BM_ImportSegment7Min120fps(benchmark::State& state) {
    const auto files = karateFiles();
    if (files.empty()) {
        state.SkipWithError("../shared/mocap/cmu135_karate not found");
        return;
    }
    const int target = 7 * 60 * 120;
    int actions = 0, frames = 0;
    for (auto _ : state) {
        fray::Motion all;
        for (std::size_t i = 0; all.frameCount() < target; ++i) {
            auto m = fray::loadMotion(files[i % files.size()]);
            if (!m) {
                state.SkipWithError(m.error().message.c_str());
                return;
            }
            if (all.frameCount() == 0) {
                all = std::move(*m);
            } else {
                auto joined = fray::concatenate(all, *m, true);
                if (!joined) {
                    state.SkipWithError(joined.error().message.c_str());
                    return;
                }
                all = std::move(*joined);
            }
        }
        const auto joints = fray::guessStandardJoints(all.skeleton());
        auto signals = fray::prep::computeSignals(all, joints);
        if (!signals) {
            state.SkipWithError(signals.error().message.c_str());
            return;
        }
        const auto contacts = fray::prep::heuristicContacts(*signals);
        const auto result = fray::prep::segment(*signals, contacts);
        actions = static_cast<int>(result.cuts.size()) + 1;
        frames = all.frameCount();
        benchmark::DoNotOptimize(result.cuts.data());
    }
    state.counters["frames"] = frames;
    state.counters["actions"] = actions;
}
BENCHMARK(BM_ImportSegment7Min120fps)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace
