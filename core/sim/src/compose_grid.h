#pragma once
// A uniform grid over the floor for composition at scale: items (a
// character, a footprint) are inserted with their floor box and found again
// by box, so collision and density tests look at the neighbourhood instead of
// everyone. A query visits every item whose box shares a cell with the query
// box, each once and in increasing item order, so a test that then checks the
// exact geometry gives the same answer as a pass over every item.
// Internal to fray_sim.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "fray/sim/patches.h"

namespace fray::sim::detail {

class FloorGrid {
public:
    explicit FloorGrid(float cell = 2.0f) : cell_(cell) {}

    void insert(int item, const SweptBox& box) {
        forCells(box, [&](std::uint64_t key) { cells_[key].push_back(item); });
    }
    void insert(int item, const glm::vec2& p) { insert(item, SweptBox{p, p}); }

    // The items whose boxes share a cell with `box`, ascending, each once.
    const std::vector<int>& near(const SweptBox& box) const {
        found_.clear();
        forCells(box, [&](std::uint64_t key) {
            const auto it = cells_.find(key);
            if (it != cells_.end()) found_.insert(found_.end(), it->second.begin(), it->second.end());
        });
        std::sort(found_.begin(), found_.end());
        found_.erase(std::unique(found_.begin(), found_.end()), found_.end());
        return found_;
    }
    const std::vector<int>& near(const glm::vec2& p, float radius) const {
        return near(SweptBox{p - glm::vec2(radius), p + glm::vec2(radius)});
    }

private:
    template <class F>
    void forCells(const SweptBox& box, F&& f) const {
        if (!(box.lo.x <= box.hi.x) || !(box.lo.y <= box.hi.y)) return;  // empty (or not a number)
        const std::int64_t x0 = index(box.lo.x), x1 = index(box.hi.x), z0 = index(box.lo.y), z1 = index(box.hi.y);
        for (std::int64_t z = z0; z <= z1; ++z) {
            for (std::int64_t x = x0; x <= x1; ++x) f(key(x, z));
        }
    }
    std::int64_t index(float v) const { return static_cast<std::int64_t>(std::floor(v / cell_)); }
    static std::uint64_t key(std::int64_t x, std::int64_t z) {
        return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(x)) << 32) | static_cast<std::uint32_t>(z);
    }

    float cell_;
    std::unordered_map<std::uint64_t, std::vector<int>> cells_;
    mutable std::vector<int> found_;
};

}  // namespace fray::sim::detail
