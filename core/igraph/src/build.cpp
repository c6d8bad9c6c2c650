// Building the Interaction Graph (SPEC 3.2-3.3): off-policy sampling by
// selective game-tree expansion, K-means clustering of the samples under the
// SPEC distance, edges by simulating every action of each state's Next set,
// and the coverage of tree expansion's states.
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <numeric>
#include <unordered_map>

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "fray/sim/patches.h"  // libraryFingerprint
#include "game.h"

namespace fray::igraph {

using detail::Body;
using sim::ActionLibrary;

namespace {

// A decision of a duel: both bodies, the time now 0 and the chooser at the
// origin facing +Z (the state does not depend on where the duel is).
struct Node {
    std::array<Body, 2> b;
};

Node normalise(const ActionLibrary& lib, std::array<Body, 2> b, double t) {
    const int n = detail::chooser(b);
    const sim::RootXf inv = b[static_cast<std::size_t>(n)].placement(lib, t).inverse();
    for (auto& body : b) {
        body.root = inv * body.root;
        body.start -= t;
        body.end -= t;
    }
    return {b};
}

// The archive's cells: samples closer than a fraction of the sigmas are one sample.
struct CellCoder {
    double rStep, thetaStep, frameStep;
    std::uint64_t key(const InteractionState& s) const {
        const auto rb = static_cast<std::uint64_t>(std::min(255.0, std::floor(s.r / rStep)));
        const int nTheta = static_cast<int>(std::ceil(2 * std::numbers::pi / thetaStep));
        auto tb = [&](double th) {
            const int b = static_cast<int>(std::floor((th + std::numbers::pi) / thetaStep));
            return static_cast<std::uint64_t>(std::clamp(b, 0, std::min(nTheta - 1, 31)));
        };
        const auto fb = static_cast<std::uint64_t>(std::min(1023.0, std::floor(s.frameB / frameStep)));
        return (static_cast<std::uint64_t>(s.nextSet) << 48) | (static_cast<std::uint64_t>(s.actionB) << 32) | (fb << 18) |
               (rb << 10) | (tb(s.thetaA) << 5) | tb(s.thetaB);
    }
};

struct Cell {
    double r = 0, thetaA = 0, thetaB = 0, frame = 0;
    std::int64_t count = 0;
    int nextSet = 0, actionB = 0;
    void add(const InteractionState& s) {
        r += s.r, thetaA += s.thetaA, thetaB += s.thetaB, frame += s.frameB, ++count;
        nextSet = s.nextSet, actionB = s.actionB;
    }
    InteractionState mean() const {
        const double n = static_cast<double>(count);
        return {static_cast<float>(r / n), static_cast<float>(thetaA / n), static_cast<float>(thetaB / n), nextSet, actionB,
                static_cast<float>(frame / n)};
    }
};

// Sensible start states: the chooser has just finished an idle action, the
// other stands 0.8-2.6 m away roughly facing it, idle or in any of its
// actions. Seeded.
std::vector<Node> startStates(const Rules& rules, const BuildOptions& o) {
    const auto& lib = rules.library();
    detail::Rng rng{o.seed ^ 0x5157A27ull};
    std::vector<Node> out;
    for (int k = 0; k < o.startStates; ++k) {
        const double r = rng.uniform(0.8, 2.6);
        const double thA = rng.uniform(-0.8, 0.8), thB = rng.uniform(-0.8, 0.8);
        const int idleA = rules.idle()[rng.below(rules.idle().size())];
        const bool busy = rng.uniform() < 0.5;
        const int actB = busy ? rules.actions()[rng.below(rules.actions().size())] : rules.idle()[rng.below(rules.idle().size())];
        const double clipB = rng.uniform(0.0, lib.action(actB).duration);
        Body a = detail::bodyAt(lib, idleA, lib.action(idleA).duration, {}, 0.0);
        a.end = 0;  // about to choose
        const glm::vec2 d = static_cast<float>(r) * sim::headingVector(thA);
        const sim::RootXf pb{d, sim::wrapAngle(sim::angleOf(-d) - thB)};
        Body b = detail::bodyAt(lib, actB, clipB, pb, 0.0);
        out.push_back({{a, b}});
    }
    return out;
}

// The kinds of action a user command asks for (runtime.cpp's fulfils): edges
// of different kinds are never merged.
int kindOf(const sim::LibraryAction& a) {
    if (a.is(sim::kPunch)) return 1;
    if (a.is(sim::kKick)) return 2;
    if (a.has("dodge")) return 3;
    if (a.is(sim::kAvoid)) return 4;
    if (a.is(sim::kBlock)) return 5;
    // Movements: by where they take the character (0.15 m, 0.3 rad steps).
    const int along = static_cast<int>(std::lround(a.end.pos.y / 0.15f)), side = static_cast<int>(std::lround(a.end.pos.x / 0.15f));
    const int turn = static_cast<int>(std::lround(a.end.heading / 0.3));
    return 16 + ((along & 0xff) << 16 | (side & 0xff) << 8 | (turn & 0xff));
}

struct Child {
    InteractionState sample;
    std::uint64_t key = 0;
    Node node;
    double score = 0;
    int order = 0;
};

// Every child of a node: the chooser launches each action of its (folded)
// Next set and the duel runs to its next decision.
template <class Fn>
void forEachChild(const Rules& rules, const Node& node, bool folded, Fn&& fn) {
    const auto& lib = rules.library();
    const int c = detail::chooser(node.b);
    const auto uc = static_cast<std::size_t>(c);
    const int set = rules.nextSetOf(node.b[uc].action);
    const auto& actions = folded ? rules.foldedSet(set) : rules.nextSet(set);
    const double t0 = node.b[uc].end;
    for (int a : actions) {
        std::array<Body, 2> b = node.b;
        detail::launch(lib, b[uc], a, t0);
        detail::Outcome o;
        const double t1 = detail::advanceDuel(rules, b, t0, o);
        const int n = detail::chooser(b);
        const auto un = static_cast<std::size_t>(n);
        const InteractionState s = detail::stateOf(rules, b[un], b[1 - un], t1);
        // J: blows landed within reach plus effective defences (blocked
        // blows, an avoid that leaves an attack with nothing to hit).
        double j = o.landed[uc] + o.blocked[uc];
        const auto& other = node.b[1 - uc];
        if (lib.action(a).is(sim::kAvoid) && lib.action(other.action).is(sim::kAttack) && !other.spent && o.suffered[uc] == 0) j += 1;
        fn(a, s, j, normalise(lib, b, t1));
    }
}

}  // namespace

std::size_t Graph::memoryBytes() const {
    return states.capacity() * sizeof(InteractionState) + firstEdge.capacity() * sizeof(std::uint32_t) +
           edges.capacity() * sizeof(Edge) + buckets_.capacity() * sizeof(Bucket) + states.size() * sizeof(std::uint32_t) +
           packed_.capacity() * sizeof(Packed) + cellStart_.capacity() * sizeof(std::uint32_t) + gridBytes() +
           actions.capacity() * sizeof(int) + edgeFrames.capacity() + (nearFirst.capacity() + near.capacity()) * sizeof(std::uint32_t);
}

void Graph::timeEdges(const sim::ActionLibrary& lib) {
    edgeFrames.assign(edges.size(), 0);
    auto frames = [](double seconds) {
        return static_cast<std::uint8_t>(std::clamp(std::lround(seconds * sim::kSampleRate), 1L, 255L));
    };
    for (std::size_t i = 0; i < states.size(); ++i) {
        const auto& s = states[i];
        const double leftB = lib.action(s.actionB).duration - s.frameB / sim::kSampleRate;
        for (std::uint32_t k = firstEdge[i]; k < firstEdge[i + 1]; ++k) {
            const Edge& e = edges[k];
            edgeFrames[k] = frames(e.sameChooser() ? lib.action(e.action()).duration : leftB);
        }
    }
}

void Graph::findNeighbours() {
    const std::size_t n = states.size();
    std::vector<std::array<std::uint32_t, kNeighbours>> found(n);
    std::vector<std::uint8_t> count(n, 0);
    tbb::parallel_for(std::size_t{0}, buckets_.size(), [&](std::size_t b) {
        const auto& bk = buckets_[b];
        std::vector<std::pair<double, std::uint32_t>> cand;
        for (std::uint32_t i = bk.begin; i < bk.end; ++i) {
            cand.clear();
            for (std::uint32_t j = bk.begin; j < bk.end; ++j) {
                if (j == i) continue;
                const double d = distance(states[i], states[j], options.scale);
                if (d <= options.joinRadius) cand.emplace_back(d, j);
            }
            const auto k = std::min<std::size_t>(cand.size(), kNeighbours);
            std::partial_sort(cand.begin(), cand.begin() + static_cast<std::ptrdiff_t>(k), cand.end());
            for (std::size_t q = 0; q < k; ++q) found[i][q] = cand[q].second;
            count[i] = static_cast<std::uint8_t>(k);
        }
    });
    nearFirst.assign(n + 1, 0);
    near.clear();
    for (std::size_t i = 0; i < n; ++i) {
        nearFirst[i] = static_cast<std::uint32_t>(near.size());
        near.insert(near.end(), found[i].begin(), found[i].begin() + count[i]);
    }
    nearFirst[n] = static_cast<std::uint32_t>(near.size());
}

double Graph::edgeSeconds(std::size_t edge) const {
    return edge < edgeFrames.size() ? edgeFrames[edge] / sim::kSampleRate : 0.0;
}

int Graph::frameBucket(double frame) const {
    return std::clamp(static_cast<int>(std::floor(frame / options.scale.frameSigma)), 0, 0xffff);
}

std::uint64_t Graph::bucketKey(int nextSet, int actionB, int fb) const {
    return (static_cast<std::uint64_t>(nextSet) << 40) | (static_cast<std::uint64_t>(actionB) << 16) | static_cast<std::uint64_t>(fb);
}

void Graph::index() {
    buckets_.clear();
    for (std::uint32_t i = 0; i < states.size();) {
        const auto& s = states[i];
        const std::uint64_t key = bucketKey(s.nextSet, s.actionB, frameBucket(s.frameB));
        std::uint32_t j = i + 1;
        while (j < states.size() &&
               bucketKey(states[j].nextSet, states[j].actionB, frameBucket(states[j].frameB)) == key) ++j;
        buckets_.push_back({key, i, j});
        i = j;
    }
    std::sort(buckets_.begin(), buckets_.end(), [](const Bucket& a, const Bucket& b) { return a.key < b.key; });
    indexBuckets();
    int sets = 0;
    for (const auto& s : states) sets = std::max(sets, s.nextSet + 1);
    withEdges_.assign(static_cast<std::size_t>(std::max(sets, 1)), {});
    for (std::uint32_t i = 0; i < states.size(); ++i) {
        if (firstEdge.size() == states.size() + 1 && firstEdge[i + 1] > firstEdge[i]) withEdges_[static_cast<std::size_t>(states[i].nextSet)].push_back(i);
    }
    for (auto& list : withEdges_) {
        std::stable_sort(list.begin(), list.end(), [&](std::uint32_t a, std::uint32_t b) { return states[a].r < states[b].r; });
    }
    indexGrids();
}

int Graph::find(const InteractionState& s, bool withinOnly) const {
    const int fb = frameBucket(s.frameB);
    double bestD = std::numeric_limits<double>::infinity();
    int best = -1;
    // Within joinRadius only (nearer states first found are kept; an exact
    // tie goes to the earlier bucket, then the lower index: a scan's order).
    int bestRank = -1;
    for (int dfb = -1; dfb <= 1; ++dfb) {
        if (fb + dfb < 0) continue;
        const std::uint64_t key = bucketKey(s.nextSet, s.actionB, fb + dfb);
        auto it = std::lower_bound(buckets_.begin(), buckets_.end(), key, [](const Bucket& x, std::uint64_t k) { return x.key < k; });
        if (it != buckets_.end() && it->key == key) {
            scanBucket(static_cast<std::size_t>(it - buckets_.begin()), s, options.joinRadius, false, dfb, bestD, best, bestRank);
        }
    }
    if (best >= 0 && bestD <= options.joinRadius) return best;
    if (withinOnly) return -1;
    // Off the graph: the nearest state with edges of the same Next set and
    // B in the same action (frames apart count one frameSigma per unit),
    // else of any action of B.
    if (s.nextSet < 0 || static_cast<std::size_t>(s.nextSet) >= withEdges_.size()) return -1;
    // B in the same action, any frame: its buckets are contiguous; visit
    // them outwards from this frame's and stop when the frame difference
    // alone exceeds the best found (a bucket k away is >= k - 1 units off).
    bestD = std::numeric_limits<double>::infinity();
    best = -1;
    {
        const std::uint64_t lo = bucketKey(s.nextSet, s.actionB, 0), hi = bucketKey(s.nextSet, s.actionB, 0xffff);
        const auto cmp = [](const Bucket& x, std::uint64_t k) { return x.key < k; };
        const auto first = std::lower_bound(buckets_.begin(), buckets_.end(), lo, cmp);
        auto last = first;
        while (last != buckets_.end() && last->key <= hi) ++last;
        std::uint32_t candidates = 0;
        for (auto it = first; it != last; ++it) candidates += it->withEdges;
        const auto mid = std::lower_bound(first, last, bucketKey(s.nextSet, s.actionB, fb), cmp);
        auto gap = [&](const Bucket& bk) { return std::abs(static_cast<int>(bk.key & 0xffff) - fb) - 1.0; };
        auto up = mid;
        auto down = mid;
        while (candidates > 0 && (up != last || down != first)) {
            const bool takeUp = up != last && (down == first || gap(*up) <= gap(*(down - 1)));
            const Bucket& bk = takeUp ? *up : *(down - 1);
            if (best >= 0 && gap(bk) >= bestD) break;
            int rank = 0;
            scanBucket(static_cast<std::size_t>(&bk - buckets_.data()), s, std::numeric_limits<double>::infinity(), true, 0, bestD, best, rank);
            if (takeUp) ++up; else --down;
        }
        if (best >= 0) return best;
    }
    // Any action of B (none alike has edges): the grid of the Next set's
    // states with edges (nearest.cpp), the same answer as a full scan.
    return nearestAnyB(s);
}

Result<Graph> buildGraph(const Rules& rules, const BuildOptions& o, const ProgressFn& progress) {
    if (!(o.expandFraction > 0 && o.expandFraction <= 1)) return makeError("igraph build: the expanded fraction must be in (0, 1]");
    if (o.maxSamples < 1 || o.startStates < 1 || o.maxFrontier < 1) return makeError("igraph build: sizes must be positive");
    if (!(o.scale.sigmaR > 0 && o.scale.sigmaTheta > 0 && o.scale.frameSigma > 0 && o.joinRadius > 0)) {
        return makeError("igraph build: the distance scales must be positive");
    }
    if (o.outcomeSamples < 0 || o.outcomeSamples > 4 || !(o.outcomeSpreadR >= 0 && o.outcomeSpreadR < 1) ||
        !(o.outcomeSpreadTheta >= 0 && o.outcomeSpreadTheta < 1)) {
        return makeError("igraph build: outcome samples must be 0-4 and their spreads finite, >= 0 and under 1 (m, rad)");
    }
    const auto& lib = rules.library();
    const CellCoder coder{o.scale.sigmaR * o.cellScale, o.scale.sigmaTheta * o.cellScale, o.scale.frameSigma * o.cellScale};
    Graph g;
    g.options = o;
    g.libraryKey = sim::libraryFingerprint(lib);
    g.actions = rules.actions();
    g.actionsKey = rules.key();

    // ---- sampling (SPEC 3.2) ------------------------------------------------
    std::unordered_map<std::uint64_t, std::uint32_t> where;
    std::vector<Cell> cells;
    const std::vector<Node> starts = startStates(rules, o);
    std::vector<Node> frontier = starts;
    detail::Rng pick{o.seed ^ 0xF00Dull};
    std::atomic<std::int64_t> simulated{0};
    for (int round = 0; round < o.maxRounds && !frontier.empty(); ++round) {
        const double done = std::max(static_cast<double>(round) / o.maxRounds, static_cast<double>(cells.size()) / static_cast<double>(o.maxSamples));
        if (!reportProgress(progress, 0.6 * std::min(done, 1.0), "sampling")) return cancelled();
        struct Result1 {
            std::vector<InteractionState> samples;
            std::vector<std::uint64_t> keys;
            std::vector<Node> expand;
        };
        std::int64_t total = 0, fresh = 0;
        std::vector<Node> next;
        bool full = false;
        // In batches, so the archive stops at its limit within a round (the
        // batches' order is fixed: the result does not depend on threads).
        constexpr std::size_t kBatch = 512;
        for (std::size_t b0 = 0; b0 < frontier.size() && !full; b0 += kBatch) {
            const std::size_t b1 = std::min(frontier.size(), b0 + kBatch);
            std::vector<Result1> results(b1 - b0);
            auto work = [&](std::size_t i) {
                std::vector<Child> kids;
                int order = 0;
                forEachChild(rules, frontier[i], false, [&](int, const InteractionState& s, double j, Node&& n) {
                    Child c;
                    c.sample = s;
                    c.key = coder.key(s);
                    c.score = (where.count(c.key) ? 1.0 : 0.0) + j;  // C + J against the archive as the batch began
                    c.node = std::move(n);
                    c.order = order++;
                    kids.push_back(std::move(c));
                });
                simulated += static_cast<std::int64_t>(kids.size());
                auto& out = results[i - b0];
                for (const auto& c : kids) out.samples.push_back(c.sample), out.keys.push_back(c.key);
                std::stable_sort(kids.begin(), kids.end(), [](const Child& a, const Child& b) { return a.score > b.score; });
                const auto keep = std::min(kids.size(), static_cast<std::size_t>(std::ceil(o.expandFraction * static_cast<double>(kids.size()))));
                for (std::size_t k = 0; k < keep; ++k) {
                    if (kids[k].sample.r <= o.maxDistance) out.expand.push_back(std::move(kids[k].node));
                }
            };
            if (o.parallel) {
                tbb::parallel_for(b0, b1, work);
            } else {
                for (std::size_t i = b0; i < b1; ++i) work(i);
            }
            for (auto& r : results) {
                for (std::size_t k = 0; k < r.samples.size() && !full; ++k) {
                    ++total;
                    auto [it, added] = where.emplace(r.keys[k], static_cast<std::uint32_t>(cells.size()));
                    if (added) cells.emplace_back(), ++fresh;
                    cells[it->second].add(r.samples[k]);
                    full = static_cast<std::int64_t>(cells.size()) >= o.maxSamples;
                }
                for (auto& n : r.expand) next.push_back(std::move(n));
            }
            if (!reportProgress(progress, 0.6 * std::min(1.0, std::max(static_cast<double>(round) / o.maxRounds,
                                                                         static_cast<double>(cells.size()) / static_cast<double>(o.maxSamples))),
                                "sampling")) {
                return cancelled();
            }
        }
        g.stats.rounds = round + 1;
        if (full) break;
        if (total > 0 && static_cast<double>(fresh) / static_cast<double>(total) < o.minNewShare) break;
        if (next.size() > static_cast<std::size_t>(o.maxFrontier)) {
            for (std::size_t k = 0; k < static_cast<std::size_t>(o.maxFrontier); ++k) {
                std::swap(next[k], next[k + pick.below(next.size() - k)]);
            }
            next.resize(static_cast<std::size_t>(o.maxFrontier));
        }
        frontier = std::move(next);
    }
    g.stats.samples = static_cast<std::int64_t>(cells.size());
    g.stats.simulated = simulated.load();
    where.clear();

    // ---- clustering (SPEC 3.3) -------------------------------------------------
    if (!reportProgress(progress, 0.6, "clustering")) return cancelled();
    struct Item {
        std::uint64_t group;
        InteractionState s;
        double w;
    };
    std::vector<Item> items;
    items.reserve(cells.size());
    for (const auto& c : cells) {
        const InteractionState m = c.mean();
        const auto fb = static_cast<std::uint64_t>(std::min(65535.0, std::floor(m.frameB / o.scale.frameSigma)));
        items.push_back({(static_cast<std::uint64_t>(m.nextSet) << 40) | (static_cast<std::uint64_t>(m.actionB) << 16) | fb, m,
                         static_cast<double>(c.count)});
    }
    cells = {};
    std::sort(items.begin(), items.end(), [&](const Item& a, const Item& b) {
        if (a.group != b.group) return a.group < b.group;
        return coder.key(a.s) < coder.key(b.s);
    });
    std::vector<std::pair<std::size_t, std::size_t>> groups;
    for (std::size_t i = 0; i < items.size();) {
        std::size_t j = i + 1;
        while (j < items.size() && items[j].group == items[i].group) ++j;
        groups.emplace_back(i, j);
        i = j;
    }
    std::vector<std::vector<InteractionState>> centres(groups.size());
    auto cluster = [&](std::size_t gi) {
        const auto [b, e] = groups[gi];
        // Seeds: the weighted means of a grid one sigma wide (D of about 1 across).
        std::vector<std::uint64_t> seedKey;
        std::vector<std::array<double, 5>> acc;  // r, thA, thB, frame, weight
        auto gridKey = [&](const InteractionState& s) {
            const auto rb = static_cast<std::uint64_t>(std::floor(s.r / o.scale.sigmaR));
            const auto ab = static_cast<std::uint64_t>(std::floor((s.thetaA + std::numbers::pi) / o.scale.sigmaTheta));
            const auto bb = static_cast<std::uint64_t>(std::floor((s.thetaB + std::numbers::pi) / o.scale.sigmaTheta));
            return (rb << 16) | (ab << 8) | bb;
        };
        for (std::size_t i = b; i < e; ++i) {
            const auto k = gridKey(items[i].s);
            auto it = std::find(seedKey.begin(), seedKey.end(), k);
            std::size_t at = static_cast<std::size_t>(it - seedKey.begin());
            if (it == seedKey.end()) seedKey.push_back(k), acc.push_back({0, 0, 0, 0, 0});
            const auto& s = items[i].s;
            const double w = items[i].w;
            acc[at][0] += w * s.r, acc[at][1] += w * s.thetaA, acc[at][2] += w * s.thetaB, acc[at][3] += w * s.frameB, acc[at][4] += w;
        }
        std::vector<InteractionState> c;
        auto fromAcc = [&]() {
            c.clear();
            for (const auto& a : acc) {
                if (a[4] <= 0) continue;
                c.push_back({static_cast<float>(a[0] / a[4]), static_cast<float>(a[1] / a[4]), static_cast<float>(a[2] / a[4]),
                             items[b].s.nextSet, items[b].s.actionB, static_cast<float>(a[3] / a[4])});
            }
        };
        fromAcc();
        DistanceScale loose = o.scale;
        loose.frameSigma = std::numeric_limits<double>::max();  // one group shares its frame bucket
        for (int it = 0; it < o.kmeansIterations; ++it) {
            acc.assign(c.size(), {0, 0, 0, 0, 0});
            for (std::size_t i = b; i < e; ++i) {
                std::size_t best = 0;
                double bestD = std::numeric_limits<double>::infinity();
                for (std::size_t k = 0; k < c.size(); ++k) {
                    const double d = distance(items[i].s, c[k], loose);
                    if (d < bestD) bestD = d, best = k;
                }
                const auto& s = items[i].s;
                const double w = items[i].w;
                acc[best][0] += w * s.r, acc[best][1] += w * s.thetaA, acc[best][2] += w * s.thetaB, acc[best][3] += w * s.frameB,
                    acc[best][4] += w;
            }
            fromAcc();
        }
        centres[gi] = std::move(c);
    };
    if (o.parallel) {
        tbb::parallel_for(std::size_t{0}, groups.size(), cluster);
    } else {
        for (std::size_t gi = 0; gi < groups.size(); ++gi) cluster(gi);
    }
    items = {};
    for (auto& c : centres) {
        for (auto& s : c) g.states.push_back(s);
    }
    centres = {};
    g.index();

    // ---- edges (SPEC 3.3) ---------------------------------------------------------
    if (!reportProgress(progress, 0.7, "edges")) return cancelled();
    const std::size_t n = g.states.size();
    // Chunks of states in parallel, appended in order; the edge list is
    // reserved at its bound (every action of every Next set) so it never moves.
    std::vector<std::vector<int>> edgeActions(static_cast<std::size_t>(rules.nextSetCount()));
    for (int set = 0; set < rules.nextSetCount(); ++set) {
        const auto& all = rules.nextSet(set);
        if (o.variantsPerClass <= 0) {
            edgeActions[static_cast<std::size_t>(set)] = all;
            continue;
        }
        std::vector<int> classes;
        for (int a : all) classes.push_back(lib.variantClass()[static_cast<std::size_t>(a)]);
        for (std::size_t k = 0; k < all.size(); ++k) {
            // The members of this action's class, in order; keep evenly spaced ones.
            std::vector<std::size_t> members;
            for (std::size_t m = 0; m < all.size(); ++m) {
                if (classes[m] == classes[k]) members.push_back(m);
            }
            const std::size_t count = members.size(), keep = std::min<std::size_t>(count, static_cast<std::size_t>(o.variantsPerClass));
            const std::size_t rank = static_cast<std::size_t>(std::find(members.begin(), members.end(), k) - members.begin());
            for (std::size_t j = 0; j < keep; ++j) {
                if (rank == j * count / keep) edgeActions[static_cast<std::size_t>(set)].push_back(all[k]);
            }
        }
    }
    std::size_t bound = 0;
    for (const auto& s : g.states) bound += edgeActions[static_cast<std::size_t>(s.nextSet)].size();
    g.edges.reserve(bound);
    g.firstEdge.assign(n + 1, 0);
    constexpr std::size_t kChunk = 4096;
    std::vector<std::vector<Edge>> out(kChunk);
    // Rule 3: an action whose result falls in no state still makes an edge,
    // to the state the run time takes off the graph (the nearest with edges,
    // Graph::find(s, false), over the edges that fall within the graph),
    // resolved once every state's in-graph edges are known. Dropping them
    // lost the blows: an edge that lands a blow leaves a reaction behind and
    // fell in no state about three times as often as the rest (docs/IGRAPH.md).
    struct OffGraph {
        InteractionState s;
        int action = 0;
        bool sameChooser = false;
        float given = 0, received = 0;
    };
    std::vector<std::vector<OffGraph>> offGraph(n);
    for (std::size_t c0 = 0; c0 < n; c0 += kChunk) {
        const std::size_t c1 = std::min(n, c0 + kChunk);
        auto edgesOf = [&](std::size_t i) {
            auto& mineOut = out[i - c0];
            mineOut.clear();
            const auto& s = g.states[i];
            const glm::vec2 d = static_cast<float>(s.r) * sim::headingVector(s.thetaA);
            const sim::RootXf pb{d, sim::wrapAngle(sim::angleOf(-d) - s.thetaB)};
            Node node;
            node.b[1] = detail::bodyAt(lib, s.actionB, s.frameB / sim::kSampleRate, pb, 0.0);
            // A is about to choose at the origin facing +Z: its previous
            // action is placed so that it ends there.
            node.b[0].action = rules.idle().front();
            node.b[0].root = lib.action(node.b[0].action).end.inverse();
            node.b[0].end = 0;
            // B placed around the mean (outcomeSamples): the blows are averaged over them.
            std::array<Body, 4> spread{};
            const int spreadCount = std::clamp(o.outcomeSamples, 0, 4);
            for (int k = 0; k < spreadCount; ++k) {
                constexpr int kSigns[4][3] = {{1, 1, -1}, {-1, -1, 1}, {1, -1, 1}, {-1, 1, -1}};
                const double r = std::max(0.05, s.r + kSigns[k][0] * o.outcomeSpreadR);
                const double ta = s.thetaA + kSigns[k][1] * o.outcomeSpreadTheta, tb = s.thetaB + kSigns[k][2] * o.outcomeSpreadTheta;
                const glm::vec2 dk = static_cast<float>(r) * sim::headingVector(ta);
                spread[static_cast<std::size_t>(k)] =
                    detail::bodyAt(lib, s.actionB, s.frameB / sim::kSampleRate, sim::RootXf{dk, sim::wrapAngle(sim::angleOf(-dk) - tb)}, 0.0);
            }
            for (int a : edgeActions[static_cast<std::size_t>(s.nextSet)]) {
                std::array<Body, 2> b = node.b;
                detail::launch(lib, b[0], a, 0.0);
                detail::Outcome oc;
                const double t1 = detail::advanceDuel(rules, b, 0.0, oc);
                const int nc = detail::chooser(b);
                const auto un = static_cast<std::size_t>(nc);
                const InteractionState reached = detail::stateOf(rules, b[un], b[1 - un], t1);
                const int to = g.find(reached);
                if (spreadCount > 0) {
                    // The expected blows over the mean and the spread placements.
                    double given = static_cast<double>(oc.given[0]), received = static_cast<double>(oc.received[0]);
                    for (int k = 0; k < spreadCount; ++k) {
                        std::array<Body, 2> bk = {node.b[0], spread[static_cast<std::size_t>(k)]};
                        detail::launch(lib, bk[0], a, 0.0);
                        detail::Outcome ok;
                        detail::advanceDuel(rules, bk, 0.0, ok);
                        given += static_cast<double>(ok.given[0]), received += static_cast<double>(ok.received[0]);
                    }
                    oc.given[0] = static_cast<float>(given / (spreadCount + 1));
                    oc.received[0] = static_cast<float>(received / (spreadCount + 1));
                }
                if (to < 0) {
                    offGraph[i].push_back({reached, a, nc == 0, oc.given[0], oc.received[0]});
                    continue;
                }
                // Actions of one kind that lead to the same state with the
                // same blows (speeds within 1 m/s) are one edge, the first of
                // them: min-max cannot tell them apart, and a command still
                // finds its kind (the variants of a jab mostly end this way).
                const int kind = kindOf(lib.action(a));
                const auto same = [&](const Edge& e) {
                    return e.to == to && e.sameChooser() == (nc == 0) && kindOf(lib.action(e.action())) == kind &&
                           std::lround(e.given()) == std::lround(static_cast<double>(oc.given[0])) &&
                           std::lround(e.received()) == std::lround(static_cast<double>(oc.received[0]));
                };
                if (std::any_of(mineOut.begin(), mineOut.end(), same)) continue;
                mineOut.push_back(Edge::make(a, to, nc == 0, static_cast<double>(oc.given[0]), static_cast<double>(oc.received[0])));
            }
        };
        if (o.parallel) {
            tbb::parallel_for(c0, c1, edgesOf);
        } else {
            for (std::size_t i = c0; i < c1; ++i) edgesOf(i);
        }
        for (std::size_t i = c0; i < c1; ++i) {
            g.firstEdge[i] = static_cast<std::uint32_t>(g.edges.size());
            g.edges.insert(g.edges.end(), out[i - c0].begin(), out[i - c0].end());
        }
        if (!reportProgress(progress, 0.7 + 0.25 * static_cast<double>(c1) / static_cast<double>(n), "edges")) return cancelled();
    }
    g.firstEdge[n] = static_cast<std::uint32_t>(g.edges.size());
    out = {};
    g.index();
    {
        // The off-graph results: each to the nearest state with edges, then
        // merged after the state's in-graph edges (the same merging of one
        // kind, one target, the same blows).
        std::vector<std::vector<Edge>> extra(n);
        auto resolve = [&](std::size_t i) {
            for (const auto& x : offGraph[i]) {
                const int to = g.find(x.s, false);
                if (to < 0) continue;
                const int kind = kindOf(lib.action(x.action));
                const auto same = [&](const Edge& e) {
                    return e.to == to && e.sameChooser() == x.sameChooser && kindOf(lib.action(e.action())) == kind &&
                           std::lround(e.given()) == std::lround(static_cast<double>(x.given)) &&
                           std::lround(e.received()) == std::lround(static_cast<double>(x.received));
                };
                if (std::any_of(g.edgesBegin(static_cast<int>(i)), g.edgesEnd(static_cast<int>(i)), same) ||
                    std::any_of(extra[i].begin(), extra[i].end(), same))
                    continue;
                extra[i].push_back(Edge::make(x.action, to, x.sameChooser, static_cast<double>(x.given), static_cast<double>(x.received)));
            }
            offGraph[i] = {};
        };
        if (o.parallel) {
            tbb::parallel_for(std::size_t{0}, n, resolve);
        } else {
            for (std::size_t i = 0; i < n; ++i) resolve(i);
        }
        offGraph = {};
        std::size_t added = 0;
        for (const auto& x : extra) added += x.size();
        if (added > 0) {
            std::vector<Edge> merged;
            merged.reserve(g.edges.size() + added);
            std::vector<std::uint32_t> first(n + 1, 0);
            for (std::size_t i = 0; i < n; ++i) {
                first[i] = static_cast<std::uint32_t>(merged.size());
                merged.insert(merged.end(), g.edgesBegin(static_cast<int>(i)), g.edgesEnd(static_cast<int>(i)));
                merged.insert(merged.end(), extra[i].begin(), extra[i].end());
            }
            first[n] = static_cast<std::uint32_t>(merged.size());
            extra = {};
            g.edges = std::move(merged);
            g.firstEdge = std::move(first);
            g.index();
        }
    }

    // ---- coverage ---------------------------------------------------------------
    if (o.coverageDepth > 0 && o.coverageStarts > 0) {
        if (!reportProgress(progress, 0.95, "coverage")) return cancelled();
        const std::size_t count = std::min<std::size_t>(starts.size(), static_cast<std::size_t>(o.coverageStarts));
        struct Tally {
            std::int64_t visited = 0, inside = 0;
        };
        std::vector<Tally> tallies(count);
        // As tree expansion searches (SimOptions::variants): every variant at
        // the root, one per variant class below it.
        auto walk = [&](auto&& self, const Node& node, int depth, Tally& t) -> void {
            forEachChild(rules, node, depth < o.coverageDepth, [&](int, const InteractionState& s, double, Node&& child) {
                ++t.visited;
                if (g.find(s) >= 0) ++t.inside;
                if (depth > 1) self(self, child, depth - 1, t);
            });
        };
        auto cover = [&](std::size_t k) { walk(walk, starts[k], o.coverageDepth, tallies[k]); };
        if (o.parallel) {
            tbb::parallel_for(std::size_t{0}, count, cover);
        } else {
            for (std::size_t k = 0; k < count; ++k) cover(k);
        }
        Tally sum;
        for (const auto& t : tallies) sum.visited += t.visited, sum.inside += t.inside;
        g.stats.coverageVisited = sum.visited;
        g.stats.coverage = sum.visited > 0 ? static_cast<double>(sum.inside) / static_cast<double>(sum.visited) : 0.0;
    }
    reportProgress(progress, 1.0, "done");
    g.timeEdges(lib);
    g.findNeighbours();
    return g;
}

}  // namespace fray::igraph
