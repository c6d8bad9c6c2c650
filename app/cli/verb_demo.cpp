// fray-cli demo-library OUTDIR [--seed N] [--minutes M] [--report]: writes the
// procedural demo actor's takes (BVH) and their ground truth (JSON).
#include <chrono>
#include <cstdio>
#include <map>
#include <memory>

#include "fray/demo/demo_actor.h"
#include "fray/demo/library.h"
#include "fray/demo/metrics.h"
#include "verbs.h"

namespace fray::cli {
namespace {

struct DemoArgs {
    std::string outDir;
    std::uint64_t seed = 1;
    double minutes = 0.0;
    bool report = false;
};

// Quality figures per take (the thresholds the tests check).
void printReport(const demo::LibraryOptions& options) {
    std::printf("%-22s %9s %9s %9s %10s %-16s\n", "take", "skate_mm", "min_y_mm", "contact%", "max_deg/s", "fastest");
    std::map<std::string, std::pair<double, double>> speed;  // kind -> min, max peak speed
    std::map<std::string, std::pair<double, int>> dur[2];    // kind -> sum seconds, count (energetic, tired)
    for (const auto& spec : demo::planLibrary(options)) {
        const demo::Take take = demo::generateTake(spec, demo::takeSeed(options.seed, spec.name));
        const demo::TakeMetrics m = demo::measureTake(take.motion, take.truth);
        std::printf("%-22s %9.3f %9.1f %9.1f %10.0f %-16s\n", spec.name.c_str(), m.maxSkate * 1000, m.minJointHeight * 1000,
                    100.0 * m.contactFrames / std::max(1, take.motion.frameCount()), m.maxAngularSpeed, m.fastestJoint.c_str());
        for (const auto& a : m.actions) {
            if (a.peakEffectorSpeed > 0) {
                auto [it, fresh] = speed.try_emplace(a.name, a.peakEffectorSpeed, a.peakEffectorSpeed);
                if (!fresh) it->second = {std::min(it->second.first, a.peakEffectorSpeed), std::max(it->second.second, a.peakEffectorSpeed)};
            }
            if (a.style == "energetic" || a.style == "tired") {
                auto& d = dur[a.style == "tired" ? 1 : 0][a.name];
                d.first += a.seconds;
                d.second += 1;
            }
        }
    }
    std::printf("\n%-18s %8s %8s\n", "attack", "min m/s", "max m/s");
    for (const auto& [k, v] : speed) std::printf("%-18s %8.2f %8.2f\n", k.c_str(), v.first, v.second);
    std::printf("\n%-18s %8s %8s %6s\n", "fighting action", "energ s", "tired s", "ratio");
    for (const auto& [k, e] : dur[0]) {
        const auto t = dur[1].find(k);
        if (t == dur[1].end()) continue;
        const double me = e.first / e.second, mt = t->second.first / t->second.second;
        std::printf("%-18s %8.3f %8.3f %6.2f\n", k.c_str(), me, mt, me / mt);
    }
}

void run(const DemoArgs& a) {
    using Clock = std::chrono::steady_clock;
    demo::LibraryOptions options;
    options.seed = a.seed;
    options.minutes = a.minutes;
    const auto t0 = Clock::now();
    auto last = t0;
    auto written = demo::writeDemoLibrary(a.outDir, options, [&](int done, int total, const std::string& name) {
        const auto now = Clock::now();
        std::fprintf(stderr, "[%d/%d] %s (%.2f s)\n", done, total, name.c_str(), std::chrono::duration<double>(now - last).count());
        last = now;
    });
    if (!written) return fail(written.error().message);
    const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    int frames = 0, actions = 0;
    for (const auto& w : *written) {
        frames += w.frames;
        actions += w.actions;
        std::printf("%-40s %7d frames %5d actions\n", w.bvh.string().c_str(), w.frames, w.actions);
    }
    std::printf("%zu takes, %.2f min of motion, %d actions, written in %.2f s\n", written->size(),
                frames / demo::kDemoFps / 60.0, actions, seconds);
    if (a.report) {
        std::printf("\n");
        printReport(options);
    }
}

}  // namespace

void registerDemoLibrary(CLI::App& app) {
    auto args = std::make_shared<DemoArgs>();
    auto* cmd = app.add_subcommand("demo-library",
                                   "Write the synthetic actor's motion library (BVH takes + ground-truth JSON)");
    cmd->add_option("outdir", args->outDir, "Output folder (created if missing)")->required();
    cmd->add_option("--seed", args->seed, "Random seed; the same seed gives byte-identical files");
    cmd->add_option("--minutes", args->minutes,
                    "Total length of the library in minutes (default: shadow-boxing takes of 2 min, others ~1 min)")
        ->check(CLI::Range(0.0, 600.0));
    cmd->add_flag("--report", args->report, "Also print quality figures (foot skate, speeds, style durations)");
    cmd->callback([args] { run(*args); });
}

}  // namespace fray::cli
