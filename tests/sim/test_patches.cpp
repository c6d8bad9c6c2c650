// Interaction Patches (SPEC 4): PatternLists, generation, the validity rules,
// connection tables, standard poses and the patch cache, on the demo project.
#include <gtest/gtest.h>

#include <cstdio>

#include "fray/sim/compose.h"
#include "fray/sim/metrics.h"
#include "fray/sim/patches.h"
#include "fray/sim/patterns.h"
#include "sim/demo_world.h"

namespace fray::sim {
namespace {

using test::demoWorld;

PatternList pattern(const std::string& name) {
    for (const auto& p : defaultPatterns()) {
        if (p.name == name) return p;
    }
    throw std::runtime_error("no pattern " + name);
}

TEST(PatchProbe, Generate) {
    const auto& lib = demoWorld().library;
    PatternSet set;
    for (const char* name : {"attack-fall", "attack-defence", "attack-defence-attack-fall", "attack-attack-fall"}) {
        PatchLibrary out;
        auto st = generatePatches(lib, pattern(name), set, out);
        ASSERT_TRUE(st) << st.error().message;
        const auto& s = out.stats;
        std::printf("%s: ics %lld paths %lld dup %lld kept %lld close %lld order %lld hit %lld missed %lld below %lld %.2fs\n", name,
                    (long long)s.initialConditions, (long long)s.paths, (long long)s.duplicates, (long long)s.kept, (long long)s.tooClose,
                    (long long)s.wrongOrder, (long long)s.unintendedHit, (long long)s.missedContact, (long long)s.belowThreshold,
                    s.seconds);
        buildConnections(lib, out);
        std::size_t t = 0, sp = 0;
        for (auto& v : out.temporal) t += v.size();
        for (auto& v : out.spatial) sp += v.size();
        std::printf("  temporal %zu spatial %zu poses %zu\n", t, sp, out.standardPoses.size());
    }
}

TEST(PatchProbe, Compose) {
    const auto& lib = demoWorld().library;
    PatternSet set;
    PatchLibrary out;
    for (const char* name : {"attack-fall", "attack-defence", "attack-defence-attack-fall", "attack-attack-fall"}) {
        ASSERT_TRUE(generatePatches(lib, pattern(name), set, out));
    }
    buildConnections(lib, out);
    for (auto kind : {SceneKind::OneVsMany, SceneKind::OneVsOne}) {
        ComposeSpec spec;
        spec.kind = kind;
        spec.enemies = 10;
        ComposeStats st;
        auto scene = compose(lib, out, spec, &st);
        ASSERT_TRUE(scene) << scene.error().message;
        const auto m = computeMetrics(*scene, lib);
        std::printf("%s: chars %zu dur %.1f hits %zu used %d linked %d recycled %d steps %d junction %.2f pen %d hitrate %.2f %.3fs\n",
                    sceneKindName(kind), scene->characters.size(), scene->duration, scene->hits.size(), st.patchesUsed,
                    st.temporalLinks, st.recycled, st.locomotionSteps, st.maxJunctionError, m.penetrationFrames, m.hitRate, st.seconds);
    }
}

}  // namespace
}  // namespace fray::sim
