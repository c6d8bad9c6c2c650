// fray-cli bench import FILES...: BVH import throughput of our reader against
// Assimp's BVH importer on the same files, in the same run.
#include <assimp/Importer.hpp>
#include <assimp/scene.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>

#include "fray/io/bvh.h"
#include "verbs.h"

namespace fray::cli {
namespace {

struct BenchArgs {
    std::vector<std::string> files;
    int repeat = 3;
    bool json = false;
    bool skipAssimp = false;
};

using Clock = std::chrono::steady_clock;

// Best-of-N wall time in seconds for one file (best-of rejects scheduler noise).
template <class F>
double bestOf(int n, F&& f) {
    double best = 1e30;
    for (int i = 0; i < n; ++i) {
        const auto t0 = Clock::now();
        if (!f()) return -1;
        best = std::min(best, std::chrono::duration<double>(Clock::now() - t0).count());
    }
    return best;
}

void run(const BenchArgs& a) {
    double bytes = 0, oursTotal = 0, assimpTotal = 0;
    nlohmann::json rows = nlohmann::json::array();
    if (!a.json) std::printf("%-44s %9s %12s %12s %8s\n", "file", "MB", "fray MB/s", "assimp MB/s", "ratio");
    for (const auto& file : a.files) {
        std::error_code ec;
        const double size = static_cast<double>(std::filesystem::file_size(file, ec));
        if (ec) return fail(file + ": cannot read (" + ec.message() + ")");
        std::string err;
        const double ours = bestOf(a.repeat, [&] {
            auto m = readBvh(file);
            if (!m) err = m.error().message;
            return m.ok();
        });
        if (ours < 0) return fail(err);
        double theirs = 0;
        if (!a.skipAssimp) {
            theirs = bestOf(a.repeat, [&] {
                Assimp::Importer imp;
                const aiScene* s = imp.ReadFile(file, 0);
                if (!s) err = file + ": Assimp: " + imp.GetErrorString();
                return s != nullptr;
            });
            if (theirs < 0) return fail(err);
        }
        bytes += size;
        oursTotal += ours;
        assimpTotal += theirs;
        const double mb = size / 1e6;
        rows.push_back({{"file", file}, {"mb", mb}, {"fray_mb_s", mb / ours},
                        {"assimp_mb_s", theirs > 0 ? mb / theirs : 0.0}, {"ratio", theirs > 0 ? theirs / ours : 0.0}});
        if (!a.json)
            std::printf("%-44s %9.2f %12.1f %12.1f %8.1f\n", std::filesystem::path(file).filename().string().c_str(), mb,
                        mb / ours, theirs > 0 ? mb / theirs : 0.0, theirs > 0 ? theirs / ours : 0.0);
    }
    const double mb = bytes / 1e6;
    const double ratio = assimpTotal > 0 ? assimpTotal / oursTotal : 0.0;
    if (a.json) {
        nlohmann::json j = {{"files", rows}, {"total_mb", mb}, {"fray_mb_s", mb / oursTotal},
                            {"assimp_mb_s", assimpTotal > 0 ? mb / assimpTotal : 0.0}, {"ratio", ratio}};
        std::printf("%s\n", j.dump(2).c_str());
    } else {
        std::printf("%-44s %9.2f %12.1f %12.1f %8.1f\n", "TOTAL", mb, mb / oursTotal,
                    assimpTotal > 0 ? mb / assimpTotal : 0.0, ratio);
    }
}

}  // namespace

void registerBench(CLI::App& app) {
    auto* bench = app.add_subcommand("bench", "Measure throughput of pipeline steps");
    bench->require_subcommand(1);
    auto args = std::make_shared<BenchArgs>();
    auto* imp = bench->add_subcommand("import", "BVH import MB/s: Fray's reader vs Assimp, same files, same run");
    imp->add_option("files", args->files, "BVH files")->required()->check(CLI::ExistingFile);
    imp->add_option("--repeat", args->repeat, "Runs per file (best is kept)")->check(CLI::Range(1, 100));
    imp->add_flag("--json", args->json, "Print JSON");
    imp->add_flag("--no-assimp", args->skipAssimp, "Time Fray's reader only");
    imp->callback([args] { run(*args); });
}

}  // namespace fray::cli
