// Rejected patches never compose (issue 23): on the demo project, a
// one-vs-one setup composed from a small patch library plays some attack; the
// same setup with every patch holding that attack rejected never plays it.
#include <gtest/gtest.h>

#include <map>
#include <set>

#include "fray/pipeline/setup_run.h"
#include "fray/pipeline/sim_session.h"
#include "fray/setup/convert.h"
#include "fray/setup/scene_setup.h"
#include "fray/sim/compose.h"
#include "fray/sim/patches.h"
#include "fray/sim/patterns.h"

using namespace fray;

namespace {

std::map<int, int> attacksPlayed(const sim::Scene& scene, const sim::ActionLibrary& lib) {
    std::map<int, int> out;
    for (const auto& c : scene.characters) {
        for (const auto& inst : c.track) {
            if (lib.actions()[static_cast<std::size_t>(inst.action)].is(sim::kPunch | sim::kKick)) ++out[inst.action];
        }
    }
    return out;
}

}  // namespace

TEST(RejectedPatches, NeverCompose) {
    auto ss = pipeline::openSimSession(FRAY_DEMO_PROJECT, {});
    ASSERT_TRUE(ss.ok()) << ss.error().message;
    const sim::ActionLibrary& lib = (*ss)->library;
    sim::PatternSet set;
    set.patterns = sim::defaultPatterns();
    sim::PatchLibrary patches;
    sim::GenerateOptions options;
    options.maxChoicesPerEntry = 6;
    for (const char* name : {"attack-fall", "attack-defence"}) {
        const sim::PatternList* pattern = set.find(name);
        ASSERT_TRUE(pattern) << name;
        ASSERT_TRUE(sim::generatePatches(lib, *pattern, set, patches, options).ok());
    }
    sim::buildConnections(lib, patches);
    ASSERT_GT(patches.patches.size(), 4u);

    setup::SceneSetup s = setup::makeSetup("ovo", setup::SetupKind::OneVsOne);
    ASSERT_TRUE(setup::setParameter(s, "/duration", "30").ok());
    auto spec = setup::toComposeSpec(s, patches);
    ASSERT_TRUE(spec.ok()) << spec.error().message;
    auto scene = sim::compose(lib, patches, *spec);
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    const auto played = attacksPlayed(*scene, lib);
    ASSERT_FALSE(played.empty()) << "the scene plays no attack: the test could not fail";

    // Reject every patch that plays the scene's most frequent attack, as the
    // patch browser would one by one.
    int attack = played.begin()->first;
    for (const auto& [a, n] : played) {
        if (n > played.at(attack)) attack = a;
    }
    for (std::size_t i = 0; i < patches.patches.size(); ++i) {
        bool holds = false;
        for (const auto& track : patches.patches[i].tracks) {
            for (const auto& inst : track) holds = holds || inst.action == attack;
        }
        if (holds) s.patches.rejected.push_back(static_cast<int>(i));
    }
    ASSERT_FALSE(s.patches.rejected.empty());
    ASSERT_LT(s.patches.rejected.size(), patches.patches.size()) << "every patch plays it: nothing left to compose";

    // The setup survives the project file with its verdicts.
    prep::Project p = prep::makeProject("t");
    setup::setProjectSetups(p, {s});
    auto stored = setup::projectSetups(*prep::projectFromJson(prep::projectToJson(p), "t"), "t");
    ASSERT_TRUE(stored.ok());
    ASSERT_EQ(stored->front().patches.rejected, s.patches.rejected);

    auto kept = setup::withoutRejected(patches, stored->front().patches.rejected);
    ASSERT_TRUE(kept.ok());
    EXPECT_EQ(kept->patches.size(), patches.patches.size() - s.patches.rejected.size());
    // The pipeline's run (fray-cli compose --setup, the editor's Generate) is
    // given the whole library and leaves the rejected patches out itself.
    pipeline::SetupRunStats stats;
    auto again = pipeline::runSetup(**ss, stored->front(), &patches, {}, &stats);
    ASSERT_TRUE(again.ok()) << again.error().message;
    EXPECT_GT(stats.compose.patchesUsed, 0);
    EXPECT_EQ(attacksPlayed(*again, lib).count(attack), 0u) << "a rejected patch's attack was played";
    // Without verdicts it is byte for byte the scene composed directly.
    setup::SceneSetup plainSetup = stored->front();
    plainSetup.patches.rejected.clear();
    auto plain = pipeline::runSetup(**ss, plainSetup, &patches);
    ASSERT_TRUE(plain.ok()) << plain.error().message;
    EXPECT_EQ(sim::sceneToJson(*plain, lib), sim::sceneToJson(*scene, lib));
}
