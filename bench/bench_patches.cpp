// Interaction Patches benchmarks (SPEC 4; targets in docs/BENCHMARKS.md):
// patch-library generation per PatternList, opening the demo patch library
// file (tables stored) against rebuilding its tables (what every open cost
// before file version 4), and scene composition + pose sampling without
// rendering for 100, 1,000 and 10,000 characters.
#include <benchmark/benchmark.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <vector>

#include "fray/core/motion.h"
#include "fray/sim/compose.h"
#include "fray/sim/compose/one_vs_one.h"
#include "fray/sim/patches.h"
#include "fray/sim/patterns.h"
#include "sim/demo_world.h"

namespace {

using fray::test::demoWorld;
using namespace fray::sim;

const PatternList& patternAt(int i) {
    static const auto patterns = defaultPatterns();
    return patterns[static_cast<std::size_t>(i)];
}

// Arg 0: index in defaultPatterns(); arg 1: keep every path (1) or the best 3 of each (0).
void BM_GeneratePatches(benchmark::State& state) {
    const auto& lib = demoWorld().library;
    const PatternSet set;
    GenerateOptions opt;
    opt.keepPerPath = state.range(1) != 0 ? 0 : 3;
    double patches = 0, paths = 0;
    for (auto _ : state) {
        PatchLibrary out;
        auto st = generatePatches(lib, patternAt(static_cast<int>(state.range(0))), set, out, opt);
        if (!st) {
            state.SkipWithError(st.error().message.c_str());
            return;
        }
        buildConnections(lib, out);
        patches = static_cast<double>(out.patches().size());
        paths = static_cast<double>(out.stats().paths);
        benchmark::DoNotOptimize(out.temporal().size());
    }
    state.SetLabel(patternAt(static_cast<int>(state.range(0))).name);
    state.counters["patches"] = patches;
    state.counters["paths"] = paths;
}
BENCHMARK(BM_GeneratePatches)
    ->ArgsProduct({{0, 1, 2, 3}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->UseRealTime();

// The demo patch library as `fray-cli patches generate` makes it from the
// demo project (its PatternLists, else the defaults its actions can play),
// saved once to a file in the temporary folder.
const std::filesystem::path& demoPatchFile() {
    static const std::filesystem::path file = [] {
        const auto& world = demoWorld();
        auto set = projectPatterns(world.project, "demo.frayproj");
        if (!set) throw std::runtime_error(set.error().message);
        if (set->patterns.empty()) {
            for (auto& p : defaultPatterns()) {
                if (checkPattern(p, *set, world.library)) set->patterns.push_back(std::move(p));
            }
        }
        PatchLibrary out;
        for (const auto& p : set->patterns) {
            if (auto st = generatePatches(world.library, p, *set, out); !st) throw std::runtime_error(st.error().message);
        }
        buildConnections(world.library, out);
        const auto path = std::filesystem::temp_directory_path() / "fray_bench_demo.patches";
        if (auto st = savePatchLibrary(out, path); !st) throw std::runtime_error(st.error().message);
        return path;
    }();
    return file;
}

// Opening the demo patch library: read, checksum, patches and stored tables.
void BM_OpenPatchLibrary(benchmark::State& state) {
    const auto& lib = demoWorld().library;
    const auto& file = demoPatchFile();
    std::size_t links = 0;
    for (auto _ : state) {
        auto patches = loadPatchLibrary(file, lib);
        if (!patches) {
            state.SkipWithError(patches.error().message.c_str());
            return;
        }
        links = 0;
        for (const auto& row : patches->temporal()) links += row.size();
        benchmark::DoNotOptimize(links);
    }
    state.counters["patches"] = static_cast<double>(loadPatchLibrary(file, lib)->patches().size());
    state.counters["temporal_links"] = static_cast<double>(links);
    state.counters["file_MB"] = static_cast<double>(std::filesystem::file_size(file)) / 1e6;
}
BENCHMARK(BM_OpenPatchLibrary)->Unit(benchmark::kMillisecond)->UseRealTime();

// What opening cost before the file stored the tables: rebuilding them.
void BM_RebuildPatchTables(benchmark::State& state) {
    const auto& lib = demoWorld().library;
    auto loaded = loadPatchLibrary(demoPatchFile(), lib);
    if (!loaded) {
        state.SkipWithError(loaded.error().message.c_str());
        return;
    }
    const PatchLibrary loadedLib = std::move(*loaded);
    for (auto _ : state) {
        PatchLibrary copy = loadedLib;  // buildConnections replaces its tables
        buildConnections(lib, copy);
        benchmark::DoNotOptimize(copy.temporal().size());
    }
}
BENCHMARK(BM_RebuildPatchTables)->Unit(benchmark::kMillisecond)->UseRealTime();

// The fighting library the composition benchmark uses (generated once).
const PatchLibrary& fightLibrary() {
    static const std::unique_ptr<PatchLibrary> lib = [] {
        auto out = std::make_unique<PatchLibrary>();
        const PatternSet set;
        for (int i : {0, 1, 2}) (void)generatePatches(demoWorld().library, patternAt(i), set, *out);
        buildConnections(demoWorld().library, *out);
        return out;
    }();
    return *lib;
}

// Arg: characters. One-vs-one fights (pairs) composed with their own seeds
// and laid out on a grid 4 m apart; every frame poses every character.
// Counters: compose_s (all pairs, 20 s each), fps = frames posed per second,
// fps_with_compose = frames per second when composition is spread over the
// 600 frames of the 20 s scene.
void BM_ComposeAndPose(benchmark::State& state) {
    const auto& lib = demoWorld().library;
    const int characters = static_cast<int>(state.range(0));
    const int pairs = characters / 2;
    ComposeSpec spec = ComposeSpec::of(OneVsOneSpec{});
    spec.duration = 20;
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<Scene> scenes;
    scenes.reserve(static_cast<std::size_t>(pairs));
    const int side = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(pairs))));
    for (int k = 0; k < pairs; ++k) {
        spec.seed = static_cast<std::uint64_t>(k + 1);
        auto scene = compose(lib, fightLibrary(), spec);
        if (!scene) {
            state.SkipWithError(scene.error().message.c_str());
            return;
        }
        const RootXf offset{glm::vec2(4.0f * static_cast<float>(k % side), 4.0f * static_cast<float>(k / side)), 0.0};
        for (auto& c : scene->characters) {
            for (auto& inst : c.track) inst.root = offset * inst.root;
        }
        scenes.push_back(std::move(*scene));
    }
    const double composeSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::vector<std::unique_ptr<ScenePoser>> posers;
    for (const auto& s : scenes) posers.push_back(std::make_unique<ScenePoser>(s, lib));
    fray::Pose pose;
    double t = 0;
    std::int64_t frames = 0;
    for (auto _ : state) {
        for (const auto& p : posers) {
            for (int c = 0; c < 2; ++c) {
                p->pose(c, t, pose);
                benchmark::DoNotOptimize(pose.translations.data());
            }
        }
        t += 1.0 / 30.0;
        if (t > spec.duration) t = 0;
        ++frames;
    }
    state.counters["characters"] = 2.0 * pairs;
    state.counters["compose_s"] = composeSeconds;
    state.counters["fps"] = benchmark::Counter(static_cast<double>(frames), benchmark::Counter::kIsRate);
    state.counters["compose_ms_per_frame"] = 1000.0 * composeSeconds / 600.0;
}
BENCHMARK(BM_ComposeAndPose)->Arg(100)->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
