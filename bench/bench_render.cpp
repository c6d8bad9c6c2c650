// Google Benchmark: offscreen frame time of the Vulkan renderer at 1280x720
// in both qualities for crowds of demo characters, on whatever
// device the loader offers (lavapipe on the CI machine; FRAY_VULKAN_DEVICE=cpu
// forces it). Poses come from a generated shadow-boxing take, pre-posed, so the
// time is the renderer's: uploading instances and palettes, the shadow pass,
// the main pass (bodies, floor, overlays) and waiting for the device.
//
//   build/bin/fray-bench --benchmark_filter=Render
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <memory>
#include <vector>

#include "fray/core/kinematics.h"
#include "fray/demo/demo_actor.h"
#include "fray/render/motion_stage.h"
#include "fray/render/renderer.h"

namespace {

using namespace fray;
using namespace fray::render;

constexpr int kPosedFrames = 48;

// One device and a set of pre-posed frames for every benchmark of this file.
struct RenderBench {
    std::shared_ptr<VulkanDevice> device;
    std::string error;
    demo::Take take;
    std::vector<std::vector<glm::vec3>> positions;  // [frame][joint], root moved to the origin
    std::vector<std::vector<glm::quat>> rotations;

    static RenderBench& get() {
        static RenderBench b;
        return b;
    }

private:
    RenderBench() {
        auto d = VulkanDevice::create(DeviceOptions{});
        if (!d) {
            error = d.error().message;
            return;
        }
        device = *d;
        take = demo::generateTake({"bench", demo::TakeKind::ShadowBoxing, demo::Style::Energetic, 10.0}, 7);
        const Motion& m = take.motion;
        const auto jc = static_cast<std::size_t>(m.jointCount());
        for (int k = 0; k < kPosedFrames; ++k) {
            const int f = (k * 11) % m.frameCount();
            std::vector<glm::vec3> p(jc);
            std::vector<glm::quat> r(jc);
            worldTransforms(m, f, p, r);
            const glm::vec3 root(p[0].x, 0.0f, p[0].z);
            for (glm::vec3& q : p) q -= root;
            positions.push_back(std::move(p));
            rotations.push_back(std::move(r));
        }
    }
};

void renderCrowd(benchmark::State& state, Quality quality, bool readback) {
    RenderBench& b = RenderBench::get();
    if (!b.device) {
        state.SkipWithError(b.error.c_str());
        return;
    }
    const int n = static_cast<int>(state.range(0));
    RendererOptions options;
    options.quality = quality;
    auto r = Renderer::create(b.device, options);
    if (!r) {
        state.SkipWithError(r.error().message.c_str());
        return;
    }
    Renderer& renderer = **r;
    // Characters on a square grid 1.4 m apart, four teams.
    const int side = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n))));
    std::vector<std::vector<glm::vec3>> placed(static_cast<std::size_t>(n));
    std::vector<CharacterInstance> crowd(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
        crowd[static_cast<std::size_t>(i)].skeleton = &b.take.motion.skeleton();
        crowd[static_cast<std::size_t>(i)].tint = teamColor(i % 4);
        placed[static_cast<std::size_t>(i)].resize(b.positions[0].size());
    }
    FrameDescription frame;
    Bounds area;
    area.add(glm::vec3(-0.7f * side, 0.0f, -0.7f * side));
    area.add(glm::vec3(0.7f * side, 1.8f, 0.7f * side));
    frame.camera.yaw = 0.5f;
    frame.camera.pitch = 0.45f;
    frame.camera.frame(area, 1280.0f / 720.0f, 0.9f);
    frame.characters = crowd;
    Image image;
    // Warm up outside the timing: the first frame builds the body mesh and
    // compiles the pipeline variants.
    for (int i = 0; i < n; ++i) {
        crowd[static_cast<std::size_t>(i)].jointPositions = b.positions[0];
        crowd[static_cast<std::size_t>(i)].jointRotations = b.rotations[0];
    }
    if (const fray::Status s = renderer.render(frame, readback ? &image : nullptr); !s) {
        state.SkipWithError(s.error().message.c_str());
        return;
    }
    int tick = 0;
    double processCpu = 0.0;  // CPU seconds of all threads (lavapipe renders on worker threads)
    auto cpuNow = [] {
        timespec ts{};
        clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
        return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
    };
    for (auto _ : state) {
        state.PauseTiming();
        for (int i = 0; i < n; ++i) {
            const auto k = static_cast<std::size_t>((i * 7 + tick) % kPosedFrames);
            const glm::vec3 at((static_cast<float>(i % side) - 0.5f * side) * 1.4f, 0.0f,
                               (static_cast<float>(i / side) - 0.5f * side) * 1.4f);
            auto& p = placed[static_cast<std::size_t>(i)];
            for (std::size_t j = 0; j < p.size(); ++j) p[j] = b.positions[k][j] + at;
            crowd[static_cast<std::size_t>(i)].jointPositions = p;
            crowd[static_cast<std::size_t>(i)].jointRotations = b.rotations[k];
        }
        ++tick;
        state.ResumeTiming();
        const double c0 = cpuNow();
        const fray::Status s = renderer.render(frame, readback ? &image : nullptr);
        processCpu += cpuNow() - c0;
        if (!s) {
            state.SkipWithError(s.error().message.c_str());
            break;
        }
    }
    state.counters["fps"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
    state.counters["cpu_ms"] = 1e3 * processCpu / static_cast<double>(std::max<std::int64_t>(state.iterations(), 1));
    state.counters["triangles"] = static_cast<double>(renderer.stats().triangles);
    state.SetLabel(b.device->description() + ", " + (renderer.quality() == Quality::Fast ? "fast" : "high") + ", " +
                   std::to_string(renderer.msaaSamples()) + "x MSAA");
}

// Viewport quality on a CPU device (what Auto picks on lavapipe): no MSAA,
// blob shadows, 6-sided capsules.
void BM_RenderFast720p(benchmark::State& state) { renderCrowd(state, Quality::Fast, false); }
BENCHMARK(BM_RenderFast720p)->Arg(50)->Arg(200)->Arg(1000)->Unit(benchmark::kMillisecond)->UseRealTime();

// Export quality (fray-cli render, Auto on GPUs): 4x MSAA, 2048 shadow map, 8-sided capsules.
void BM_RenderHigh720p(benchmark::State& state) { renderCrowd(state, Quality::High, false); }
BENCHMARK(BM_RenderHigh720p)->Arg(50)->Arg(200)->Arg(1000)->Unit(benchmark::kMillisecond)->UseRealTime();

// The PNG path's extra cost: reading the 1280x720 image back.
void BM_RenderFast720pReadback(benchmark::State& state) { renderCrowd(state, Quality::Fast, true); }
BENCHMARK(BM_RenderFast720pReadback)->Arg(200)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
