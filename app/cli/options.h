#pragma once
// Shared parsing of the --units / --up options of import verbs.
#include <CLI/CLI.hpp>
#include <optional>
#include <string>

#include "fray/core/result.h"
#include "fray/io/import.h"

namespace fray::cli {

struct ImportFlags {
    std::string units;      // "", m, cm, mm, inch, cmu, or a factor to metres
    std::string up;         // "", y, z
    std::string animation;  // Assimp animation name
    bool raw = false;       // keep file units and axes
};

Result<LoadOptions> toLoadOptions(const ImportFlags& flags);
void addImportFlags(CLI::App* cmd, ImportFlags& flags);

}  // namespace fray::cli
