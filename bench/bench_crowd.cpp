// Composition at scale (issue 27): the 10,000-character domino demo
// (resources/demo/domino_crowd.json) composed, and crowds of such scenes
// composed and posed frame after frame.
#include <benchmark/benchmark.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <vector>

#if defined(__unix__)
#include <sys/resource.h>
#endif

#include "fray/core/motion.h"
#include "fray/render/image.h"
#include "fray/sim/compose.h"
#include "fray/sim/compose/domino.h"
#include "fray/sim/metrics.h"
#include "fray/sim/patches.h"
#include "fray/sim/patterns.h"
#include "sim/demo_world.h"
#include "sim/scene_crop.h"

namespace {

using namespace fray::sim;
using fray::test::demoWorld;

// CPU time of the whole process (every thread), seconds.
double processCpuSeconds() {
#if defined(__unix__)
    rusage usage{};
    if (getrusage(RUSAGE_SELF, &usage) == 0) {
        return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
               1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
    }
#endif
    return 0.0;
}

double peakMemoryMB() {
#if defined(__unix__)
    rusage usage{};
    if (getrusage(RUSAGE_SELF, &usage) == 0) return static_cast<double>(usage.ru_maxrss) / 1024.0;
#endif
    return 0.0;
}

// The demo's chain-fall patches (the fall-fall pattern), generated once.
const PatchLibrary& fallLibrary() {
    static const std::unique_ptr<PatchLibrary> lib = [] {
        auto out = std::make_unique<PatchLibrary>();
        for (const auto& p : defaultPatterns()) {
            if (p.name != "fall-fall") continue;
            if (auto st = generatePatches(demoWorld().library, p, PatternSet{}, *out); !st) throw std::runtime_error(st.error().message);
        }
        buildConnections(demoWorld().library, *out);
        return out;
    }();
    return *lib;
}

// resources/demo/domino_crowd.json with its painted area read as fray-cli reads it.
ComposeSpec crowdSpec() {
    const std::filesystem::path file = std::filesystem::path(FRAY_SOURCE_DIR) / "resources/demo/domino_crowd.json";
    std::ifstream in(file);
    std::stringstream text;
    text << in.rdbuf();
    auto spec = parseComposeSpec(text.str(), file.string(), fallLibrary());
    if (!spec) throw std::runtime_error(spec.error().message);
    auto* domino = spec->part<DominoSpec>();
    auto image = fray::render::readPng(file.parent_path() / domino->floorFile);
    if (!image) throw std::runtime_error(image.error().message);
    FloorBitmap& f = domino->floor;
    f.width = image->width, f.height = image->height;
    f.metresPerPixel = domino->metresPerPixel;
    f.origin = domino->floorOrigin;
    f.painted.assign(static_cast<std::size_t>(f.width) * static_cast<std::size_t>(f.height), 0);
    for (int y = 0; y < f.height; ++y) {
        for (int x = 0; x < f.width; ++x) {
            const std::uint8_t* px = image->pixel(x, y);
            const int luma = (299 * px[0] + 587 * px[1] + 114 * px[2]) / 1000;
            f.painted[static_cast<std::size_t>(y) * static_cast<std::size_t>(f.width) + static_cast<std::size_t>(x)] = px[3] >= 128 && luma <= 64;
        }
    }
    return std::move(*spec);
}

// The 10,000-character domino demo composed once per iteration. Counters:
// characters, chain falls, peak memory of the process, and the scene metrics
// on four 8 m x 8 m windows (penetration samples outside intended hits, foot
// skate: the metrics compare every pair of characters, too slow for all).
void BM_DominoCrowd(benchmark::State& state) {
    const auto& lib = demoWorld().library;
    const ComposeSpec spec = crowdSpec();
    ComposeStats st;
    Scene scene;
    for (auto _ : state) {
        auto composed = compose(lib, fallLibrary(), spec, &st);
        if (!composed) {
            state.SkipWithError(composed.error().message.c_str());
            return;
        }
        scene = std::move(*composed);
    }
    state.counters["characters"] = static_cast<double>(scene.characters.size());
    state.counters["chain_falls"] = st.part<DominoStats>()->chainFalls;
    state.counters["peak_MB"] = peakMemoryMB();
    int penetration = 0, windowCharacters = 0;
    double skateMax = 0, skateMean = 0;
    for (const glm::vec2 lo : {glm::vec2(-60, -60), glm::vec2(20, -50), glm::vec2(-50, 40), glm::vec2(50, 50)}) {
        const Scene window = fray::test::cropScene(scene, lib, lo, lo + glm::vec2(8.0f));
        const auto m = computeMetrics(window, lib);
        penetration += m.penetrationFrames;
        windowCharacters += static_cast<int>(window.characters.size());
        for (const auto& c : m.characters) {
            skateMax = std::max(skateMax, c.footSkateMax);
            skateMean += c.footSkateMean;
        }
    }
    state.counters["window_characters"] = windowCharacters;
    state.counters["window_penetration_frames"] = penetration;
    state.counters["window_skate_mean_cm"] = windowCharacters > 0 ? skateMean / windowCharacters : 0.0;
    state.counters["window_skate_max_cm"] = skateMax;
}
BENCHMARK(BM_DominoCrowd)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);

// Arg: characters, in scenes of the domino demo (its seed + k, 10,000
// characters each) composed in parallel and laid side by side 200 m apart;
// every frame poses every character (TBB over characters). Counters:
// compose_s (all scenes), fps = frames posed per second, fps_with_compose =
// frames per second when composition is spread over the scene's frames at
// 30 Hz (composition + posing).
void BM_CrowdComposeAndPose(benchmark::State& state) {
    const auto& lib = demoWorld().library;
    const int wanted = static_cast<int>(state.range(0));
    const ComposeSpec base = crowdSpec();
    const int perScene = base.part<DominoSpec>()->maxCharacters;
    const int count = (wanted + perScene - 1) / perScene;
    std::vector<Scene> scenes(static_cast<std::size_t>(count));
    std::vector<std::string> errors(static_cast<std::size_t>(count));
    (void)fallLibrary();  // generated once, before the clock starts
    const auto t0 = std::chrono::steady_clock::now();
    const double composeCpu0 = processCpuSeconds();
    tbb::parallel_for(0, count, [&](int k) {
        ComposeSpec spec = base;
        spec.seed = base.seed + static_cast<std::uint64_t>(k);
        auto scene = compose(lib, fallLibrary(), spec);
        if (!scene) {
            errors[static_cast<std::size_t>(k)] = scene.error().message;
            return;
        }
        const RootXf offset{glm::vec2(200.0f * static_cast<float>(k), 0.0f), 0.0};
        for (auto& c : scene->characters) {
            for (auto& inst : c.track) inst.root = offset * inst.root;
        }
        scenes[static_cast<std::size_t>(k)] = std::move(*scene);
    });
    const double composeSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double composeCpu = processCpuSeconds() - composeCpu0;
    for (const auto& e : errors) {
        if (!e.empty()) {
            state.SkipWithError(e.c_str());
            return;
        }
    }
    std::vector<std::unique_ptr<ScenePoser>> posers;
    std::vector<std::pair<int, int>> who;  // (scene, character)
    double duration = 0;
    for (int k = 0; k < count; ++k) {
        const auto& s = scenes[static_cast<std::size_t>(k)];
        posers.push_back(std::make_unique<ScenePoser>(s, lib));
        duration = std::max(duration, s.duration);
        for (int c = 0; c < static_cast<int>(s.characters.size()) && static_cast<int>(who.size()) < wanted; ++c) who.emplace_back(k, c);
    }
    double t = 0;
    std::int64_t frames = 0;
    const double cpu0 = processCpuSeconds();
    for (auto _ : state) {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, who.size(), 256), [&](const tbb::blocked_range<std::size_t>& r) {
            fray::Pose pose;
            for (std::size_t i = r.begin(); i != r.end(); ++i) {
                posers[static_cast<std::size_t>(who[i].first)]->pose(who[i].second, t, pose);
                benchmark::DoNotOptimize(pose.translations.data());
            }
        });
        t += 1.0 / 30.0;
        if (t > duration) t = 0;
        ++frames;
    }
    const double cpuPerFrame = frames > 0 ? (processCpuSeconds() - cpu0) / static_cast<double>(frames) : 0.0;
    const double sceneFrames = duration * 30.0;
    // CPU time of every thread a frame (posing) and of the composition spread
    // over the scene's frames: what a frame costs whatever else shares the
    // machine (on a loaded machine wall time is several times this).
    state.counters["pose_cpu_ms_per_frame"] = 1000.0 * cpuPerFrame;
    state.counters["compose_cpu_ms_per_frame"] = 1000.0 * composeCpu / sceneFrames;
    state.counters["characters"] = static_cast<double>(who.size());
    state.counters["compose_s"] = composeSeconds;
    state.counters["fps"] = benchmark::Counter(static_cast<double>(frames), benchmark::Counter::kIsRate);
    state.counters["compose_ms_per_frame"] = 1000.0 * composeSeconds / sceneFrames;
    state.counters["peak_MB"] = peakMemoryMB();
}
BENCHMARK(BM_CrowdComposeAndPose)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond)->UseRealTime();

// Posing alone, on one thread: every character of one composed domino crowd
// (10,000 people) posed per iteration, frame after frame. Its CPU time per
// frame is what posing costs whatever else shares the machine; 100,000
// characters are ten of these (the per-character cost does not depend on
// the scene), spread over the cores as BM_CrowdComposeAndPose does.
void BM_CrowdPoseOneThread(benchmark::State& state) {
    const auto& lib = demoWorld().library;
    auto scene = compose(lib, fallLibrary(), crowdSpec());
    if (!scene) {
        state.SkipWithError(scene.error().message.c_str());
        return;
    }
    const ScenePoser poser(*scene, lib);
    const int n = static_cast<int>(scene->characters.size());
    fray::Pose pose;
    double t = 0;
    for (auto _ : state) {
        for (int c = 0; c < n; ++c) {
            poser.pose(c, t, pose);
            benchmark::DoNotOptimize(pose.translations.data());
        }
        t += 1.0 / 30.0;
        if (t > scene->duration) t = 0;
    }
    state.counters["characters"] = n;
}
BENCHMARK(BM_CrowdPoseOneThread)->Unit(benchmark::kMillisecond);

}  // namespace
