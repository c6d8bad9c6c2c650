#include "fray/io/assimp_import.h"

namespace fray {

Result<Motion> importWithAssimp(const std::filesystem::path& path, const AssimpImportOptions&) {
    return makeError(path.string() + ": Assimp import not implemented yet");
}

}  // namespace fray
