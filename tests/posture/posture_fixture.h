#pragma once
// Scenes the posture tests and benchmark run: the README duel and the
// one-vs-many fight composed from the demo PatternLists, built in memory.
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "fray/sim/compose.h"
#include "fray/sim/patches.h"
#include "fray/sim/patterns.h"
#include "fray/sim/planner.h"
#include "fray/sim/spec.h"
#include "sim/demo_world.h"

namespace fray::test {

inline std::string readText(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error("cannot read " + path);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

// A planned scene from a spec file of resources/demo (tree expansion).
inline sim::Scene plannedScene(const std::string& specPath) {
    const auto& w = demoWorld();
    auto spec = sim::parseSceneSpec(readText(specPath), specPath, w.library, sim::builtinPresets());
    if (!spec) throw std::runtime_error(spec.error().message);
    auto scene = sim::simulate(w.library, w.project.combos, *spec);
    if (!scene) throw std::runtime_error(scene.error().message);
    return std::move(*scene);
}

// Patches of the named demo PatternLists, connected.
inline sim::PatchLibrary demoPatches(std::initializer_list<const char*> names) {
    sim::PatchLibrary out;
    for (const char* name : names) {
        bool found = false;
        for (const auto& p : sim::defaultPatterns()) {
            if (p.name != name) continue;
            found = true;
            auto st = sim::generatePatches(demoWorld().library, p, sim::PatternSet{}, out);
            if (!st) throw std::runtime_error(st.error().message);
        }
        if (!found) throw std::runtime_error(std::string("no pattern ") + name);
    }
    sim::buildConnections(demoWorld().library, out);
    return out;
}

// A composed scene from a spec file of resources/demo.
inline sim::Scene composedScene(const std::string& specPath, const sim::PatchLibrary& patches) {
    auto spec = sim::parseComposeSpec(readText(specPath), specPath, patches);
    if (!spec) throw std::runtime_error(spec.error().message);
    auto scene = sim::compose(demoWorld().library, patches, *spec);
    if (!scene) throw std::runtime_error(scene.error().message);
    return std::move(*scene);
}

}  // namespace fray::test
