#pragma once
// Progress and cancellation for long work: the one way to stop a step. A step
// reports a fraction in [0, 1] and a short stage name; the callback returns
// false to cancel, and the step then stops at its next check and returns
// fray::cancelled() (an Error of kind ErrorKind::Cancelled). Callers test
// error().isCancelled(), never the message. A caller that cancels from
// another thread (a Cancel button) wraps its callback with cancelWhen(flag).
#include <atomic>
#include <functional>
#include <string_view>
#include <utility>

namespace fray {

using ProgressFn = std::function<bool(double fraction, std::string_view stage)>;

// Calls progress if set; true means "keep going".
inline bool reportProgress(const ProgressFn& progress, double fraction, std::string_view stage) {
    return !progress || progress(fraction, stage);
}

// A callback that cancels once `flag` is set (read at every report), and
// otherwise passes the report on to `inner` (if any). The flag must outlive the step.
inline ProgressFn cancelWhen(const std::atomic<bool>& flag, ProgressFn inner = {}) {
    return [&flag, inner = std::move(inner)](double fraction, std::string_view stage) {
        return !flag.load(std::memory_order_relaxed) && reportProgress(inner, fraction, stage);
    };
}

}  // namespace fray
