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
// 1 the direct dWorldStep, 2 QuickStep, 3 the hybrid of the two; 1 and 3
// with calm pairs as by default; 4 the hybrid without calm pairs, the
// default before them: Options::calmPairs). `first`:
// the first measured frame; the frames before it are simulated untimed.
void runPosture(benchmark::State& state, int first) {
    const auto scene = crowd(static_cast<int>(state.range(0)));
    const int frames = static_cast<int>(state.range(1));
    fray::posture::Options options;
    if (state.range(2) == 1) options.solver = fray::posture::Solver::Direct;
    if (state.range(2) == 2) options.solver = fray::posture::Solver::Iterative;
    if (state.range(2) == 3) options.solver = fray::posture::Solver::Hybrid;
    if (state.range(2) == 4) options.calmPairs = false;
    double produced = 0, cpu = 0, touching = 0;
    for (auto _ : state) {
        // BM_PosturePhysics times the construction (as it always did);
        // BM_PosturePhysicsContact does not.
        if (first > 1) state.PauseTiming();
        fray::posture::Simulator sim(scene, demoWorld().library, options);
        if (first <= 1) state.PauseTiming();
        sim.step();  // frame 0 places the bodies: not a simulated frame
        while (sim.frame() + 1 < first) sim.step();
        const auto before = sim.report();
        state.ResumeTiming();
        const std::clock_t start = std::clock();  // CPU time of the process, all threads
        for (int f = 0; f < frames; ++f) sim.step();
        cpu += static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
        produced += frames;
        benchmark::DoNotOptimize(sim.positions(0).data());
        const auto& report = sim.report();
        const auto iterative = static_cast<double>(report.iterativeSteps - before.iterativeSteps);
        const auto steps = static_cast<double>(report.directSteps - before.directSteps) + iterative;
        touching = steps > 0 ? iterative / steps : 0.0;
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

void BM_PosturePhysics(benchmark::State& state) { runPosture(state, 1); }

// The same crowd measured from frame `range(3)` on (the construction and the
// frames before it simulated untimed): a window of the duel where the pairs
// touch.
void BM_PosturePhysicsContact(benchmark::State& state) { runPosture(state, static_cast<int>(state.range(3))); }

// The crowd's first second has no contact between characters (quickstep_share
// 0): only free characters are measured (BM_PosturePhysicsContact below
// measures windows with contact); {2, 1200, *} is the whole 20 s duel, blows
// and all.
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
    ->Args({200, 60, 4})
    ->Args({1000, 30, 4})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Windows of the duel (per 60-frame window of {2, 60, 0, f}, the share of
// character-steps touching another character: 0 in frames 1-180, 85 % in
// 181-240, 18-20 % in 421-540, 97 % in 721-780, 18 % over the whole duel):
// 421-480 an exchange of blows touching as often as the duel's average (its
// first 30 frames do not touch: 60 frames for 1,000 characters too), 721-780
// a clinch where nearly every step touches (the worst case). Solver 4: the
// same without calm pairs, in the same binary.
BENCHMARK(BM_PosturePhysicsContact)
    ->Args({200, 60, 0, 421})
    ->Args({1000, 60, 0, 421})
    ->Args({200, 60, 0, 721})
    ->Args({1000, 60, 0, 721})
    ->Args({200, 60, 4, 421})
    ->Args({1000, 60, 4, 421})
    ->Args({200, 60, 4, 721})
    ->Args({1000, 60, 4, 721})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
