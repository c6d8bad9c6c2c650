// The shape of core/sim: the interaction engine's explicit state (reaction
// pools and choices kept by value), and an action library that owns what it
// reads.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <optional>
#include <thread>
#include <vector>

#include "demo_world.h"
#include "fray/sim/action_library.h"
#include "interaction.h"

namespace fray::sim {
namespace {

using test::demoWorld;

bool contains(const std::vector<int>& pool, int action) { return std::find(pool.begin(), pool.end(), action) != pool.end(); }

// The reactive clips of the demo library: falls and pushes, and an idle to be hit in.
struct Pools {
    std::vector<int> falls, pushes;
    int idle = -1;
};
Pools demoPools(const ActionLibrary& lib) {
    Pools p;
    for (int a = 0; a < lib.size(); ++a) {
        if (lib.action(a).is(kFalling)) p.falls.push_back(a);
        else if (lib.action(a).is(kPushed)) p.pushes.push_back(a);
        else if (lib.action(a).is(kIdle) && p.idle < 0) p.idle = a;
    }
    return p;
}

// A pool is kept by its clips, not by where the caller kept them: the same
// vector refilled for another character (one address, two pools) gets
// choices from its new clips. (The choice cache used to be keyed by the
// pool's address and answered the second pool from the first one's clips.)
TEST(InteractionEngine, ReactionPoolsAreKeptByValue) {
    const auto& lib = demoWorld().library;
    const Pools p = demoPools(lib);
    ASSERT_FALSE(p.falls.empty());
    ASSERT_FALSE(p.pushes.empty());
    ASSERT_GE(p.idle, 0);
    detail::InteractionEngine engine(lib);
    std::vector<int> pool = p.falls;
    const int falls = engine.addPool(pool);
    pool = p.pushes;
    const int pushes = engine.addPool(pool);
    EXPECT_NE(falls, pushes);
    EXPECT_EQ(engine.addPool(p.falls), falls) << "equal pools share one id";
    const detail::Playing victim{p.idle, 0.0, 0.0, RootXf{}};
    for (const bool strong : {true, false}) {
        for (const RootXf pusher : {RootXf{{0.0f, 1.0f}, 0.0}, RootXf{{1.0f, 0.0f}, 0.0}, RootXf{{0.0f, -1.0f}, 0.0}}) {
            const auto a = engine.react(victim, pusher, 0.4, strong, falls);
            const auto b = engine.react(victim, pusher, 0.4, strong, pushes);
            EXPECT_TRUE(contains(p.falls, a.action)) << "fall pool chose " << a.action;
            EXPECT_TRUE(contains(p.pushes, b.action)) << "push pool chose " << b.action;
            // The same choice from an engine that met the pools in the other
            // order and asks in the other order (nothing depends on history).
            detail::InteractionEngine fresh(lib);
            const int pushes2 = fresh.addPool(p.pushes), falls2 = fresh.addPool(p.falls);
            EXPECT_EQ(fresh.react(victim, pusher, 0.4, strong, pushes2).action, b.action);
            EXPECT_EQ(fresh.react(victim, pusher, 0.4, strong, falls2).action, a.action);
            // The reaction continues the victim's pose: its first frame is
            // placed so that the clip at its start offset stands where the victim stood.
            const RootXf at = a.root * lib.rootAt(a.action, a.offset);
            const RootXf was = victim.placement(lib, 0.4);
            EXPECT_NEAR(at.pos.x, was.pos.x, 1e-4);
            EXPECT_NEAR(at.pos.y, was.pos.y, 1e-4);
            EXPECT_GT(a.end, 0.4);
        }
    }
}

// Threads each keep their own choices and agree with one another.
TEST(InteractionEngine, ChoicesAgreeAcrossThreads) {
    const auto& lib = demoWorld().library;
    const Pools p = demoPools(lib);
    ASSERT_FALSE(p.pushes.empty());
    detail::InteractionEngine engine(lib);
    const int pool = engine.addPool(p.pushes);
    const detail::Playing victim{p.idle, 0.0, 0.0, RootXf{}};
    const RootXf pusher{{0.3f, 1.0f}, 0.0};
    const int expected = engine.react(victim, pusher, 0.2, false, pool).action;
    std::vector<int> seen(4, -2);
    std::vector<std::thread> threads;
    for (std::size_t k = 0; k < seen.size(); ++k) {
        threads.emplace_back([&, k] { seen[k] = engine.react(victim, pusher, 0.2, false, pool).action; });
    }
    for (auto& t : threads) t.join();
    for (const int s : seen) EXPECT_EQ(s, expected);
}

// A library keeps the motions it was built from: what the caller does with
// its own copy afterwards (change it, free it) does not reach the library.
// (It used to point into the caller's motions: a change showed through, and
// reading them once freed read freed memory.)
TEST(ActionLibraryShape, OutlivesTheMotionsItWasBuiltFrom) {
    const auto& world = demoWorld();
    std::optional<ActionLibrary> lib;
    auto motions = std::make_unique<std::vector<prep::LoadedMotion>>(world.motions);
    auto built = buildActionLibrary(world.project, *motions, world.graph);
    ASSERT_TRUE(built) << built.error().message;
    lib.emplace(std::move(*built));
    auto sameJoints = [&] {
        for (int m = 0; m < lib->motionCount(); ++m) {
            EXPECT_EQ(lib->motion(m).joints.pelvis, world.motions[static_cast<std::size_t>(m)].joints.pelvis);
            EXPECT_EQ(lib->motion(m).joints.leftHand, world.motions[static_cast<std::size_t>(m)].joints.leftHand);
        }
    };
    for (auto& m : *motions) m.joints.pelvis = m.joints.leftHand = -7;  // the caller reuses its copy
    sameJoints();
    motions.reset();  // and frees it
    sameJoints();
    ASSERT_EQ(lib->size(), world.library.size());
    ASSERT_EQ(lib->motionCount(), static_cast<int>(world.motions.size()));
    for (int a = 0; a < lib->size(); ++a) {
        EXPECT_EQ(lib->frameAt(a, 0.3), world.library.frameAt(a, 0.3));
        const auto& m = lib->motion(lib->action(a).motion);
        EXPECT_EQ(m.motion.frameCount(), world.motions[static_cast<std::size_t>(lib->action(a).motion)].motion.frameCount());
    }
    // Forced reactions match poses read from those motions.
    const Pools p = demoPools(*lib);
    detail::InteractionEngine engine(*lib);
    const int pool = engine.addPool(p.pushes);
    EXPECT_GE(engine.react({p.idle, 0.0, 0.0, RootXf{}}, RootXf{{0.0f, 1.0f}, 0.0}, 0.3, false, pool).action, 0);
}

}  // namespace
}  // namespace fray::sim
