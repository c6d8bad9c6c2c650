// The off-graph look-up's spatial index (docs/IGRAPH.md, "Run time"): the
// nearest state with edges of a Next set under the SPEC 3.3 distance without
// its frame term, found in a grid over (r, theta_A, theta_B) instead of a scan.
//
// Cells are sigma_r wide in r and 2 pi / n wide in each angle (n = floor(2 pi
// / sigma_theta), so at least one sigma), so any state in a cell k cells away
// (Chebyshev, the angles wrapping) is at least k - 1 away in D. Shells of
// cells are visited outwards and the search stops when the best found is
// nearer than the next shell can be; a cell whose own lower bound exceeds the
// best is skipped. The answer is the full scan's: the smallest D, ties to the
// lowest state index (tests compare with a brute-force scan).
#include <algorithm>
#include <cmath>
#include <limits>

#include "fray/igraph/igraph.h"
#include "fray/sim/geometry.h"

namespace fray::igraph {

namespace {

constexpr double kPi = std::numbers::pi;
// Lower bounds are loosened by this much (in D units) so that rounding never
// skips a cell holding an exact tie.
constexpr double kSlack = 1e-9;
// Groups of fewer states are scanned whole (cells cost more than they save).
constexpr std::uint32_t kCellsFrom = 48;

int thetaCell(double theta, double width, int n) {
    const double t = sim::wrapAngle(theta) + kPi;  // (0, 2 pi]
    return std::clamp(static_cast<int>(std::floor(t / width)), 0, n - 1);
}

// The angle from theta to the arc [lo, lo + width] (0 inside).
double arcGap(double theta, double lo, double width) {
    const double into = sim::wrapAngle(theta - lo);
    if (into >= 0 && into <= width) return 0;
    return std::min(std::fabs(into), std::fabs(sim::wrapAngle(theta - (lo + width))));
}

}  // namespace

void Graph::indexGrids() {
    grids_.assign(withEdges_.size(), {});
    const double sr = options.scale.sigmaR, st = options.scale.sigmaTheta;
    const int nt = std::max(1, static_cast<int>(std::floor(2 * kPi / st)));
    for (std::size_t set = 0; set < withEdges_.size(); ++set) {
        const auto& list = withEdges_[set];  // sorted by r
        Grid& g = grids_[set];
        if (list.empty()) continue;
        g.nt = nt;
        g.tw = 2 * kPi / nt;
        const double maxR = std::max(0.0, states[list.back()].r);
        g.nr = std::clamp(static_cast<int>(std::floor(maxR / sr)) + 1, 1, 4096);
        const std::size_t cells = static_cast<std::size_t>(g.nr) * static_cast<std::size_t>(nt) * static_cast<std::size_t>(nt);
        auto cellOf = [&](const InteractionState& s) {
            const int ir = std::clamp(static_cast<int>(std::floor(s.r / sr)), 0, g.nr - 1);
            return (static_cast<std::size_t>(ir) * static_cast<std::size_t>(nt) + static_cast<std::size_t>(thetaCell(s.thetaA, g.tw, nt))) *
                       static_cast<std::size_t>(nt) +
                   static_cast<std::size_t>(thetaCell(s.thetaB, g.tw, nt));
        };
        std::vector<std::uint32_t> sorted(list.begin(), list.end());
        std::sort(sorted.begin(), sorted.end());
        g.start.assign(cells + 1, 0);
        for (std::uint32_t i : sorted) ++g.start[cellOf(states[i]) + 1];
        for (std::size_t c = 0; c < cells; ++c) g.start[c + 1] += g.start[c];
        g.items.resize(sorted.size());
        std::vector<std::uint32_t> fill(g.start.begin(), g.start.end() - 1);
        for (std::uint32_t i : sorted) g.items[fill[cellOf(states[i])]++] = i;
    }
}

std::size_t Graph::gridBytes() const {
    std::size_t n = 0;
    for (const auto& g : grids_) n += (g.start.capacity() + g.items.capacity()) * sizeof(std::uint32_t);
    n += packedR_.capacity() * sizeof(float);
    return n;
}

void Graph::indexBuckets() {
    // Cells of (theta_A, theta_B), each 2 pi / n wide (n = floor(pi / sigma_theta): two sigmas).
    const int n = std::clamp(static_cast<int>(std::floor(kPi / options.scale.sigmaTheta)), 1, 64);
    const double tw = 2 * kPi / n;
    thetaCells_ = n;
    const std::size_t cells = static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
    packed_.resize(states.size());
    packedR_.resize(states.size());
    cellStart_.clear();
    std::vector<std::pair<int, std::uint32_t>> order;
    for (std::size_t b = 0; b < buckets_.size(); ++b) {
        auto& bk = buckets_[b];
        bk.withEdges = 0;
        bk.cells = kNoCells;
        if (bk.end - bk.begin < kCellsFrom) {
            // Few states: kept in index order and scanned whole.
            for (std::uint32_t i = bk.begin; i < bk.end; ++i) {
                const auto& t = states[i];
                const bool withEdges = firstEdge.size() == states.size() + 1 && firstEdge[i + 1] > firstEdge[i];
                packed_[i] = {t.r, t.thetaA, t.thetaB, t.frameB, i, withEdges ? 1u : 0u};
                packedR_[i] = static_cast<float>(t.r);
                if (withEdges) ++bk.withEdges;
            }
            continue;
        }
        bk.cells = static_cast<std::uint32_t>(cellStart_.size());
        cellStart_.resize(cellStart_.size() + cells + 1);
        order.clear();
        for (std::uint32_t i = bk.begin; i < bk.end; ++i) {
            order.emplace_back(thetaCell(states[i].thetaA, tw, n) * n + thetaCell(states[i].thetaB, tw, n), i);
        }
        std::sort(order.begin(), order.end(), [&](const auto& x, const auto& y) {
            if (x.first != y.first) return x.first < y.first;
            const double rx = states[x.second].r, ry = states[y.second].r;
            return rx < ry || (rx == ry && x.second < y.second);
        });
        std::uint32_t* cs = cellStart_.data() + bk.cells;
        std::size_t k = bk.begin;
        for (std::size_t c = 0; c <= cells; ++c) {
            cs[c] = static_cast<std::uint32_t>(k);
            while (c < cells && k - bk.begin < order.size() && order[k - bk.begin].first == static_cast<int>(c)) {
                const std::uint32_t i = order[k - bk.begin].second;
                const auto& t = states[i];
                const bool withEdges = firstEdge.size() == states.size() + 1 && firstEdge[i + 1] > firstEdge[i];
                packed_[k] = {t.r, t.thetaA, t.thetaB, t.frameB, i, withEdges ? 1u : 0u};
                packedR_[k] = static_cast<float>(t.r);
                if (withEdges) ++bk.withEdges;
                ++k;
            }
        }
    }
}

void Graph::scanBucket(std::size_t bucket, const InteractionState& s, double limit, bool edgesOnlyWithFrames, int rank, double& bestD, int& best,
                       int& bestRank) const {
    const int n = thetaCells_;
    const std::size_t cells = static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
    const double tw = 2 * kPi / n, sr = options.scale.sigmaR, st = options.scale.sigmaTheta, sf = options.scale.frameSigma;
    auto bound = [&] { return std::min(limit, bestD); };
    auto consider = [&](const Packed& p) {
        double d;
        if (edgesOnlyWithFrames) {
            if (!p.hasEdges) return;
            d = std::fabs(s.r - p.r) / sr + std::fabs(sim::wrapAngle(s.thetaA - p.thetaA)) / st + std::fabs(sim::wrapAngle(s.thetaB - p.thetaB)) / st +
                std::fabs(s.frameB - p.frameB) / sf;
        } else {
            if (!(std::fabs(s.frameB - p.frameB) < sf)) return;  // D is infinite
            d = std::fabs(s.r - p.r) / sr + std::fabs(sim::wrapAngle(s.thetaA - p.thetaA)) / st + std::fabs(sim::wrapAngle(s.thetaB - p.thetaB)) / st;
        }
        if (d > limit) return;  // beyond the limit: a nearer one may lie where the limit did not look
        const int i = static_cast<int>(p.index);
        if (d < bestD || (d == bestD && rank == bestRank && i < best)) bestD = d, best = i, bestRank = rank;
    };
    const Bucket& bk = buckets_[bucket];
    if (bk.cells == kNoCells) {
        for (std::uint32_t k = bk.begin; k < bk.end; ++k) consider(packed_[k]);
        return;
    }
    const std::uint32_t* cs = cellStart_.data() + bk.cells;
    // Each angle's gap to each of its cells (in sigmas); the query's own cell first.
    double gapA[64], gapB[64];  // n <= 64
    for (int c = 0; c < n; ++c) {
        gapA[c] = arcGap(s.thetaA, -kPi + c * tw, tw) / st;
        gapB[c] = arcGap(s.thetaB, -kPi + c * tw, tw) / st;
    }
    const int home = thetaCell(s.thetaA, tw, n) * n + thetaCell(s.thetaB, tw, n);
    for (int step = -1; step < static_cast<int>(cells); ++step) {
        const int c = step < 0 ? home : step;
        if (step == home) continue;
        if (cs[c] == cs[c + 1]) continue;
        const double gap = gapA[c / n] + gapB[c % n];
        if (gap - kSlack > bound()) continue;
        const Packed* first = packed_.data() + cs[c];
        const Packed* last = packed_.data() + cs[c + 1];
        auto reach = [&] { return (bound() - gap) * sr * (1 + 1e-9) + 1e-12; };  // r within this can still do better (or tie)
        if (!std::isfinite(bound())) {
            // Nothing found yet: the few states nearest in r first, for a bound.
            const float* r0 = packedR_.data() + cs[c];
            const float* r1 = packedR_.data() + cs[c + 1];
            const auto at = std::lower_bound(r0, r1, static_cast<float>(s.r)) - r0;
            const auto n0 = std::max<std::ptrdiff_t>(0, at - 2), n1 = std::min<std::ptrdiff_t>(last - first, at + 2);
            for (auto k = n0; k < n1; ++k) consider(first[k]);
        }
        const Packed* p = first;
        if (std::isfinite(bound())) {
            // In the compact float copy of r, from a little below (rounding):
            // the exact test below decides.
            const double lo = s.r - reach();
            const float loF = static_cast<float>(lo - 1e-5 * (1 + std::fabs(lo)));
            const float* r0 = packedR_.data() + cs[c];
            const float* r1 = packedR_.data() + cs[c + 1];
            p = first + (std::lower_bound(r0, r1, loF) - r0);
        }
        for (; p != last; ++p) {
            if (std::isfinite(bound()) && p->r > s.r + reach()) break;
            consider(*p);
        }
    }
}

int Graph::nearestAnyB(const InteractionState& s) const {
    if (s.nextSet < 0 || static_cast<std::size_t>(s.nextSet) >= grids_.size()) return -1;
    const Grid& g = grids_[static_cast<std::size_t>(s.nextSet)];
    if (g.items.empty()) return -1;
    const double sr = options.scale.sigmaR, st = options.scale.sigmaTheta;
    const int nt = g.nt, nr = g.nr;
    const int ir = std::clamp(static_cast<int>(std::floor(s.r / sr)), 0, nr - 1);
    const int ia = thetaCell(s.thetaA, g.tw, nt), ib = thetaCell(s.thetaB, g.tw, nt);
    // Canonical wrapped offsets of a theta cell: -(nt - 1) / 2 .. nt / 2.
    const int oLo = -(nt - 1) / 2, oHi = nt / 2;
    double bestD = std::numeric_limits<double>::infinity();
    int best = -1;
    auto rGap = [&](int cr) {
        const double lo = cr == 0 ? -std::numeric_limits<double>::infinity() : cr * sr;
        const double hi = cr == nr - 1 ? std::numeric_limits<double>::infinity() : (cr + 1) * sr;
        return s.r < lo ? (lo - s.r) / sr : s.r > hi ? (s.r - hi) / sr : 0.0;
    };
    auto visit = [&](int dr, int oa, int ob) {
        const int cr = ir + dr;
        const int ca = ((ia + oa) % nt + nt) % nt, cb = ((ib + ob) % nt + nt) % nt;
        const std::size_t cell = (static_cast<std::size_t>(cr) * static_cast<std::size_t>(nt) + static_cast<std::size_t>(ca)) *
                                     static_cast<std::size_t>(nt) +
                                 static_cast<std::size_t>(cb);
        const std::uint32_t b = g.start[cell], e = g.start[cell + 1];
        if (b == e) return;
        const double bound = rGap(cr) + arcGap(s.thetaA, -kPi + ca * g.tw, g.tw) / st + arcGap(s.thetaB, -kPi + cb * g.tw, g.tw) / st;
        if (bound - kSlack > bestD) return;
        for (std::uint32_t k = b; k < e; ++k) {
            const std::uint32_t i = g.items[k];
            const auto& t = states[i];
            const double d = std::fabs(s.r - t.r) / sr + std::fabs(sim::wrapAngle(s.thetaA - t.thetaA)) / st +
                             std::fabs(sim::wrapAngle(s.thetaB - t.thetaB)) / st;
            if (d < bestD || (d == bestD && static_cast<int>(i) < best)) bestD = d, best = static_cast<int>(i);
        }
    };
    const int shells = std::max(nr, nt);
    for (int k = 0; k <= shells; ++k) {
        // Every cell of shell k is at least k - 1 away (each cell >= 1 unit wide).
        if (best >= 0 && bestD < (k - 1) - kSlack) break;
        const int drLo = std::max(-k, -ir), drHi = std::min(k, nr - 1 - ir);
        const int aLo = std::max(-k, oLo), aHi = std::min(k, oHi);
        for (int dr = drLo; dr <= drHi; ++dr) {
            for (int oa = aLo; oa <= aHi; ++oa) {
                if (std::abs(dr) == k || std::abs(oa) == k) {
                    for (int ob = aLo; ob <= aHi; ++ob) visit(dr, oa, ob);
                } else {
                    if (-k >= oLo) visit(dr, oa, -k);
                    if (k != 0 && k <= oHi) visit(dr, oa, k);
                }
            }
        }
    }
    return best;
}

}  // namespace fray::igraph
