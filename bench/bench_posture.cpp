// Posture synthesis speed (issue 25; targets in docs/BENCHMARKS.md): N
// characters with physics on, simulation only (no metrics, no rendering).
// The crowd is the README duel repeated on a grid 5 m apart, so every pair
// is its own island. Counter fps = frames (1/60 s of scene each) produced per
// wall-clock second.
#include <benchmark/benchmark.h>

#include <cmath>
#include <string>

#include "fray/posture/posture.h"
#include "posture/posture_fixture.h"

namespace {

using fray::test::demoWorld;

fray::sim::Scene crowd(int characters) {
    static const fray::sim::Scene duel = fray::test::plannedScene(FRAY_SOURCE_DIR "/resources/demo/duel.json");
    fray::sim::Scene out = duel;
    out.characters.clear();
    out.hits.clear();
    const int pairs = (characters + 1) / 2;
    const int side = static_cast<int>(std::ceil(std::sqrt(pairs)));
    for (int p = 0; p < pairs; ++p) {
        const glm::vec2 at(5.0f * static_cast<float>(p % side), 5.0f * static_cast<float>(p / side));
        const int base = static_cast<int>(out.characters.size());
        for (int k = 0; k < 2 && base + k < characters; ++k) {
            auto c = duel.characters[static_cast<std::size_t>(k)];
            c.name += std::to_string(p);
            for (auto& inst : c.track) inst.root.pos += at;
            out.characters.push_back(std::move(c));
        }
        for (auto h : duel.hits) {
            if (base + 1 >= characters) break;
            h.attacker += base, h.defender += base;
            out.hits.push_back(h);
        }
    }
    return out;
}

// Args: characters, frames simulated per iteration.
void BM_PosturePhysics(benchmark::State& state) {
    const auto scene = crowd(static_cast<int>(state.range(0)));
    const int frames = static_cast<int>(state.range(1));
    double produced = 0;
    for (auto _ : state) {
        fray::posture::Simulator sim(scene, demoWorld().library, {});
        state.PauseTiming();
        sim.step();  // frame 0 places the bodies: not a simulated frame
        state.ResumeTiming();
        for (int f = 0; f < frames; ++f) sim.step();
        produced += frames;
        benchmark::DoNotOptimize(sim.positions(0).data());
    }
    state.counters["fps"] = benchmark::Counter(produced, benchmark::Counter::kIsRate);
    state.counters["characters"] = static_cast<double>(state.range(0));
}

BENCHMARK(BM_PosturePhysics)->Args({2, 120})->Args({200, 60})->Args({1000, 30})->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
