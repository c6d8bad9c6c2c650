// Google Benchmark: offscreen frame time of the Vulkan renderer at 1280x720
// in both qualities for crowds of demo characters, on whatever
// device the loader offers (lavapipe on the CI machine; FRAY_VULKAN_DEVICE=cpu
// forces it). Poses come from a generated shadow-boxing take, pre-posed, so the
// time is the renderer's: uploading instances and palettes, the shadow pass,
// the main pass (bodies, floor, overlays) and waiting for the device.
// BM_RenderRigVsCapsules compares a skinned rig with the capsules it replaces.
//
//   build/bin/fray-bench --benchmark_filter=Render
#include <benchmark/benchmark.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <ctime>
#include <memory>
#include <vector>

#include "fray/core/kinematics.h"
#include "fray/demo/demo_actor.h"
#include "fray/io/rig_import.h"
#include "fray/render/motion_stage.h"
#include "fray/render/renderer.h"
#include "rig_fixture.h"
#include "temp_dir.h"

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
    // The take's skeleton exported as GLB by Fray's exporter and read back: the
    // full-detail capsule body, one joint per vertex.
    SkinnedMesh rig;

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
        fray::test::TempDir dir("fray_bench_rig_");
        fray::test::writeExportedRig(m.skeleton(), dir / "rig.glb", false);
        auto loaded = loadRig(dir / "rig.glb", m.skeleton());
        if (!loaded) {
            error = loaded.error().message;
            device.reset();
            return;
        }
        rig = std::move(*loaded);
    }
};

// Characters on a square grid 1.4 m apart, four teams, the camera framing
// them all; pose(tick) gives each a different pre-posed frame.
class Crowd {
public:
    Crowd(const RenderBench& b, int n)
        : b_(b), side_(static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n))))), placed_(static_cast<std::size_t>(n)),
          instances_(static_cast<std::size_t>(n)) {
        for (int i = 0; i < n; ++i) {
            instances_[static_cast<std::size_t>(i)].skeleton = &b.take.motion.skeleton();
            instances_[static_cast<std::size_t>(i)].tint = teamColor(i % 4);
            placed_[static_cast<std::size_t>(i)].resize(b.positions[0].size());
        }
        Bounds area;
        area.add(glm::vec3(-0.7f * side_, 0.0f, -0.7f * side_));
        area.add(glm::vec3(0.7f * side_, 1.8f, 0.7f * side_));
        frame.camera.yaw = 0.5f;
        frame.camera.pitch = 0.45f;
        frame.camera.frame(area, 1280.0f / 720.0f, 0.9f);
        frame.characters = instances_;
    }

    void pose(int tick) {
        const int n = static_cast<int>(instances_.size());
        for (int i = 0; i < n; ++i) {
            const auto k = static_cast<std::size_t>((i * 7 + tick) % kPosedFrames);
            const glm::vec3 at((static_cast<float>(i % side_) - 0.5f * side_) * 1.4f, 0.0f,
                               (static_cast<float>(i / side_) - 0.5f * side_) * 1.4f);
            auto& p = placed_[static_cast<std::size_t>(i)];
            for (std::size_t j = 0; j < p.size(); ++j) p[j] = b_.positions[k][j] + at;
            instances_[static_cast<std::size_t>(i)].jointPositions = p;
            instances_[static_cast<std::size_t>(i)].jointRotations = b_.rotations[k];
        }
    }

    // Forward kinematics of every character from the take, in parallel:
    // what a viewport does each frame before it draws.
    void poseFromTake(int tick) {
        const Motion& m = b_.take.motion;
        const int n = static_cast<int>(instances_.size());
        if (rotated_.size() != placed_.size()) rotated_.assign(placed_.size(), std::vector<glm::quat>(placed_[0].size()));
        tbb::parallel_for(tbb::blocked_range<int>(0, n, 256), [&](const tbb::blocked_range<int>& r) {
            for (int i = r.begin(); i != r.end(); ++i) {
                const auto u = static_cast<std::size_t>(i);
                const int f = (i * 7 + tick) % m.frameCount();
                worldTransforms(m, f, placed_[u], rotated_[u]);
                const glm::vec3 root(placed_[u][0].x, 0.0f, placed_[u][0].z);
                const glm::vec3 at((static_cast<float>(i % side_) - 0.5f * side_) * 1.4f, 0.0f,
                                   (static_cast<float>(i / side_) - 0.5f * side_) * 1.4f);
                for (glm::vec3& q : placed_[u]) q += at - root;
                instances_[u].jointPositions = placed_[u];
                instances_[u].jointRotations = rotated_[u];
            }
        });
    }

    FrameDescription frame;

private:
    std::vector<std::vector<glm::quat>> rotated_;
    const RenderBench& b_;
    int side_;
    std::vector<std::vector<glm::vec3>> placed_;
    std::vector<CharacterInstance> instances_;
};

double cpuSeconds() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

void renderCrowd(benchmark::State& state, Quality quality, bool readback, int farPixels = -1) {
    RenderBench& b = RenderBench::get();
    if (!b.device) {
        state.SkipWithError(b.error.c_str());
        return;
    }
    const int n = static_cast<int>(state.range(0));
    RendererOptions options;
    options.quality = quality;
    options.farPixels = farPixels;
    auto r = Renderer::create(b.device, options);
    if (!r) {
        state.SkipWithError(r.error().message.c_str());
        return;
    }
    Renderer& renderer = **r;
    Crowd crowd(b, n);
    Image image;
    // Warm up outside the timing: the first frame builds the body mesh and
    // compiles the pipeline variants.
    crowd.pose(0);
    if (const fray::Status s = renderer.render(crowd.frame, readback ? &image : nullptr); !s) {
        state.SkipWithError(s.error().message.c_str());
        return;
    }
    int tick = 0;
    double processCpu = 0.0;  // CPU seconds of all threads (lavapipe renders on worker threads)
    for (auto _ : state) {
        state.PauseTiming();
        crowd.pose(tick++);
        state.ResumeTiming();
        const double c0 = cpuSeconds();
        const fray::Status s = renderer.render(crowd.frame, readback ? &image : nullptr);
        processCpu += cpuSeconds() - c0;
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
// blob shadows, cards for the characters below 96 px (all of them from 200 on).
void BM_RenderFast720p(benchmark::State& state) { renderCrowd(state, Quality::Fast, false); }
BENCHMARK(BM_RenderFast720p)->Arg(50)->Arg(200)->Arg(1000)->Unit(benchmark::kMillisecond)->UseRealTime();

// The far field (issue 27): Fast with far cards for the characters under 40 px
// (Arg 1 = 1, the default) or without them (0: cards as before), on crowds
// framed as above (at 2,000 characters all of them are far).
void BM_RenderFast720pFarField(benchmark::State& state) {
    renderCrowd(state, Quality::Fast, false, state.range(1) != 0 ? -1 : 0);
}
BENCHMARK(BM_RenderFast720pFarField)->Args({2000, 0})->Args({2000, 1})->Args({1000, 0})->Args({1000, 1})
    ->Unit(benchmark::kMillisecond)->UseRealTime();

// The viewport at crowd scale (issue 27): every frame poses each character
// from the take by forward kinematics (parallel over characters, TBB) and
// renders the crowd at 1280x720 in the viewport's Fast quality with far
// cards, the camera framing all of them; the time is posing plus drawing
// (counters: pose_ms, prepare_ms the renderer's CPU side, device_ms the
// device's time per frame from timestamps, wait_ms the time the CPU waited
// for the frame before to leave the device: two frames are in flight).
// On lavapipe run the small sizes only; 100,000 is for a GPU.
void BM_Viewport720p(benchmark::State& state) {
    RenderBench& b = RenderBench::get();
    if (!b.device) {
        state.SkipWithError(b.error.c_str());
        return;
    }
    RendererOptions options;
    options.quality = Quality::Fast;
    auto r = Renderer::create(b.device, options);
    if (!r) {
        state.SkipWithError(r.error().message.c_str());
        return;
    }
    Renderer& renderer = **r;
    Crowd crowd(b, static_cast<int>(state.range(0)));
    crowd.poseFromTake(0);
    if (const fray::Status s = renderer.render(crowd.frame, nullptr); !s) {
        state.SkipWithError(s.error().message.c_str());
        return;
    }
    int tick = 1;
    double poseSeconds = 0.0, prepareMs = 0.0, deviceMs = 0.0, waitMs = 0.0;
    for (auto _ : state) {
        const auto t0 = std::chrono::steady_clock::now();
        crowd.poseFromTake(tick++);
        poseSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (const fray::Status s = renderer.render(crowd.frame, nullptr); !s) {
            state.SkipWithError(s.error().message.c_str());
            break;
        }
        prepareMs += renderer.stats().prepareMs;
        deviceMs += renderer.stats().deviceMs;
        waitMs += renderer.stats().waitMs;
    }
    const double frames = static_cast<double>(std::max<std::int64_t>(state.iterations(), 1));
    state.counters["prepare_ms"] = prepareMs / frames;
    state.counters["device_ms"] = deviceMs / frames;
    state.counters["wait_ms"] = waitMs / frames;
    state.counters["fps"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
    state.counters["pose_ms"] = 1e3 * poseSeconds / frames;
    state.counters["triangles"] = static_cast<double>(renderer.stats().triangles);
    state.SetLabel(b.device->description());
}
BENCHMARK(BM_Viewport720p)->Arg(2000)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond)->UseRealTime();

// Export quality (fray-cli render, Auto on GPUs): 4x MSAA, 2048 shadow map, 8-sided capsules.
void BM_RenderHigh720p(benchmark::State& state) { renderCrowd(state, Quality::High, false); }
BENCHMARK(BM_RenderHigh720p)->Arg(50)->Arg(200)->Arg(1000)->Unit(benchmark::kMillisecond)->UseRealTime();

// A rig against the capsules it replaces, at the same triangle count (the
// capsules at full detail, lodPixels 0: a rig has no levels of detail).
// Frames alternate between two renderers on one device, so load from other
// processes falls on both alike; the counters are the mean frame time of each.
// Args: characters, quality (0 Fast, 1 High), joints per vertex (1: the
// exported body as it is; 4: each vertex spread over its joint, the parent,
// the grandparent and the root with weights 0.55, 0.25, 0.15, 0.05).
void BM_RenderRigVsCapsules(benchmark::State& state) {
    RenderBench& b = RenderBench::get();
    if (!b.device) {
        state.SkipWithError(b.error.c_str());
        return;
    }
    const Skeleton& sk = b.take.motion.skeleton();
    SkinnedMesh rig = b.rig;
    if (state.range(2) == 4)
        for (SkinnedVertex& v : rig.vertices) {
            const int j = v.joints[0];
            const int p = std::max(0, sk.parents[static_cast<std::size_t>(j)]);
            const int g = std::max(0, sk.parents[static_cast<std::size_t>(p)]);
            v.joints = {static_cast<std::uint16_t>(j), static_cast<std::uint16_t>(p), static_cast<std::uint16_t>(g), 0};
            v.weights = glm::vec4(0.55f, 0.25f, 0.15f, 0.05f);
        }
    RendererOptions options;
    options.quality = state.range(1) ? Quality::High : Quality::Fast;
    options.lodPixels = 0;
    auto capsules = Renderer::create(b.device, options);
    auto rigged = Renderer::create(b.device, options);
    if (!capsules || !rigged) {
        state.SkipWithError((capsules ? rigged.error() : capsules.error()).message.c_str());
        return;
    }
    if (const fray::Status s = (*rigged)->setRig(sk, rig); !s) {
        state.SkipWithError(s.error().message.c_str());
        return;
    }
    Crowd crowd(b, static_cast<int>(state.range(0)));
    crowd.pose(0);
    for (Renderer* r : {capsules->get(), rigged->get()})
        if (const fray::Status s = r->render(crowd.frame); !s) {
            state.SkipWithError(s.error().message.c_str());
            return;
        }
    std::array<double, 2> seconds{};
    int tick = 0;
    for (auto _ : state) {
        state.PauseTiming();
        crowd.pose(tick++);
        state.ResumeTiming();
        for (std::size_t k = 0; k < 2; ++k) {
            const auto t0 = std::chrono::steady_clock::now();
            const fray::Status s = (k ? *rigged : *capsules)->render(crowd.frame);
            seconds[k] += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            if (!s) state.SkipWithError(s.error().message.c_str());
        }
    }
    const auto frames = static_cast<double>(std::max<std::int64_t>(state.iterations(), 1));
    state.counters["capsules_ms"] = 1e3 * seconds[0] / frames;
    state.counters["rig_ms"] = 1e3 * seconds[1] / frames;
    state.counters["triangles"] = static_cast<double>((*rigged)->stats().triangles);
    state.SetLabel(b.device->description() + ", " + ((*rigged)->quality() == Quality::Fast ? "fast" : "high"));
}
BENCHMARK(BM_RenderRigVsCapsules)
    ->Args({200, 0, 1})
    ->Args({200, 0, 4})
    ->Args({50, 1, 1})
    ->Args({50, 1, 4})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The PNG path's extra cost: reading the 1280x720 image back.
void BM_RenderFast720pReadback(benchmark::State& state) { renderCrowd(state, Quality::Fast, true); }
BENCHMARK(BM_RenderFast720pReadback)->Arg(200)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
