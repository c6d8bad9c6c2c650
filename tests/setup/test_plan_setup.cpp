// core/setup: a new duel's action set derived from the project, and a duel's
// or chase's spec checked against the project as its parameters are edited,
// a patch kind's as compose reads it, and the painted floor's scale.
#include <gtest/gtest.h>

#include <cmath>

#include "fray/prep/project.h"
#include "fray/setup/convert.h"
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

// The check of a duel edit reads the setup before and after against one
// context (presets and catalogue built once): the same answers as the
// project-taking form.
TEST(PlanSetup, OneContextChecksBeforeAndAfter) {
    auto p = prep::loadProject(FRAY_DEMO_PROJECT);
    ASSERT_TRUE(p.ok()) << p.error().message;
    auto context = planCheckContext(*p, "demo.frayproj");
    ASSERT_TRUE(context) << context.error().message;
    EXPECT_GT(context->catalogue.size(), 0);
    SceneSetup s = makeSetup("duel", SetupKind::Duel);
    EXPECT_TRUE(checkPlanSetup(s, *context));
    ASSERT_TRUE(setParameter(s, "/characters/1/reactions", R"(["@pushed"])"));
    EXPECT_TRUE(checkPlanSetup(s, *context)) << "a reactions list simulate reads";
    ASSERT_TRUE(setParameter(s, "/characters/1/reactions", R"(["@moonwalk"])"));
    const Status st = checkPlanSetup(s, *context);
    ASSERT_FALSE(st);
    EXPECT_EQ(st.error().message, checkPlanSetup(s, *p, "demo.frayproj").error().message);
    EXPECT_NE(st.error().message.find("setup 'duel': /characters/1/reactions/0"), std::string::npos) << st.error().message;
}

// A patch kind's setup read as compose reads it: the rat's nested speed and
// its other numbers, ranges included, and fields compose does not know.
TEST(PlanSetup, ComposeKindsAreCheckedAsComposeReadsThem) {
    const std::vector<sim::PatternList> none;
    SceneSetup rat = makeSetup("rat", SetupKind::Rat);
    ASSERT_TRUE(checkComposeSetup(rat, none)) << checkComposeSetup(rat, none).error().message;
    const struct {
        const char* pointer;
        const char* value;
        const char* says;
    } bad[] = {
        {"/rat/speed", "20", "setup 'rat': /rat/speed: must be in [0.3, 10] m/s"},
        {"/rat/speed", "0.1", "/rat/speed"},
        {"/rat/start", "-1", "/rat/start"},
        {"/rat/pace", "3", "/rat/pace: unknown field"},
        {"/bumps", "2", "/bumps: must be in [0, 1]"},
        {"/spacing", "0.1", "/spacing"},
    };
    for (const auto& b : bad) {
        SceneSetup s = rat;
        ASSERT_TRUE(setParameter(s, b.pointer, b.value));
        const Status st = checkComposeSetup(s, none);
        ASSERT_FALSE(st) << b.pointer;
        EXPECT_NE(st.error().message.find(b.says), std::string::npos) << st.error().message;
    }
    SceneSetup fast = rat;
    ASSERT_TRUE(setParameter(fast, "/rat/speed", "4"));
    EXPECT_TRUE(checkComposeSetup(fast, none));
    EXPECT_FALSE(checkComposeSetup(makeSetup("duel", SetupKind::Duel), none)) << "not a compose kind";
}

// The painted floor's scale: pixels and origin kept, the chain starts on
// their pixels, the spec's copy follows; out of (0.001, 10] refused naming
// the setup and the field.
TEST(PlanSetup, FloorScaleKeepsThePixelsAndTheStarts) {
    SceneSetup d = makeSetup("domino", SetupKind::Domino);
    ASSERT_TRUE(setDominoStarts(d, {{0.5, {-5, 0}}, {3.0, {5, 1}}}));
    const FloorPaint was = *d.floor;
    ASSERT_TRUE(setFloorScale(d, 0.2));
    EXPECT_EQ(d.floor->metresPerPixel, 0.2);
    EXPECT_EQ(d.floor->painted, was.painted);
    EXPECT_EQ(d.floor->origin, was.origin);
    const auto starts = dominoStarts(d);
    ASSERT_EQ(starts.size(), 2u);
    EXPECT_EQ(starts[0].pos, (Point{0, 6}));
    EXPECT_EQ(starts[1].pos, (Point{20, 8}));
    EXPECT_EQ(starts[1].time, 3.0);
    EXPECT_EQ(parameter(d, "/floor/metres_per_pixel").value_or(""), "0.2");
    EXPECT_TRUE(checkComposeSetup(d, {}));
    for (double bad : {0.001, 0.0, -1.0, 11.0, std::nan("")}) {
        SceneSetup s = d;
        const Status st = setFloorScale(s, bad);
        ASSERT_FALSE(st) << bad;
        EXPECT_NE(st.error().message.find("setup 'domino': /floor/metres_per_pixel"), std::string::npos) << st.error().message;
        EXPECT_EQ(s, d) << "unchanged";
    }
    SceneSetup r = makeSetup("rat", SetupKind::Rat);
    EXPECT_FALSE(setFloorScale(r, 0.2)) << "no painted floor";
}
