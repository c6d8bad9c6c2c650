#pragma once
// Shared parsing of the --units / --up options of import verbs.
#include <CLI/CLI.hpp>
#include <optional>
#include <string>

#include "fray/core/result.h"
#include "fray/io/import.h"
#include "fray/posture/posture.h"

namespace fray::cli {

struct ImportFlags {
    std::string units;      // "", m, cm, mm, inch, cmu, or a factor to metres
    std::string up;         // "", y, z
    std::string animation;  // Assimp animation name
    bool raw = false;       // keep file units and axes
};

Result<LoadOptions> toLoadOptions(const ImportFlags& flags);

// Checks of numeric flags, applied to the text as typed: a finite number
// (nan, inf and overflowing values such as 1e999 are refused) within
// [lo, hi], or within (0, hi] for finitePositive. CLI11 prints the failure
// with the flag's name ("--fps: 1e9 must be a finite number in (0, 1000]").
CLI::Validator finiteRange(double lo, double hi);
CLI::Validator finitePositive(double hi);

// Largest frame rate convert resamples to (docs/FILES.md).
inline constexpr double kMaxFps = 1000.0;
void addImportFlags(CLI::App* cmd, ImportFlags& flags);

// --posture kinematic|physics (docs/POSTURE.md) of render, export and metrics.
void addPostureFlag(CLI::App* cmd, std::string& mode, const std::string& help);
// The mode named by --posture ("" = kinematic); the error names the flag.
Result<posture::Mode> postureMode(const std::string& flag);
// --hand-pins: with --posture physics, a porter's hands are pinned to the
// luggage it holds (posture::Options::handPins, off by default).
void addHandPinsFlag(CLI::App* cmd, bool& on);
// The solver's options of these flags; the error names --hand-pins where it
// is given without --posture physics.
Result<posture::Options> postureOptions(const std::string& mode, bool handPins);
// The solver's report as "note:" lines (to stderr; nothing when quiet or empty).
void printPostureNotes(const posture::Report& report, bool quiet);

}  // namespace fray::cli
