// core/setup: a new duel's action set derived from the project, and a duel's
// or chase's spec checked against the project as its parameters are edited.
#include <gtest/gtest.h>

#include "fray/prep/project.h"
#include "fray/setup/plan_setup.h"
#include "fray/setup/scene_setup.h"

using namespace fray;
using namespace fray::setup;

TEST(PlanSetup, ANewDuelFightsWithTheTakesThatHoldAttacks) {
    auto p = prep::loadProject(FRAY_DEMO_PROJECT);
    ASSERT_TRUE(p.ok()) << p.error().message;
    const ActionSet set = defaultDuelActionSet(*p);
    // The demo library: two shadow-boxing takes hold punches and kicks; walking,
    // running, carrying and falling do not.
    EXPECT_EQ(set.motions, (std::vector<std::string>{"shadowbox_energetic", "shadowbox_tired"}));
    EXPECT_EQ(set.actions, (std::vector<std::string>{"@punch", "@kick", "@avoid", "@dodge", "@block", "@step", "@transition", "@turn",
                                                     "@idle"}))
        << "vocabulary order; reactions (pushed, falling) are forced by hits, not chosen";
    SceneSetup s = makeSetup("duel", SetupKind::Duel);
    ASSERT_TRUE(applyActionSet(s, set));
    EXPECT_EQ(parameter(s, "/characters/1/motions").value_or(""), R"(["shadowbox_energetic","shadowbox_tired"])");
    EXPECT_TRUE(checkPlanSetup(s, *p, "demo.frayproj")) << checkPlanSetup(s, *p, "demo.frayproj").error().message;

    // A project without attacks: no set (the duel allows every take's actions).
    prep::Project walking = *p;
    std::erase_if(walking.motions, [](const prep::ProjectMotion& m) { return m.id.starts_with("shadowbox"); });
    walking.combos = {};
    EXPECT_EQ(defaultDuelActionSet(walking), ActionSet{});
}

TEST(PlanSetup, AnEditSimulateCannotReadIsNamed) {
    auto p = prep::loadProject(FRAY_DEMO_PROJECT);
    ASSERT_TRUE(p.ok()) << p.error().message;
    const SceneSetup good = makeSetup("duel", SetupKind::Duel);
    ASSERT_TRUE(checkPlanSetup(good, *p, "demo.frayproj"));
    const struct {
        const char* pointer;
        const char* value;
        const char* says;
    } bad[] = {
        {"/characters/0/preset", R"("boxer")", "/characters/0/preset: unknown preset 'boxer'"},
        {"/characters/1/weights/w_r", "-1", "/characters/1/weights/w_r: must be between 0 and 1e6"},
        {"/characters/1/weights/r_d", "1000", "/characters/1/weights/r_d: must be between 0 and 100"},
        {"/characters/0/weights/catches", "3", "/characters/0/weights/catches"},
        {"/characters/0/actions", R"(["@moonwalk"])", "unknown annotation 'moonwalk'"},
        {"/characters/0/motions", R"(["nowhere"])", "no motion 'nowhere'"},
        {"/characters/0/actions", "[]", "/characters/0/actions"},
    };
    for (const auto& b : bad) {
        SceneSetup s = good;
        ASSERT_TRUE(setParameter(s, b.pointer, b.value));
        const Status st = checkPlanSetup(s, *p, "demo.frayproj");
        ASSERT_FALSE(st) << b.pointer;
        EXPECT_NE(st.error().message.find(b.says), std::string::npos) << st.error().message;
        EXPECT_NE(st.error().message.find("setup 'duel'"), std::string::npos) << st.error().message;
    }
}
