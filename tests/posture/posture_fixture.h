#pragma once
// Scenes the posture tests and benchmark run: the README duel and the
// one-vs-many fight composed from the demo PatternLists, built in memory.
#include <cmath>
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
// rootBeam >= 0 replaces the spec's root beam (0: the exact search).
inline sim::Scene plannedScene(const std::string& specPath, int rootBeam = -1) {
    const auto& w = demoWorld();
    auto spec = sim::parseSceneSpec(readText(specPath), specPath, w.library, sim::builtinPresets());
    if (!spec) throw std::runtime_error(spec.error().message);
    if (rootBeam >= 0) spec->options.rootBeam = rootBeam;
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

// A crowd: copies of a two-character scene on a grid `spacing` m apart
// (each pair its own island when far enough), `characters` in all.
inline sim::Scene pairCrowd(const sim::Scene& pair, int characters, float spacing = 5.0f) {
    sim::Scene out = pair;
    out.characters.clear();
    out.hits.clear();
    out.catches.clear();
    const int pairs = (characters + 1) / 2;
    const int side = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(pairs))));
    for (int p = 0; p < pairs; ++p) {
        const glm::vec2 at(spacing * static_cast<float>(p % side), spacing * static_cast<float>(p / side));
        const int base = static_cast<int>(out.characters.size());
        for (int k = 0; k < 2 && base + k < characters; ++k) {
            auto c = pair.characters[static_cast<std::size_t>(k)];
            c.name += std::to_string(p);
            for (auto& inst : c.track) inst.root.pos += at;
            out.characters.push_back(std::move(c));
        }
        if (base + 1 >= characters) continue;
        for (auto h : pair.hits) {
            h.attacker += base, h.defender += base;
            out.hits.push_back(h);
        }
    }
    return out;
}

}  // namespace fray::test
