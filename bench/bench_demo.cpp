// Google Benchmark: the synthetic actor. Generating 10 minutes of takes (no
// file output) and generating + writing them (BVH text + ground-truth JSON).
#include <benchmark/benchmark.h>

#include <filesystem>

#include "fray/demo/demo_actor.h"
#include "fray/demo/library.h"

namespace {

void BM_DemoGenerate10Minutes(benchmark::State& state) {
    fray::demo::LibraryOptions opt;
    opt.minutes = 10.0;
    double seconds = 0;
    for (auto _ : state) {
        seconds = 0;
        for (const auto& spec : fray::demo::planLibrary(opt)) {
            auto take = fray::demo::generateTake(spec, fray::demo::takeSeed(opt.seed, spec.name));
            seconds += take.motion.duration();
            benchmark::DoNotOptimize(take);
        }
    }
    state.counters["motion_min"] = seconds / 60.0;
}
BENCHMARK(BM_DemoGenerate10Minutes)->Unit(benchmark::kMillisecond);

void BM_DemoWriteLibrary10Minutes(benchmark::State& state) {
    fray::demo::LibraryOptions opt;
    opt.minutes = 10.0;
    const auto dir = std::filesystem::temp_directory_path() / "fray_bench_demo";
    for (auto _ : state) {
        auto r = fray::demo::writeDemoLibrary(dir, opt);
        if (!r) state.SkipWithError(r.error().message.c_str());
    }
    std::filesystem::remove_all(dir);
}
BENCHMARK(BM_DemoWriteLibrary10Minutes)->Unit(benchmark::kMillisecond);

}  // namespace
