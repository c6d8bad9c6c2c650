// fray-cli demo-library OUTDIR [--seed N] [--minutes M] [--set S] [--report]: writes the
// procedural demo actor's takes (BVH), their ground truth (JSON) and the demo
// project (demo.frayproj) that references them.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "fray/core/atomic_file.h"
#include "fray/demo/demo_actor.h"
#include "fray/demo/demo_project.h"
#include "fray/demo/library.h"
#include "fray/demo/metrics.h"
#include "verbs.h"

namespace fray::cli {
namespace {

struct DemoArgs {
    std::string outDir;
    std::uint64_t seed = 1;
    double minutes = 0.0;
    std::string set = "default";
    bool report = false;
};

// Quality figures per take (the thresholds the tests check), gathered while
// the library is written.
class Report {
public:
    void add(const demo::Take& take) {
        const demo::TakeMetrics m = demo::measureTake(take.motion, take.truth);
        char line[160];
        std::snprintf(line, sizeof line, "%-22s %9.3f %9.1f %9.1f %10.0f %-16s\n", take.spec.name.c_str(),
                      m.maxSkate * 1000, m.minJointHeight * 1000,
                      100.0 * m.contactFrames / std::max(1, take.motion.frameCount()), m.maxAngularSpeed,
                      m.fastestJoint.c_str());
        takes_ += line;
        for (const auto& a : m.actions) {
            if (a.peakEffectorSpeed > 0) {
                auto [it, fresh] = speed_.try_emplace(a.name, a.peakEffectorSpeed, a.peakEffectorSpeed);
                if (!fresh) it->second = {std::min(it->second.first, a.peakEffectorSpeed), std::max(it->second.second, a.peakEffectorSpeed)};
            }
            double& fastest = angular_[a.name];
            fastest = std::max(fastest, a.maxAngularSpeed);
            if (a.style == "energetic" || a.style == "tired") {
                auto& d = dur_[a.style == "tired" ? 1 : 0][a.name];
                d.first += a.seconds;
                d.second += 1;
            }
        }
    }

    void print() const {
        std::printf("%-22s %9s %9s %9s %10s %-16s\n%s", "take", "skate_mm", "min_y_mm", "contact%", "max_deg/s",
                    "fastest", takes_.c_str());
        std::printf("\n%-18s %8s %8s\n", "attack", "min m/s", "max m/s");
        for (const auto& [k, v] : speed_) std::printf("%-18s %8.2f %8.2f\n", k.c_str(), v.first, v.second);
        std::vector<std::pair<double, std::string>> fast;
        for (const auto& [k, v] : angular_) fast.emplace_back(v, k);
        std::sort(fast.rbegin(), fast.rend());
        std::printf("\n%-18s %10s\n", "fastest actions", "max_deg/s");
        for (std::size_t i = 0; i < fast.size() && i < 5; ++i) std::printf("%-18s %10.0f\n", fast[i].second.c_str(), fast[i].first);
        std::printf("\n%-18s %8s %8s %6s\n", "fighting action", "energ s", "tired s", "ratio");
        for (const auto& [k, e] : dur_[0]) {
            const auto t = dur_[1].find(k);
            if (t == dur_[1].end()) continue;
            const double me = e.first / e.second, mt = t->second.first / t->second.second;
            std::printf("%-18s %8.3f %8.3f %6.2f\n", k.c_str(), me, mt, me / mt);
        }
    }

private:
    std::string takes_;
    std::map<std::string, std::pair<double, double>> speed_;  // kind -> min, max peak speed
    std::map<std::string, std::pair<double, int>> dur_[2];    // kind -> sum seconds, count (energetic, tired)
    std::map<std::string, double> angular_;                   // kind -> fastest joint rotation (deg/s)
};

void run(const DemoArgs& a) {
    using Clock = std::chrono::steady_clock;
    demo::LibraryOptions options;
    options.seed = a.seed;
    options.minutes = a.minutes;
    options.set = a.set;
    const auto t0 = Clock::now();
    auto last = t0;
    Report report;
    std::vector<demo::ProjectTake> projectTakes;
    auto written = demo::writeDemoLibrary(a.outDir, options, [&](int done, int total, const demo::Take& take) {
        const auto now = Clock::now();
        std::fprintf(stderr, "[%d/%d] %s (%.2f s)\n", done, total, take.spec.name.c_str(),
                     std::chrono::duration<double>(now - last).count());
        last = now;
        if (a.report) report.add(take);
        projectTakes.push_back({take.truth, take.truth.motionFile});
    });
    if (!written) return fail(written.error().message);
    const auto projectFile = std::filesystem::path(a.outDir) / "demo.frayproj";
    const prep::Project project = demo::makeDemoProject(projectTakes);
    if (auto st = prep::saveProject(project, projectFile); !st) return fail(st.error().message);
    // The same labels as a CSV, for `fray-cli contacts P --train` on fresh projects.
    std::vector<prep::LabelRow> rows;
    for (const auto& m : project.motions) {
        for (const auto& l : m.contactLabels) rows.push_back({m.id, l, 0});
    }
    const auto labelsFile = std::filesystem::path(a.outDir) / "contact_labels.csv";
    if (auto st = writeFileAtomically(labelsFile, prep::labelsToCsv(rows)); !st) return fail(st.error().message);
    const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    int frames = 0, actions = 0;
    for (const auto& w : *written) {
        frames += w.frames;
        actions += w.actions;
        std::printf("%-40s %7d frames %5d actions\n", w.bvh.string().c_str(), w.frames, w.actions);
    }
    std::printf("%zu takes, %.2f min of motion, %d actions, written in %.2f s\n", written->size(),
                frames / demo::kDemoFps / 60.0, actions, seconds);
    std::printf("demo project: %s\n", projectFile.string().c_str());
    if (a.report) {
        std::printf("\n");
        report.print();
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
    cmd->add_option("--set", args->set,
                    "Which takes: default (fighting, running, falls, carrying, walking), football (runs, cuts, tackles) or carry (one end of a long box)")
        ->check(CLI::IsMember(demo::librarySets()));
    cmd->add_flag("--report", args->report, "Also print quality figures (foot skate, speeds, style durations)");
    cmd->callback([args] { run(*args); });
}

}  // namespace fray::cli
