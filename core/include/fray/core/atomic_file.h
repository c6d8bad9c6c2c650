#pragma once
// Atomic file replacement: write beside the target, flush, then rename, so a
// failure never leaves half a file and never clobbers the previous version.
#include <filesystem>
#include <string_view>

#include "fray/core/result.h"

namespace fray {

Status writeFileAtomically(const std::filesystem::path& path, std::string_view contents);

}  // namespace fray
