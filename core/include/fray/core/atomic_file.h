#pragma once
// Whole-file I/O. Atomic file replacement: write beside the target, flush, then rename, so a
// failure never leaves half a file and never clobbers the previous version.
#include <filesystem>
#include <string>
#include <string_view>

#include "fray/core/result.h"

namespace fray {

Status writeFileAtomically(const std::filesystem::path& path, std::string_view contents);

// Reads a whole file. Errors name the file and what it was meant to be:
// readWholeFile("p.frayproj", "the project file") ->
// "p.frayproj: cannot open the project file: no such file".
Result<std::string> readWholeFile(const std::filesystem::path& path, std::string_view what = "the file");

}  // namespace fray
