// A fighting pair going round a circle (issue 23): tree expansion's path term
// (docs/TREE_EXPANSION.md "Following a path") keeps a duel on a drawn circle
// with timed checkpoints, reaching them in order, while the pair still fights.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "fray/sim/metrics.h"
#include "sim/sim_fixture.h"

namespace fray::sim {
namespace {

struct CirclePath {
    std::string json;                    // the "path" array
    std::vector<glm::vec2> checkpoints;  // the timed ones
    std::vector<double> times;
};

// A circle of `radius` through (0, 0), centre (0, -radius), clockwise seen
// from above (first towards +x, where the opponent stands) or the other way
// (the editor's Circle tool's way, away from the opponent first), sampled
// every metre as the editor's trajectories are, with timed checkpoints at 1/4,
// 1/2 and 3/4 of the way round.
CirclePath circlePath(double radius, const std::vector<double>& times, bool clockwise = true) {
    const double length = 2 * std::numbers::pi * radius;
    auto at = [&](double s) {
        const double a = std::numbers::pi / 2 + (clockwise ? -1.0 : 1.0) * s / radius;
        return glm::vec2(static_cast<float>(radius * std::cos(a)), static_cast<float>(-radius + radius * std::sin(a)));
    };
    struct Item {
        double s;
        std::optional<double> time;
    };
    std::vector<Item> items;
    std::vector<double> cps;
    for (std::size_t k = 0; k < times.size(); ++k) cps.push_back(length * static_cast<double>(k + 1) / static_cast<double>(times.size() + 1));
    for (double s = 0; s <= length + 1e-9; s += 1.0) {
        bool near = false;
        for (double c : cps) near = near || std::fabs(c - s) < 0.3;
        if (!near) items.push_back({s, std::nullopt});
    }
    for (std::size_t k = 0; k < cps.size(); ++k) items.push_back({cps[k], times[k]});
    items.push_back({length, std::nullopt});
    std::stable_sort(items.begin(), items.end(), [](const Item& a, const Item& b) { return a.s < b.s; });
    CirclePath out;
    for (const auto& it : items) {
        const glm::vec2 p = at(it.s);
        out.json += (out.json.empty() ? "" : ", ") + std::string(R"({"x": )") + std::to_string(p.x) + R"(, "z": )" + std::to_string(p.y);
        if (it.time) {
            out.json += R"(, "time": )" + std::to_string(*it.time);
            out.checkpoints.push_back(p);
            out.times.push_back(*it.time);
        }
        out.json += "}";
    }
    return out;
}

std::string circleDuel(const CirclePath& path, const std::string& preset, int depthRed, double duration, int seed) {
    const std::string actions = R"(["@punch", "@kick", "@block", "@avoid", "@step", "@idle", "@transition", "@turn"])";
    return R"({"version": 1, "duration": )" + std::to_string(duration) + R"(, "seed": )" + std::to_string(seed) +
           R"(, "characters": [
      {"name": "red", "side": 0, "depth": )" + std::to_string(depthRed) + R"(, "preset": ")" + preset +
           R"(", "motions": ["shadowbox_energetic"], "actions": )" + actions +
           R"(, "start": {"x": 0, "z": 0, "heading_deg": 90}, "path": [)" + path.json + R"(]},
      {"name": "blue", "side": 1, "depth": 2, "preset": "general-boxer", "motions": ["shadowbox_energetic"], "actions": )" +
           actions + R"(, "start": {"x": 1.1, "z": 0, "heading_deg": -90}}]})";
}

// When red's root first comes within 0.6 m of each timed checkpoint at or
// after its time, in order (-1: never).
std::vector<double> reachedAt(const Scene& scene, const ActionLibrary& lib, const CirclePath& path) {
    std::vector<double> at(path.checkpoints.size(), -1.0);
    std::size_t next = 0;
    for (double t = 0; t <= scene.duration && next < at.size(); t += 1.0 / 30.0) {
        const int i = scene.instanceAt(0, t);
        if (i < 0) continue;
        const auto& inst = scene.characters[0].track[static_cast<std::size_t>(i)];
        const glm::vec2 p = inst.placementAt(lib, inst.clipTimeAt(t)).pos;
        if (t >= path.times[next] - 1e-9 && glm::length(p - path.checkpoints[next]) <= 0.6f) at[next++] = t;
    }
    return at;
}

// The issue's figure: a duel on a circle of 3 m (1.5 m radius) with three
// timed checkpoints a quarter of the way round apart (8, 16, 24 s; about
// 0.3 m/s, what boxing steps between blows manage): mean path error under
// 0.5 m, every checkpoint reached in order and within 2.5 s of its time, and
// blows still land. Red follows the path (general-boxer-path with the
// editor's weight for a drawn trajectory, w_path 300), blue only fights and
// keeps up with red (the pair's gap term). Both ways round (towards blue
// first, and away from it as the editor's Circle tool draws it) and two
// seeds each: before the schedule's pace after the last checkpoint, the 3x
// weight off the path and the gap term, only the first of these four kept
// the schedule, with blue 2 m away.
TEST(SimPathFollow, DuelGoesRoundACircleWithTimedCheckpoints) {
    int blows = 0;
    for (bool clockwise : {true, false}) {
        for (int seed : {1, 2}) {
            const CirclePath path = circlePath(1.5, {8.0, 16.0, 24.0}, clockwise);
            std::string text = circleDuel(path, "general-boxer-path", 3, 32.0, seed);
            text.insert(text.find(R"("preset": "general-boxer-path")"), R"("weights": {"w_path": 300}, )");
            auto scene = test::runSpec(text);
            ASSERT_TRUE(scene.ok()) << scene.error().message;
            const auto& lib = test::demoWorld().library;
            const auto m = computeMetrics(*scene, lib);
            ASSERT_TRUE(m.characters[0].pathErrorMean.has_value());
            const auto at = reachedAt(*scene, lib, path);
            // The metrics' own account of the same (pelvis, 0.6 m, at or after the time, in order).
            ASSERT_EQ(m.characters[0].checkpointsReached.size(), at.size());
            for (std::size_t k = 0; k < at.size(); ++k) EXPECT_NEAR(m.characters[0].checkpointsReached[k], at[k], 1e-6);
            const auto hits = test::landedHits(*scene);
            blows += hits[0] + hits[1];
            std::printf("circle duel (%s, seed %d): red's path error mean %.3f m (max %.2f m); checkpoints (8, 16, 24 s) reached at "
                        "%.2f, %.2f, %.2f s; hits %d / %d; mean distance %.2f m\n",
                        clockwise ? "towards blue first" : "away from blue first", seed, *m.characters[0].pathErrorMean,
                        m.characters[0].pathErrorMax.value_or(0), at[0], at[1], at[2], hits[0], hits[1],
                        m.characters[0].meanOpponentDistance.value_or(0));
            EXPECT_LT(*m.characters[0].pathErrorMean, 0.5);
            for (std::size_t k = 0; k < at.size(); ++k) {
                EXPECT_GE(at[k], 0) << "checkpoint " << k << " never reached";
                EXPECT_LT(at[k], path.times[k] + 2.5) << "checkpoint " << k << " reached late";
            }
            // Blue keeps up: 1.2 to 1.7 m from red on average, a step beyond
            // fighting reach (a plain duel keeps about 1 m); it stood off at
            // about 2 m before the gap term.
            EXPECT_LT(m.characters[0].meanOpponentDistance.value_or(99), 1.8);
        }
    }
    EXPECT_GT(blows, 0) << "the pairs no longer fight";
}

}  // namespace
}  // namespace fray::sim
