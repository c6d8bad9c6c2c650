// The indexed closest-enemy search of a graph-driven match (enemy_index.h)
// against its reference, the plain rule with a full scan, on random
// configurations: teams in lines, crowds, far-apart teams, far-flung bodies
// (the sparse fallback), bodies on the same spot (ties), two, three or six sides,
// and exact placements anywhere within the slack of the indexed positions.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "fray/igraph/enemy_index.h"

namespace {

using fray::igraph::closestEnemyScan;
using fray::igraph::EnemyIndex;

struct Config {
    std::vector<glm::vec2> here, exact;
    std::vector<int> sides;
    double slack = 0;
};

Config randomConfig(std::mt19937_64& rng, int kind) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    Config c;
    const int n = 1 + static_cast<int>(u(rng) * (kind == 0 ? 12 : 400));
    const double pick = u(rng);
    const int sideCount = pick < 0.15 ? 3 : (pick < 0.25 ? 6 : 2);  // 6: more sides than the coarse grids take
    const double extent = kind == 3 ? 5e4 : 2.0 + u(rng) * 80.0;  // kind 3: far-flung, the sparse path
    const double gap = kind == 2 ? 20.0 + u(rng) * 60.0 : 0.0;    // kind 2: two teams far apart
    c.slack = u(rng) < 0.2 ? 0.0 : u(rng) * 0.6;
    for (int i = 0; i < n; ++i) {
        const int side = static_cast<int>(u(rng) * sideCount) % sideCount;
        glm::vec2 p;
        if (i > 0 && u(rng) < 0.05) {
            p = c.here[static_cast<std::size_t>(u(rng) * i) % c.here.size()];  // the same spot: ties
        } else {
            p = {static_cast<float>(u(rng) * extent - extent / 2), static_cast<float>(u(rng) * extent - extent / 2)};
            if (kind == 2) p.y += static_cast<float>(side == 0 ? -gap : gap);
            if (kind == 1) p = glm::round(p / 1.6f) * 1.6f;  // lines 1.6 m apart, as teamStarts
        }
        c.here.push_back(p);
        c.sides.push_back(side);
        // Anywhere within the slack (sometimes exactly on it, sometimes not moved).
        const double a = u(rng) * 6.283185307179586, r = u(rng) < 0.2 ? 0.0 : (u(rng) < 0.3 ? 1.0 : u(rng)) * c.slack * 0.999;
        c.exact.push_back(p + glm::vec2(static_cast<float>(r * std::cos(a)), static_cast<float>(r * std::sin(a))));
    }
    return c;
}

TEST(IgraphEnemyIndex, MatchesFullScanOnRandomConfigurations) {
    std::mt19937_64 rng(24);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int queries = 0, far = 0, none = 0;
    for (int k = 0; k < 600; ++k) {
        const Config c = randomConfig(rng, k % 4);
        EnemyIndex index;
        index.build(&c.here, &c.sides);
        index.setSlack(c.slack);
        auto where = [&](int o) { return c.exact[static_cast<std::size_t>(o)]; };
        for (int q = 0; q < 40; ++q) {
            const int who = static_cast<int>(u(rng) * static_cast<double>(c.here.size())) % static_cast<int>(c.here.size());
            // The decider's own exact place, or a point anywhere near the bodies.
            glm::vec2 p = c.exact[static_cast<std::size_t>(who)];
            if (q % 3 == 2) p += glm::vec2(static_cast<float>(u(rng) * 30 - 15), static_cast<float>(u(rng) * 30 - 15));
            const int side = c.sides[static_cast<std::size_t>(who)];
            const int want = closestEnemyScan(c.here, c.sides, p, side, where);
            const int got = index.closest(p, side, where);
            ASSERT_EQ(got, want) << "configuration " << k << " (" << c.here.size() << " bodies, slack " << c.slack << "), query " << q;
            ++queries;
            if (want < 0) {
                ++none;
            } else if (glm::length(glm::floor(p / 2.0f) - glm::floor(c.here[static_cast<std::size_t>(want)] / 2.0f)) > 2.9f) {
                ++far;
            }
        }
    }
    // The configurations reach every branch: the near rings, the search of all, no enemy at all.
    EXPECT_GT(far, 1000);
    EXPECT_GT(none, 10);
    EXPECT_EQ(queries, 600 * 40);
}

TEST(IgraphEnemyIndex, NearbyCellsAsTheBlowSearchSeesThem) {
    std::mt19937_64 rng(7);
    for (int k = 0; k < 200; ++k) {
        const Config c = randomConfig(rng, k % 4);
        EnemyIndex index;
        index.build(&c.here, &c.sides);
        const auto& p = c.here[static_cast<std::size_t>(k) % c.here.size()];
        const int cx = fray::igraph::enemyCellOf(p.x), cz = fray::igraph::enemyCellOf(p.y);
        std::vector<int> seen(c.here.size(), 0), want(c.here.size(), 0);
        index.forNear(cx, cz, 1, [&](int o) { ++seen[static_cast<std::size_t>(o)]; });
        for (std::size_t o = 0; o < c.here.size(); ++o) {
            want[o] = std::abs(fray::igraph::enemyCellOf(c.here[o].x) - cx) <= 1 && std::abs(fray::igraph::enemyCellOf(c.here[o].y) - cz) <= 1;
        }
        ASSERT_EQ(seen, want) << "configuration " << k;
    }
}

TEST(IgraphEnemyIndex, NoEnemyNoBodies) {
    EnemyIndex index;
    std::vector<glm::vec2> here;
    std::vector<int> sides;
    index.build(&here, &sides);
    EXPECT_EQ(index.closest({0, 0}, 0, [&](int) { return glm::vec2(0); }), -1);
    here = {{0, 0}, {3, 1}};
    sides = {1, 1};
    index.build(&here, &sides);
    EXPECT_EQ(index.closest({0, 0}, 1, [&](int o) { return here[static_cast<std::size_t>(o)]; }), -1);
    EXPECT_EQ(index.closest({40, 0}, 0, [&](int o) { return here[static_cast<std::size_t>(o)]; }), 1);
}

}  // namespace
