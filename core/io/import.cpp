#include "fray/io/import.h"

#include <algorithm>
#include <cctype>
#include <system_error>

#include "fray/io/assimp_import.h"
#include "fray/io/bvh.h"

namespace fray {

Result<Motion> loadMotion(const std::filesystem::path& path, const LoadOptions& options) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) return makeError(path.string() + ": file not found");
    if (!std::filesystem::is_regular_file(path, ec)) {
        return makeError(path.string() + ": not a regular file (a folder, device or pipe)");
    }
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    Result<Motion> motion = (ext == ".bvh" && !options.forceAssimp)
                                ? readBvh(path)
                                : importWithAssimp(path, AssimpImportOptions{options.animation, {}, 0.0});
    if (!motion) return motion;
    if (options.doNormalize) normalize(*motion, options.normalize);
    return motion;
}

}  // namespace fray
