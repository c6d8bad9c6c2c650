#pragma once
// Normalisation of a motion to metres and Y-up.
#include <optional>
#include <string_view>

#include "fray/core/motion.h"

namespace fray {

struct UnitGuess {
    double scale = 1.0;        // file units -> metres
    const char* name = "m";
    double heightInFileUnits = 0.0;  // standing height measured on the data
};

// Guesses the length unit from the actor's measured height (feet to head, or
// the skeleton's extent) by picking the candidate unit (m, cm, mm, inch, CMU
// units) that makes it closest to an adult's 1.7 m.
UnitGuess guessUnits(const Motion& motion);
// Guesses the up axis (Y or Z) from where the head is relative to the feet.
UpAxis guessUpAxis(const Motion& motion);

struct NormalizeOptions {
    std::optional<double> unitScale;  // force file units -> metres
    std::optional<UpAxis> upAxis;     // force the source up axis
};

// The scale of a named unit (m, cm, mm, inch or in, cmu: CMU's 0.056444 m),
// and the up axis of a name (y/Y, z/Z); nullopt for any other name.
std::optional<double> unitScaleByName(std::string_view name);
std::optional<UpAxis> upAxisByName(std::string_view name);
// Options from a project entry's overrides ("" means detect).
NormalizeOptions normalizeOptionsFor(std::string_view units, std::string_view up);

// Scales to metres and rotates Z-up data to Y-up (only the root changes, so
// joint-local data stays as in the file). Records what it did in source().
void normalize(Motion& motion, const NormalizeOptions& options = {});

}  // namespace fray
