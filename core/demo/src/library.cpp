#include "fray/demo/library.h"

#include <nlohmann/json.hpp>
#include <system_error>

#include "fray/core/atomic_file.h"
#include "fray/io/bvh.h"

namespace fray::demo {

Result<std::vector<WrittenTake>> writeDemoLibrary(const std::filesystem::path& outDir, const LibraryOptions& options,
                                                  const ProgressFn& progress) {
    std::error_code ec;
    std::filesystem::create_directories(outDir, ec);
    if (ec) return makeError(outDir.string() + ": cannot create directory: " + ec.message());
    const std::vector<TakeSpec> plan = planLibrary(options);
    if (plan.empty()) return makeError("demo library: unknown set '" + options.set + "' (known: default, football, carry)");
    std::vector<WrittenTake> written;
    nlohmann::ordered_json index;
    index["format"] = "fray-demo-library";
    index["version"] = 1;
    index["seed"] = options.seed;
    index["minutes"] = options.minutes;
    index["set"] = options.set;
    index["fps"] = kDemoFps;
    index["takes"] = nlohmann::ordered_json::array();
    for (std::size_t i = 0; i < plan.size(); ++i) {
        const TakeSpec& spec = plan[i];
        const Take take = generateTake(spec, takeSeed(options.seed, spec.name));
        WrittenTake w;
        w.name = spec.name;
        w.bvh = outDir / (spec.name + ".bvh");
        w.truth = outDir / (spec.name + ".truth.json");
        w.frames = take.motion.frameCount();
        w.actions = static_cast<int>(take.truth.actions.size());
        if (auto st = writeBvh(take.motion, w.bvh); !st) return st.error();
        if (auto st = writeFileAtomically(w.truth, toJson(take.truth)); !st) return st.error();
        index["takes"].push_back({{"name", spec.name},
                                  {"kind", std::string(toString(spec.kind))},
                                  {"style", std::string(toString(spec.style))},
                                  {"motion", w.bvh.filename().string()},
                                  {"truth", w.truth.filename().string()},
                                  {"frames", w.frames},
                                  {"actions", w.actions}});
        written.push_back(w);
        if (progress) progress(static_cast<int>(i + 1), static_cast<int>(plan.size()), take);
    }
    if (auto st = writeFileAtomically(outDir / "demo_library.json", index.dump(2) + "\n"); !st) return st.error();
    return written;
}

}  // namespace fray::demo
