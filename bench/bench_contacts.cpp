// Google Benchmark: supporting-foot classification (SPEC 1.3). The SVM grid
// search with leave-one-out on 20 s of labels (target: <= 5 s on 2 cores),
// and classifying / the heuristic per minute of motion.
#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <string>

#include "fray/core/joint_guess.h"
#include "fray/demo/demo_actor.h"
#include "fray/io/import.h"
#include "fray/prep/contacts.h"

namespace {

using namespace fray;
using namespace fray::prep;

struct DemoTake {
    MotionSignals signals;
    FootContacts truth;
};

// The demo takes the benchmarks use (library seed 1, as the tests).
const std::map<std::string, DemoTake>& demoTakes() {
    static const std::map<std::string, DemoTake> takes = [] {
        std::map<std::string, DemoTake> out;
        demo::LibraryOptions options;
        options.seed = 1;
        for (const auto& spec : demo::planLibrary(options)) {
            if (spec.name != "shadowbox_energetic" && spec.name != "running_around" && spec.name != "falls" &&
                spec.name != "walking")
                continue;
            const demo::Take take = demo::generateTake(spec, demo::takeSeed(options.seed, spec.name));
            auto s = computeSignals(take.motion, guessStandardJoints(take.motion.skeleton()));
            if (!s) continue;
            out[spec.name] = {std::move(*s), {take.truth.leftContact, take.truth.rightContact}};
        }
        return out;
    }();
    return takes;
}

// 4 x 5 s of ground-truth labels from different takes (as tests/prep/test_contacts.cpp).
std::vector<TrainingSample> twentySecondsOfLabels() {
    struct Range {
        const char* take;
        int first;
        int last;
    };
    const Range ranges[] = {{"shadowbox_energetic", 1200, 1499},
                            {"running_around", 900, 1199},
                            {"falls", 1500, 1799},
                            {"walking", 600, 899}};
    std::vector<TrainingSample> out;
    for (const auto& r : ranges) {
        const auto it = demoTakes().find(r.take);
        if (it == demoTakes().end()) return {};
        const auto labels = expandLabels(labelsFromContacts(it->second.truth, r.first, r.last),
                                         it->second.signals.frameCount);
        if (!labels) return {};
        const auto s = collectSamples(it->second.signals, *labels);
        out.insert(out.end(), s.begin(), s.end());
    }
    return out;
}

// Runs the grid search + LOO once per iteration and reports the chosen model.
void trainEveryIteration(benchmark::State& state, const std::vector<TrainingSample>& samples) {
    std::optional<ContactSvm> svm;
    for (auto _ : state) {
        auto r = ContactSvm::train(samples);
        if (!r) {
            state.SkipWithError(r.error().message.c_str());
            return;
        }
        svm.emplace(std::move(*r));
    }
    const SvmReport& rep = svm->report();
    state.counters["samples"] = rep.samples;
    state.counters["distinct"] = rep.distinctSamples;
    state.counters["cells"] = static_cast<double>(rep.grid.size());
    state.counters["loo_retrains"] = static_cast<double>(rep.looRetrains);
    state.counters["loo_acc"] = rep.looAccuracy;
    state.counters["log2C"] = std::log2(rep.C);
    state.counters["log2gamma"] = std::log2(rep.gamma);
}

void BM_SvmGridSearchLoo20s(benchmark::State& state) {
    const auto samples = twentySecondsOfLabels();
    trainEveryIteration(state, samples);
}
BENCHMARK(BM_SvmGridSearchLoo20s)->Unit(benchmark::kMillisecond)->Iterations(3)->UseRealTime();

// Same, on 20 s of real captures whose labels are a smoothed heuristic's
// (no exact duplicates, overlapping classes near the transitions): the cost
// of noisier labels than the demo actor's.
void BM_SvmGridSearchLoo20sSharedPseudoLabels(benchmark::State& state) {
    struct Range {
        const char* file;
        int first;
        int count;
    };
    const Range ranges[] = {{"lafan1/walk4_subject1.bvh", 300, 300},
                            {"cmu135_karate/bassai.bvh", 1000, 1200},
                            {"lafan1/fallAndGetUp1_subject1.bvh", 600, 300}};
    std::vector<TrainingSample> samples;
    for (const auto& r : ranges) {
        const auto motion = loadMotion(std::filesystem::path(FRAY_SHARED_DIR) / "mocap" / r.file);
        if (!motion) {
            state.SkipWithError(motion.error().message.c_str());
            return;
        }
        const auto signals = computeSignals(*motion, guessStandardJoints(motion->skeleton()));
        if (!signals) {
            state.SkipWithError(signals.error().message.c_str());
            return;
        }
        HeuristicParams smooth;
        smooth.maxSpeed = 0.4f;
        smooth.maxHeight = 0.04f;
        smooth.medianWindow = 11;
        const auto labels =
            expandLabels(labelsFromContacts(heuristicContacts(*signals, smooth), r.first, r.first + r.count - 1),
                         signals->frameCount);
        if (!labels) {
            state.SkipWithError(labels.error().message.c_str());
            return;
        }
        const auto s = collectSamples(*signals, *labels);
        samples.insert(samples.end(), s.begin(), s.end());
    }
    trainEveryIteration(state, samples);
}
BENCHMARK(BM_SvmGridSearchLoo20sSharedPseudoLabels)->Unit(benchmark::kMillisecond)->Iterations(1)->UseRealTime();

// One minute of motion (3600 frames at 60 fps, both feet).
MotionSignals oneMinute() {
    MotionSignals s = demoTakes().at("shadowbox_energetic").signals;
    constexpr std::size_t kFrames = 3600;
    s.frameCount = static_cast<int>(kFrames);
    for (auto& v : s.footSpeed) v.resize(kFrames);
    for (auto& v : s.footHeight) v.resize(kFrames);
    return s;
}

void BM_SvmClassifyPerMinute(benchmark::State& state) {
    auto svm = ContactSvm::train(twentySecondsOfLabels());
    if (!svm) {
        state.SkipWithError(svm.error().message.c_str());
        return;
    }
    const MotionSignals minute = oneMinute();
    for (auto _ : state) benchmark::DoNotOptimize(svm->classify(minute));
    state.counters["support_vectors"] = svm->report().supportVectors;
}
BENCHMARK(BM_SvmClassifyPerMinute)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_HeuristicPerMinute(benchmark::State& state) {
    const MotionSignals minute = oneMinute();
    for (auto _ : state) benchmark::DoNotOptimize(heuristicContacts(minute));
}
BENCHMARK(BM_HeuristicPerMinute)->Unit(benchmark::kMillisecond);

}  // namespace
