// Posture synthesis speed (issue 25; targets in docs/BENCHMARKS.md): N
// characters with physics on, simulation only (no metrics, no rendering).
// The crowd is the README duel repeated on a grid 5 m apart, so every pair
// is its own island. Counter fps = frames (1/60 s of scene each) produced per
// wall-clock second; fps_per_core = frames per CPU-second of all threads.
#include <benchmark/benchmark.h>

#include <cmath>
#include <ctime>
#include <string>

#include "fray/posture/posture.h"
#include "posture/posture_fixture.h"

namespace {

using fray::test::demoWorld;

fray::sim::Scene crowd(int characters) {
    static const fray::sim::Scene duel = fray::test::plannedScene(FRAY_SOURCE_DIR "/resources/demo/duel.json");
    return fray::test::pairCrowd(duel, characters);
}

// Args: characters, frames simulated per iteration, solver (0 the default,
// 1 the direct dWorldStep, 2 QuickStep, 3 the hybrid of the two).
void BM_PosturePhysics(benchmark::State& state) {
    const auto scene = crowd(static_cast<int>(state.range(0)));
    const int frames = static_cast<int>(state.range(1));
    fray::posture::Options options;
    if (state.range(2) == 1) options.solver = fray::posture::Solver::Direct;
    if (state.range(2) == 2) options.solver = fray::posture::Solver::Iterative;
    if (state.range(2) == 3) options.solver = fray::posture::Solver::Hybrid;
    double produced = 0, cpu = 0, touching = 0;
    for (auto _ : state) {
        fray::posture::Simulator sim(scene, demoWorld().library, options);
        state.PauseTiming();
        sim.step();  // frame 0 places the bodies: not a simulated frame
        state.ResumeTiming();
        const std::clock_t start = std::clock();  // CPU time of the process, all threads
        for (int f = 0; f < frames; ++f) sim.step();
        cpu += static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
        produced += frames;
        benchmark::DoNotOptimize(sim.positions(0).data());
        const auto& report = sim.report();
        const double steps = static_cast<double>(report.directSteps + report.iterativeSteps);
        touching = steps > 0 ? static_cast<double>(report.iterativeSteps) / steps : 0.0;
    }
    state.counters["fps"] = benchmark::Counter(produced, benchmark::Counter::kIsRate);
    state.counters["characters"] = static_cast<double>(state.range(0));
    // Frames per CPU-second of all threads: what one free core would give
    // (on the shared VM the wall clock also counts the other builds).
    state.counters["fps_per_core"] = cpu > 0 ? produced / cpu : 0.0;
    // Share of character-steps solved by QuickStep: all with it, none with the
    // direct solver, those touching another character with the hybrid.
    state.counters["quickstep_share"] = touching;
}

// The crowd's first second has no contact between characters (quickstep_share
// 0); {2, 1200, *} is the whole 20 s duel, blows and all.
BENCHMARK(BM_PosturePhysics)
    ->Args({2, 120, 0})
    ->Args({2, 1200, 0})
    ->Args({2, 1200, 1})
    ->Args({2, 1200, 2})
    ->Args({200, 60, 0})
    ->Args({1000, 30, 0})
    ->Args({200, 60, 1})
    ->Args({1000, 30, 1})
    ->Args({200, 60, 2})
    ->Args({1000, 30, 2})
    ->Args({200, 60, 3})
    ->Args({1000, 30, 3})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
