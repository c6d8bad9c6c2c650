#include "cli_session.h"

#include "fray/core/atomic_file.h"

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

Result<SceneSource> readSceneSource(std::string_view verb, const std::string& spec, const std::string& setupName,
                                    const std::filesystem::path& out, std::string_view what) {
    if (spec.empty() == setupName.empty()) return makeError(std::string(verb) + ": give either --spec FILE or --setup NAME");
    SceneSource source;
    source.label = setupName.empty() ? spec : "setup '" + setupName + "'";
    if (Status st = checkSceneOutput(out); !st) return st.error();
    if (!spec.empty()) {
        auto text = readWholeFile(spec, what);
        if (!text) return text.error();
        source.specText = std::move(*text);
    }
    return source;
}

Result<setup::SceneSetup> setupToRun(std::string_view verb, const prep::Project& project, const std::string& projectFile,
                                     const std::string& name, const std::string& label) {
    auto setups = setup::projectSetups(project, projectFile);
    if (!setups) return setups.error();
    const setup::SceneSetup* found = setup::findSetup(*setups, name);
    if (!found) return makeError(projectFile + ": no setup named '" + name + "' (fray-cli setup " + projectFile + " list)");
    const bool simulate = verb == "simulate";
    if (setup::isSimulateKind(found->kind) != simulate) {
        return makeError(label + " is a " + setup::setupKindName(found->kind) + " setup: run it with " + (simulate ? "compose" : "simulate") +
                         ", not " + std::string(verb));
    }
    return *found;
}

}  // namespace fray::cli
