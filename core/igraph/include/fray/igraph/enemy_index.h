#pragma once
// The closest-enemy search of a graph-driven match (SPEC 3.5), indexed.
//
// A match keeps every body's pelvis at the start of a step ("here") and asks,
// at decisions within the step, for the enemy closest to a point at the
// decision's exact time. The rule it has always played by (kept exactly, so
// scenes stay byte-identical): in a grid of 2 m cells of the "here"
// positions, the first ring (Chebyshev 0, 1 or 2 cells around the point's
// cell) holding an enemy, plus one ring more (at most ring 2), are the
// candidates, compared by their exact placement; when rings 0-2 hold no
// enemy, every enemy is compared. Ties go to the lower index.
//
// closestEnemyScan() is that rule written plainly (a hash grid, and a full
// scan placing every enemy): the reference. EnemyIndex gives the same answer
// from a flat grid, placing only the candidates that can win: each body is
// known to be within `slack` metres of its "here" position at any time the
// match asks about, so a candidate whose "here" is farther than the best
// exact distance plus the slack is skipped, and the search for the closest
// of all enemies goes out ring by ring (in a coarse 8 m grid of each enemy
// side) and stops when no cell left can hold a nearer one.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <vector>

#include <glm/glm.hpp>

namespace fray::igraph {

inline constexpr double kEnemyGridCell = 2.0;  // m
inline int enemyCellOf(float v) { return static_cast<int>(std::floor(static_cast<double>(v) / kEnemyGridCell)); }
inline float enemyDistance2(glm::vec2 a, glm::vec2 b) {
    const glm::vec2 d = a - b;
    return glm::dot(d, d);
}

// The reference. where(o) gives body o's exact position at the decision's time.
template <class Where>
int closestEnemyScan(const std::vector<glm::vec2>& here, const std::vector<int>& sides, glm::vec2 p, int side, Where&& where) {
    std::unordered_map<std::int64_t, std::vector<int>> grid;
    auto key = [](int x, int z) { return (static_cast<std::int64_t>(x) << 32) ^ static_cast<std::int64_t>(static_cast<std::uint32_t>(z)); };
    for (int c = 0; c < static_cast<int>(here.size()); ++c) {
        grid[key(enemyCellOf(here[static_cast<std::size_t>(c)].x), enemyCellOf(here[static_cast<std::size_t>(c)].y))].push_back(c);
    }
    int best = -1;
    float bestD = std::numeric_limits<float>::max();
    auto consider = [&](int o) {
        if (sides[static_cast<std::size_t>(o)] == side) return;
        const float dd = enemyDistance2(where(o), p);
        if (dd < bestD || (dd == bestD && o < best)) bestD = dd, best = o;
    };
    auto scanRing = [&](int cx, int cz, int ring) {
        for (int dx = -ring; dx <= ring; ++dx) {
            for (int dz = -ring; dz <= ring; ++dz) {
                if (std::max(std::abs(dx), std::abs(dz)) != ring) continue;
                if (auto it = grid.find(key(cx + dx, cz + dz)); it != grid.end()) {
                    for (int o : it->second) consider(o);
                }
            }
        }
    };
    const int cx = enemyCellOf(p.x), cz = enemyCellOf(p.y);
    for (int ring = 0; ring <= 2 && best < 0; ++ring) {
        scanRing(cx, cz, ring);
        if (best >= 0 && ring < 2) {
            scanRing(cx, cz, ring + 1);
            break;
        }
    }
    if (best < 0) {
        for (int o = 0; o < static_cast<int>(here.size()); ++o) consider(o);
    }
    return best;
}

class EnemyIndex {
public:
    // Indexes the "here" positions and sides (kept by pointer: they must
    // outlive the index and not change until the next build).
    void build(const std::vector<glm::vec2>* here, const std::vector<int>* sides) {
        here_ = here;
        sides_ = sides;
        const int n = static_cast<int>(here->size());
        items_.clear();
        cellStart_.clear();
        groups_.clear();
        sparse_ = false;
        if (n == 0) {
            nx_ = nz_ = 0;
            return;
        }
        int x0 = std::numeric_limits<int>::max(), z0 = x0, x1 = std::numeric_limits<int>::min(), z1 = x1;
        for (const auto& q : *here) {
            if (!std::isfinite(q.x) || !std::isfinite(q.y) || std::fabs(q.x) > 1e6f || std::fabs(q.y) > 1e6f) {
                makeSparse();
                return;
            }
            const int cx = enemyCellOf(q.x), cz = enemyCellOf(q.y);
            x0 = std::min(x0, cx), x1 = std::max(x1, cx), z0 = std::min(z0, cz), z1 = std::max(z1, cz);
        }
        const std::int64_t cells = (static_cast<std::int64_t>(x1) - x0 + 1) * (static_cast<std::int64_t>(z1) - z0 + 1);
        if (cells > 64 * static_cast<std::int64_t>(n) + 4096) {
            makeSparse();  // far-flung bodies: the plain rule is cheaper than an empty grid
            return;
        }
        x0_ = x0, z0_ = z0, nx_ = x1 - x0 + 1, nz_ = z1 - z0 + 1;
        cellStart_.assign(static_cast<std::size_t>(cells) + 1, 0);
        std::vector<int> cellOf(static_cast<std::size_t>(n));
        for (int c = 0; c < n; ++c) {
            const auto& q = (*here)[static_cast<std::size_t>(c)];
            const int k = (enemyCellOf(q.y) - z0_) * nx_ + (enemyCellOf(q.x) - x0_);
            cellOf[static_cast<std::size_t>(c)] = k;
            ++cellStart_[static_cast<std::size_t>(k) + 1];
        }
        for (std::size_t k = 1; k < cellStart_.size(); ++k) cellStart_[k] += cellStart_[k - 1];
        items_.resize(static_cast<std::size_t>(n));
        std::vector<int> fill(cellStart_.begin(), cellStart_.end() - 1);
        for (int c = 0; c < n; ++c) {
            const auto& q = (*here)[static_cast<std::size_t>(c)];
            items_[static_cast<std::size_t>(fill[static_cast<std::size_t>(cellOf[static_cast<std::size_t>(c)])]++)] = {q, c, (*sides)[static_cast<std::size_t>(c)]};
        }
        buildGroups();
    }
    // Visits every body whose "here" cell is within `ring` cells (Chebyshev) of (cx, cz), in no set order.
    template <class F>
    void forNear(int cx, int cz, int ring, F&& f) const {
        if (sparse_) {
            for (const auto& it : items_) {
                if (std::abs(enemyCellOf(it.here.x) - cx) <= ring && std::abs(enemyCellOf(it.here.y) - cz) <= ring) f(it.index);
            }
            return;
        }
        for (int r = 0; r <= ring; ++r) {
            forRing(cx, cz, r, [&](const Item& it) {
                f(it.index);
                return true;
            });
        }
    }
    // How far (m) any body may be from its "here" position when asked about.
    void setSlack(double slack) { slack_ = slack; }
    double slack() const { return slack_; }

    // The closest enemy of `side` to p, as closestEnemyScan() finds it.
    template <class Where>
    int closest(glm::vec2 p, int side, Where&& where) const {
        if (sparse_ || !here_) return here_ ? closestEnemyScan(*here_, *sides_, p, side, where) : -1;
        if (items_.empty()) return -1;
        const int cx = enemyCellOf(p.x), cz = enemyCellOf(p.y);
        // The first ring (0-2) holding an enemy.
        int first = -1;
        for (int ring = 0; ring <= 2 && first < 0; ++ring) {
            forRing(cx, cz, ring, [&](const Item& it) {
                if (it.side != side) first = ring;
                return first < 0;
            });
        }
        Best b;
        if (first >= 0) {
            const int last = std::min(first + 1, 2);
            for (int ring = 0; ring <= last; ++ring) {
                forRing(cx, cz, ring, [&](const Item& it) {
                    if (it.side != side) consider(b, it, p, where);
                    return true;
                });
            }
            return b.index;
        }
        // None near: the closest of all. With few sides, from each enemy side's
        // coarse grid; else ring by ring outward from ring 3 of the fine one.
        if (!groups_.empty()) {
            const int fx = coarseCellOf(p.x), fz = coarseCellOf(p.y);
            for (const auto& g : groups_) {
                if (g.side == side) continue;
                const int maxRingG = std::max({fx - cx0_, cx0_ + cnx_ - 1 - fx, fz - cz0_, cz0_ + cnz_ - 1 - fz});
                for (int ring = 0; ring <= maxRingG; ++ring) {
                    if (b.index >= 0 && ring >= 2) {
                        const double lower = (ring - 1) * kCoarseCell - slack_;
                        if (lower > 0 && lower * lower > bound2(b.dist2)) break;
                    }
                    forRingOf(g.cellStart, g.items, cx0_, cz0_, cnx_, cnz_, fx, fz, ring, [&](const Item& it) {
                        consider(b, it, p, where);
                        return true;
                    });
                }
            }
            return b.index;
        }
        const int maxRing = std::max({cx - x0_, x0_ + nx_ - 1 - cx, cz - z0_, z0_ + nz_ - 1 - cz});
        for (int ring = 3; ring <= maxRing; ++ring) {
            if (b.index >= 0) {
                // Every point of ring `ring` is >= (ring - 1) cells from p.
                const double lower = (ring - 1) * kEnemyGridCell - slack_;
                if (lower > 0 && lower * lower > bound2(b.dist2)) break;
            }
            forRing(cx, cz, ring, [&](const Item& it) {
                if (it.side != side) consider(b, it, p, where);
                return true;
            });
        }
        return b.index;
    }

private:
    struct Item {
        glm::vec2 here;
        int index = 0, side = 0;
    };
    struct Best {
        int index = -1;
        float dist2 = std::numeric_limits<float>::max();
        double skip2 = std::numeric_limits<double>::infinity();  // "here" farther than this (squared) cannot win
    };
    // A squared distance safely above d2 (float rounding of the exact placement).
    static double bound2(float d2) {
        const double d = std::sqrt(static_cast<double>(d2)) * (1 + 1e-5) + 1e-4;
        return d * d;
    }
    template <class Where>
    void consider(Best& b, const Item& it, glm::vec2 p, Where&& where) const {
        // Its exact placement is within slack of "here": skip it when that cannot reach the best.
        if (static_cast<double>(enemyDistance2(it.here, p)) > b.skip2) return;
        const float dd = enemyDistance2(where(it.index), p);
        if (dd < b.dist2 || (dd == b.dist2 && it.index < b.index)) {
            b.dist2 = dd, b.index = it.index;
            const double reach = std::sqrt(bound2(dd)) + slack_;
            b.skip2 = reach * reach * (1 + 1e-6);
        }
    }
    // Visits the items of the cells on Chebyshev ring `ring` around (cx, cz) until f returns false.
    template <class F>
    void forRing(int cx, int cz, int ring, F&& f) const {
        forRingOf(cellStart_, items_, x0_, z0_, nx_, nz_, cx, cz, ring, f);
    }
    template <class F>
    static void forRingOf(const std::vector<int>& cellStart, const std::vector<Item>& items, int gx0, int gz0, int gnx, int gnz, int cx,
                          int cz, int ring, F&& f) {
        auto cell = [&](int x, int z) {
            const int gx = x - gx0, gz = z - gz0;
            if (gx < 0 || gz < 0 || gx >= gnx || gz >= gnz) return true;
            const auto k = static_cast<std::size_t>(gz * gnx + gx);
            for (int i = cellStart[k]; i < cellStart[k + 1]; ++i) {
                if (!f(items[static_cast<std::size_t>(i)])) return false;
            }
            return true;
        };
        if (ring == 0) {
            cell(cx, cz);
            return;
        }
        // Rows z = cz - ring and cz + ring in full, then the columns between them.
        for (int dz : {-ring, ring}) {
            const int z = cz + dz;
            if (z - gz0 < 0 || z - gz0 >= gnz) continue;
            for (int x = std::max(cx - ring, gx0); x <= std::min(cx + ring, gx0 + gnx - 1); ++x) {
                if (!cell(x, z)) return;
            }
        }
        for (int dx : {-ring, ring}) {
            const int x = cx + dx;
            if (x - gx0 < 0 || x - gx0 >= gnx) continue;
            for (int z = std::max(cz - ring + 1, gz0); z <= std::min(cz + ring - 1, gz0 + gnz - 1); ++z) {
                if (!cell(x, z)) return;
            }
        }
    }

    static constexpr double kCoarseCell = 8.0;  // m: the per-side grids for the search of all enemies
    static int coarseCellOf(float v) { return static_cast<int>(std::floor(static_cast<double>(v) / kCoarseCell)); }
    struct Group {
        int side = 0;
        std::vector<int> cellStart;
        std::vector<Item> items;
    };
    // One coarse grid per side (at most 4 sides; more search the fine grid).
    void buildGroups() {
        groups_.clear();
        const auto& here = *here_;
        const auto& sides = *sides_;
        int x0 = std::numeric_limits<int>::max(), z0 = x0, x1 = std::numeric_limits<int>::min(), z1 = x1;
        for (std::size_t c = 0; c < here.size(); ++c) {
            const int fx = coarseCellOf(here[c].x), fz = coarseCellOf(here[c].y);
            x0 = std::min(x0, fx), x1 = std::max(x1, fx), z0 = std::min(z0, fz), z1 = std::max(z1, fz);
            bool known = false;
            for (const auto& g : groups_) known = known || g.side == sides[c];
            if (!known) {
                if (groups_.size() == 4) {
                    groups_.clear();
                    return;
                }
                groups_.push_back({sides[c], {}, {}});
            }
        }
        cx0_ = x0, cz0_ = z0, cnx_ = x1 - x0 + 1, cnz_ = z1 - z0 + 1;
        const auto cells = static_cast<std::size_t>(cnx_) * static_cast<std::size_t>(cnz_);
        for (auto& g : groups_) {
            g.cellStart.assign(cells + 1, 0);
            for (std::size_t c = 0; c < here.size(); ++c) {
                if (sides[c] != g.side) continue;
                ++g.cellStart[static_cast<std::size_t>((coarseCellOf(here[c].y) - cz0_) * cnx_ + (coarseCellOf(here[c].x) - cx0_)) + 1];
            }
            for (std::size_t k = 1; k < g.cellStart.size(); ++k) g.cellStart[k] += g.cellStart[k - 1];
            g.items.resize(static_cast<std::size_t>(g.cellStart.back()));
            std::vector<int> fill(g.cellStart.begin(), g.cellStart.end() - 1);
            for (std::size_t c = 0; c < here.size(); ++c) {
                if (sides[c] != g.side) continue;
                const auto k = static_cast<std::size_t>((coarseCellOf(here[c].y) - cz0_) * cnx_ + (coarseCellOf(here[c].x) - cx0_));
                g.items[static_cast<std::size_t>(fill[k]++)] = {here[c], static_cast<int>(c), sides[c]};
            }
        }
    }

    void makeSparse() {
        sparse_ = true;
        nx_ = nz_ = 0;
        items_.clear();
        for (int c = 0; c < static_cast<int>(here_->size()); ++c) items_.push_back({(*here_)[static_cast<std::size_t>(c)], c, (*sides_)[static_cast<std::size_t>(c)]});
    }

    const std::vector<glm::vec2>* here_ = nullptr;
    const std::vector<int>* sides_ = nullptr;
    std::vector<Item> items_;
    std::vector<int> cellStart_;
    int x0_ = 0, z0_ = 0, nx_ = 0, nz_ = 0;
    std::vector<Group> groups_;
    int cx0_ = 0, cz0_ = 0, cnx_ = 0, cnz_ = 0;
    double slack_ = 0;
    bool sparse_ = false;
};

}  // namespace fray::igraph
