// Google Benchmark: BVH import throughput (Fray vs Assimp on the same file, in
// the same run) and pose sampling across many clips.
#include <assimp/Importer.hpp>
#include <assimp/scene.h>
#include <benchmark/benchmark.h>

#include <filesystem>

#include "fray/core/kinematics.h"
#include "fray/io/bvh.h"

namespace {

const std::filesystem::path kShared = FRAY_SHARED_DIR;
const char* kFiles[] = {"lafan1/walk4_subject1.bvh", "cmu135_karate/bassai.bvh", "cmu14/14_14.bvh",
                        "bandai/dataset-2_walk_normal_001.bvh"};

void BM_FrayBvhRead(benchmark::State& state) {
    const auto path = kShared / "mocap" / kFiles[state.range(0)];
    const auto bytes = static_cast<std::int64_t>(std::filesystem::file_size(path));
    for (auto _ : state) {
        auto m = fray::readBvh(path);
        if (!m) state.SkipWithError(m.error().message.c_str());
        benchmark::DoNotOptimize(m);
    }
    state.SetBytesProcessed(state.iterations() * bytes);
    state.SetLabel(kFiles[state.range(0)]);
}
BENCHMARK(BM_FrayBvhRead)->DenseRange(0, 3)->Unit(benchmark::kMillisecond);

void BM_AssimpBvhRead(benchmark::State& state) {
    const auto path = kShared / "mocap" / kFiles[state.range(0)];
    const auto bytes = static_cast<std::int64_t>(std::filesystem::file_size(path));
    for (auto _ : state) {
        Assimp::Importer imp;
        const aiScene* s = imp.ReadFile(path.string(), 0);
        if (!s) state.SkipWithError(imp.GetErrorString());
        benchmark::DoNotOptimize(s);
    }
    state.SetBytesProcessed(state.iterations() * bytes);
    state.SetLabel(kFiles[state.range(0)]);
}
BENCHMARK(BM_AssimpBvhRead)->DenseRange(0, 3)->Unit(benchmark::kMillisecond);

// Samples one pose (slerp) and its world positions from each of N clips.
void BM_SampleAndPose(benchmark::State& state) {
    auto m = fray::readBvh(kShared / "mocap/lafan1/walk4_subject1.bvh");
    if (!m) {
        state.SkipWithError(m.error().message.c_str());
        return;
    }
    const int clips = static_cast<int>(state.range(0));
    fray::Pose pose;
    std::vector<glm::vec3> wp(static_cast<std::size_t>(m->jointCount()));
    std::vector<glm::quat> wr(wp.size());
    double t = 0;
    for (auto _ : state) {
        for (int c = 0; c < clips; ++c) {
            m->sample(std::fmod(t + c * 0.37, m->duration()), pose);
            fray::forwardKinematics(m->skeleton(), pose.translations, pose.rotations, wp, wr);
        }
        benchmark::DoNotOptimize(wp.data());
        t += 1.0 / 60.0;
    }
    state.SetItemsProcessed(state.iterations() * clips);
}
BENCHMARK(BM_SampleAndPose)->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
