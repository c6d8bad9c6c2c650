#include "cli_session.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

namespace fray::cli {

ProgressFn stderrProgress(bool quiet) {
    if (quiet) return {};
    struct State {
        std::string stage;
        int lastDecile = -1;
    };
    auto state = std::make_shared<State>();
    return [state](double fraction, std::string_view stage) {
        const int decile = static_cast<int>(std::floor(std::clamp(fraction, 0.0, 1.0) * 10.0));
        if (stage != state->stage || decile != state->lastDecile) {
            state->stage = std::string(stage);
            state->lastDecile = decile;
            std::fprintf(stderr, "fray-cli: %.*s %d%%\n", static_cast<int>(stage.size()), stage.data(), decile * 10);
        }
        return true;
    };
}

void stderrNote(std::string_view note) {
    std::fprintf(stderr, "fray-cli: %.*s\n", static_cast<int>(note.size()), note.data());
}

}  // namespace fray::cli
