#pragma once
// Progress and cancellation for long work. A step reports a fraction in [0, 1]
// and a short stage name; the callback returns false to cancel, and the step
// then stops at its next check and returns an Error "cancelled".
#include <functional>
#include <string_view>

namespace fray {

using ProgressFn = std::function<bool(double fraction, std::string_view stage)>;

// Calls progress if set; true means "keep going".
inline bool reportProgress(const ProgressFn& progress, double fraction, std::string_view stage) {
    return !progress || progress(fraction, stage);
}

}  // namespace fray
