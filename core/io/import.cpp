#include "fray/io/import.h"

#include <algorithm>
#include <cctype>
#include <system_error>

#include "fray/io/assimp_import.h"
#include "fray/io/bvh.h"

namespace fray {
namespace {

std::string lowerExtension(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext;
}

}  // namespace

Result<Motion> loadMotion(const std::filesystem::path& path, const LoadOptions& options) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) return makeError(path.string() + ": file not found");
    if (!std::filesystem::is_regular_file(path, ec)) {
        return makeError(path.string() + ": not a regular file (a folder, device or pipe)");
    }
    Result<Motion> motion = (lowerExtension(path) == ".bvh" && !options.forceAssimp)
                                ? readBvh(path)
                                : importWithAssimp(path, AssimpImportOptions{options.animation, {}, 0.0});
    if (!motion) return motion;
    if (options.doNormalize) normalize(*motion, options.normalize);
    return motion;
}

Result<std::vector<Motion>> loadMotions(const std::filesystem::path& path, const LoadOptions& options) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) return makeError(path.string() + ": file not found");
    if (lowerExtension(path) == ".bvh" && !options.forceAssimp) {
        auto one = loadMotion(path, options);
        if (!one) return one.error();
        std::vector<Motion> out;
        out.push_back(std::move(*one));
        return out;
    }
    auto all = importAllWithAssimp(path, AssimpImportOptions{options.animation, {}, 0.0});
    if (!all) return all;
    if (options.doNormalize)
        for (Motion& m : *all) normalize(m, options.normalize);
    return all;
}

}  // namespace fray
