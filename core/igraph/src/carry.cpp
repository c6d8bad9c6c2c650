// The Interaction Graph for two carriers of one long box (SPEC 3.2-3.5,
// collaborative): sampling of the joint game tree, clustering, edges, the
// eight direction policies and the run along a user path.
#include "fray/igraph/carry.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <numbers>
#include <unordered_map>

#include <nlohmann/json.hpp>

#include "carry_internal.h"
#include "fray/sim/patches.h"  // libraryFingerprint
#include "game.h"

namespace fray::igraph {

namespace {

using sim::RootXf;
using Clock = std::chrono::steady_clock;
constexpr double kPi = std::numbers::pi;

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

glm::vec2 floorOf(const glm::vec3& p) { return {p.x, p.z}; }

// The pair's state: A is carrier 0, B carrier 1 (the carry graph has one
// Next set and both decide together, so B is always at frame 0).
InteractionState pairState(const RootXf& a, const RootXf& b) {
    const glm::vec2 d = b.pos - a.pos;
    InteractionState s;
    s.r = static_cast<double>(glm::length(d));
    s.thetaA = s.r > 1e-6 ? sim::wrapAngle(sim::angleOf(d) - a.heading) : 0.0;
    s.thetaB = s.r > 1e-6 ? sim::wrapAngle(sim::angleOf(-d) - b.heading) : 0.0;
    return s;
}

// B placed by a state, A at the origin facing +Z.
RootXf placeB(const InteractionState& s) {
    RootXf b;
    b.pos = glm::vec2(static_cast<float>(s.r * std::sin(s.thetaA)), static_cast<float>(s.r * std::cos(s.thetaA)));
    b.heading = sim::wrapAngle(s.thetaA + kPi - s.thetaB);
    return b;
}

// Per action: its grips per sample, end placement and duration.
struct ActionTrack {
    std::vector<glm::vec3> grip;
    RootXf end;
    double duration = 0;
    int nameClass = 0;
};

glm::vec3 gripOfBoxes(const sim::Obb* boxes) {
    return 0.5f * (sim::segmentTip(boxes[sim::kLeftForearm], sim::kLeftForearm) + sim::segmentTip(boxes[sim::kRightForearm], sim::kRightForearm));
}

struct Sim {
    InteractionState next;
    CarryEdge edge;
};

// Both carriers play one action each from state s.
Sim simulate(const std::vector<ActionTrack>& tracks, const InteractionState& s, int ia, int ib, double boxLength) {
    const ActionTrack& ta = tracks[static_cast<std::size_t>(ia)];
    const ActionTrack& tb = tracks[static_cast<std::size_t>(ib)];
    const RootXf a0{}, b0 = placeB(s);
    const std::size_t n = std::max(ta.grip.size(), tb.grip.size());
    double err = 0;
    for (std::size_t k = 0; k < n; ++k) {
        const glm::vec3 ga = a0.apply(ta.grip[std::min(k, ta.grip.size() - 1)]);
        const glm::vec3 gb = b0.apply(tb.grip[std::min(k, tb.grip.size() - 1)]);
        err = std::max(err, std::abs(static_cast<double>(glm::length(ga - gb)) - boxLength));
    }
    const glm::vec2 mid0 = 0.5f * (floorOf(a0.apply(ta.grip.front())) + floorOf(b0.apply(tb.grip.front())));
    const glm::vec2 mid1 = 0.5f * (floorOf(a0.apply(ta.grip.back())) + floorOf(b0.apply(tb.grip.back())));
    Sim out;
    out.next = pairState(a0 * ta.end, b0 * tb.end);
    out.edge.boxX = mid1.x - mid0.x;
    out.edge.boxZ = mid1.y - mid0.y;
    out.edge.gripError = static_cast<float>(err);
    out.edge.seconds = static_cast<float>(std::max(ta.duration, tb.duration));
    return out;
}

struct CellKey {
    std::int64_t r, a, b;
};
std::uint64_t packKey(std::int64_t r, std::int64_t a, std::int64_t b) {
    auto u = [](std::int64_t v) { return static_cast<std::uint64_t>(v + (1 << 20)) & 0x1fffffu; };
    return (u(r) << 42) | (u(a) << 21) | u(b);
}
CellKey cellOf(const InteractionState& s, const DistanceScale& sc) {
    return {static_cast<std::int64_t>(std::floor(s.r / sc.sigmaR)), static_cast<std::int64_t>(std::floor(s.thetaA / sc.sigmaTheta)),
            static_cast<std::int64_t>(std::floor(s.thetaB / sc.sigmaTheta))};
}

double dist(const InteractionState& x, const InteractionState& y, const DistanceScale& sc) {
    return std::abs(x.r - y.r) / sc.sigmaR + std::abs(sim::wrapAngle(x.thetaA - y.thetaA)) / sc.sigmaTheta +
           std::abs(sim::wrapAngle(x.thetaB - y.thetaB)) / sc.sigmaTheta;
}

// A grid of states by cell (for find).
struct StateGrid {
    std::unordered_map<std::uint64_t, std::vector<int>> cells;
    void build(const std::vector<InteractionState>& states, const DistanceScale& sc) {
        cells.clear();
        for (std::size_t i = 0; i < states.size(); ++i) {
            const CellKey k = cellOf(states[i], sc);
            cells[packKey(k.r, k.a, k.b)].push_back(static_cast<int>(i));
        }
    }
    // Nearest within `limit` (D), searching cells within `reach` cells.
    int find(const std::vector<InteractionState>& states, const InteractionState& s, const DistanceScale& sc, double limit, int reach) const {
        const CellKey k = cellOf(s, sc);
        int best = -1;
        double bestD = limit;
        for (std::int64_t dr = -reach; dr <= reach; ++dr)
            for (std::int64_t da = -reach; da <= reach; ++da)
                for (std::int64_t db = -reach; db <= reach; ++db) {
                    const auto it = cells.find(packKey(k.r + dr, k.a + da, k.b + db));
                    if (it == cells.end()) continue;
                    for (int i : it->second) {
                        const double d = dist(states[static_cast<std::size_t>(i)], s, sc);
                        if (d < bestD || (d == bestD && best >= 0 && i < best)) bestD = d, best = i;
                    }
                }
        return best;
    }
};

// The action tracks of the chosen actions (index into CarryGraph::actions).
std::vector<ActionTrack> tracksOf(const sim::ActionLibrary& lib, const std::vector<int>& actions, std::vector<std::string>& names) {
    std::vector<ActionTrack> out;
    for (int a : actions) {
        const auto& la = lib.action(a);
        ActionTrack t;
        for (int s = 0; s < la.sampleCount; ++s) t.grip.push_back(gripOfBoxes(lib.boxesAt(a, s)));
        if (t.grip.empty()) t.grip.push_back(gripOfBoxes(lib.boxesAt(a, 0)));
        t.end = la.end;
        t.duration = la.duration;
        const auto it = std::find(names.begin(), names.end(), la.name);
        t.nameClass = static_cast<int>(it - names.begin());
        if (it == names.end()) names.push_back(la.name);
        out.push_back(std::move(t));
    }
    return out;
}

struct Pieces {
    std::vector<ActionTrack> tracks;
    std::vector<std::string> names;
    std::vector<std::vector<int>> byName;  // per name class: track indices
};

Result<Pieces> piecesOf(const sim::ActionLibrary& lib, const CarryOptions& o, std::vector<int>& actions, int& hold) {
    actions = detail::carryActions(lib, o.prefix);
    if (actions.empty())
        return makeError("Interaction Graph (carrying): the project has no carry-end actions (names starting with '" + o.prefix +
                         "', e.g. the demo actor's carry set: fray-cli demo-library DIR --set carry)");
    Pieces p;
    p.tracks = tracksOf(lib, actions, p.names);
    p.byName.resize(p.names.size());
    for (std::size_t i = 0; i < p.tracks.size(); ++i) p.byName[static_cast<std::size_t>(p.tracks[i].nameClass)].push_back(static_cast<int>(i));
    hold = detail::carryHold(lib, actions);
    return p;
}

}  // namespace

namespace detail {
std::vector<int> carryActions(const sim::ActionLibrary& lib, const std::string& prefix) {
    std::vector<int> actions;
    for (int a = 0; a < lib.size(); ++a) {
        const auto& la = lib.action(a);
        if (la.name.rfind(prefix, 0) != 0 || la.is(sim::kTransition) || la.sampleCount < 2) continue;
        actions.push_back(a);
    }
    return actions;
}
int carryHold(const sim::ActionLibrary& lib, const std::vector<int>& actions) {
    for (int a : actions)
        if (lib.action(a).is(sim::kIdle)) return a;
    return actions.empty() ? -1 : actions.front();
}
}  // namespace detail

glm::vec3 gripAt(const sim::ActionLibrary& lib, int action, double t) {
    return gripOfBoxes(lib.boxesAt(action, lib.sampleAt(action, t)));
}

namespace {

// The box at time tt of a carry scene (characters 0 and 1 the carriers): both
// grips in the world, the box's root key (on the floor between them, facing
// from the first to the second) and the middle it is scored by. One rule for
// runCarry and CarryDriver, so both write the same keys.
struct BoxSample {
    glm::vec3 grip[2];
    sim::RootKey key;
    glm::vec2 middle{0.0f};
};
BoxSample boxAt(const sim::ActionLibrary& lib, const sim::Scene& scene, double tt) {
    BoxSample out;
    for (int c = 0; c < 2; ++c) {
        const auto& track = scene.characters[static_cast<std::size_t>(c)].track;
        const auto& inst = track[static_cast<std::size_t>(sim::instanceIndexAt(track, tt))];
        out.grip[c] = inst.root.apply(gripAt(lib, inst.action, inst.clipTimeAt(tt)));
    }
    const glm::vec2 fa = floorOf(out.grip[0]), fb = floorOf(out.grip[1]);
    out.key.time = tt;
    out.key.at.pos = fa;
    out.key.at.heading = sim::angleOf(fb - fa);
    out.key.height = 0.5f * (out.grip[0].y + out.grip[1].y);
    out.middle = 0.5f * (fa + fb);
    return out;
}

}  // namespace

std::size_t CarryGraph::memoryBytes() const {
    return states.capacity() * sizeof(InteractionState) + firstEdge.capacity() * sizeof(std::uint32_t) + edges.capacity() * sizeof(CarryEdge) +
           actions.capacity() * sizeof(int);
}

int CarryGraph::find(const InteractionState& s, bool nearest) const {
    int best = -1;
    double bestD = nearest ? 1e300 : options.joinRadius;
    for (std::size_t i = 0; i < states.size(); ++i) {
        if (nearest && firstEdge[i + 1] == firstEdge[i]) continue;
        const double d = dist(states[i], s, options.scale);
        if (d < bestD || (!nearest && d == bestD && best < 0)) bestD = d, best = static_cast<int>(i);
    }
    return best;
}

Result<CarryGraph> buildCarryGraph(const sim::ActionLibrary& lib, const CarryOptions& o, const ProgressFn& progress) {
    const auto t0 = Clock::now();
    if (!(o.boxLength > 0.2 && o.boxLength < 10)) return makeError("carry: the box length must be in (0.2, 10) m");
    CarryGraph g;
    g.options = o;
    g.libraryKey = sim::libraryFingerprint(lib);
    auto pieces = piecesOf(lib, o, g.actions, g.hold);
    if (!pieces) return pieces.error();
    const auto& tracks = pieces->tracks;
    const auto& byName = pieces->byName;
    const int nNames = static_cast<int>(byName.size());
    // Where the grip is: ahead of the pelvis, at what height (first samples).
    for (const auto& t : tracks) g.gripReach += static_cast<double>(t.grip.front().z), g.gripHeight += static_cast<double>(t.grip.front().y);
    g.gripReach /= static_cast<double>(tracks.size());
    g.gripHeight /= static_cast<double>(tracks.size());
    const DistanceScale& sc = o.scale;
    const double L = o.boxLength;
    const double r0 = L + 2.0 * g.gripReach;

    // ---- sampling (3.2): selective expansion of the joint game tree ----
    struct Cell {
        double r = 0, a = 0, b = 0;
        std::int64_t n = 0;
    };
    std::unordered_map<std::uint64_t, std::size_t> cellIndex;
    std::vector<Cell> cells;
    auto keyOf = [&](const InteractionState& s) {
        const CellKey k = cellOf(s, sc);
        return packKey(k.r, k.a, k.b);
    };
    detail::Rng rng{o.seed ^ 0xCA77ull};
    std::vector<InteractionState> frontier;
    for (int i = 0; i < std::max(1, o.startStates); ++i) {
        InteractionState s;
        s.r = r0 + (i == 0 ? 0.0 : rng.uniform(-0.06, 0.06));
        s.thetaA = i == 0 ? 0.0 : rng.uniform(-0.08, 0.08);
        s.thetaB = i == 0 ? 0.0 : rng.uniform(-0.08, 0.08);
        frontier.push_back(s);
    }
    auto store = [&](const InteractionState& s) {
        const std::uint64_t k = keyOf(s);
        auto [it, added] = cellIndex.emplace(k, cells.size());
        if (added) cells.push_back({});
        Cell& c = cells[it->second];
        c.r += s.r, c.a += s.thetaA, c.b += s.thetaB, ++c.n;
        return added;
    };
    for (const auto& s : frontier) store(s);
    const int children = nNames * nNames;
    const int expand = std::max(1, static_cast<int>(std::ceil(o.expandFraction * children)));
    struct Child {
        InteractionState s;
        double score;
        std::uint64_t tie;
    };
    for (int round = 0; round < o.maxRounds && !frontier.empty(); ++round) {
        if (progress && !progress(0.5 * round / o.maxRounds, "carry graph: sampling")) return cancelled();
        std::vector<std::vector<Child>> kids(frontier.size());
        const std::uint64_t roundSeed = o.seed * 0x9E3779B97F4A7C15ull + static_cast<std::uint64_t>(round);
        auto work = [&](std::size_t i) {
            detail::Rng r{roundSeed ^ (static_cast<std::uint64_t>(i) * 0xD1B54A32D192ED03ull)};
            auto& out = kids[i];
            out.reserve(static_cast<std::size_t>(children));
            for (int na = 0; na < nNames; ++na)
                for (int nb = 0; nb < nNames; ++nb) {
                    const auto& va = byName[static_cast<std::size_t>(na)];
                    const auto& vb = byName[static_cast<std::size_t>(nb)];
                    const int ia = va[r.below(va.size())], ib = vb[r.below(vb.size())];
                    const Sim sm = simulate(tracks, frontier[i], ia, ib, L);
                    // C: the child is in the archive already; J: the constraint holds (grips a box apart, facing).
                    const double c = cellIndex.count(keyOf(sm.next)) ? 1.0 : 0.0;
                    const double j = (static_cast<double>(sm.edge.gripError) <= 0.05 * L && std::abs(sm.next.thetaA) < 0.2 && std::abs(sm.next.thetaB) < 0.2) ? 1.0 : 0.0;
                    out.push_back({sm.next, c + j, r.next()});
                }
            std::sort(out.begin(), out.end(), [](const Child& x, const Child& y) { return x.score != y.score ? x.score > y.score : x.tie < y.tie; });
        };
        if (o.parallel)
            tbb::parallel_for(std::size_t{0}, frontier.size(), work);
        else
            for (std::size_t i = 0; i < frontier.size(); ++i) work(i);
        std::vector<InteractionState> next;
        std::int64_t added = 0, seen = 0;
        for (const auto& list : kids) {
            if (static_cast<std::int64_t>(cells.size()) >= o.maxSamples) break;  // the archive is full (the rest of the round is dropped, in node order)
            for (std::size_t c = 0; c < list.size(); ++c) {
                added += store(list[c].s) ? 1 : 0;
                ++seen;
                g.simulated += 1;
                if (static_cast<int>(c) < expand) next.push_back(list[c].s);
            }
        }
        g.rounds = round + 1;
        if (static_cast<int>(next.size()) > o.maxFrontier) {
            for (std::size_t i = next.size(); i > 1; --i) std::swap(next[i - 1], next[rng.below(i)]);
            next.resize(static_cast<std::size_t>(o.maxFrontier));
        }
        frontier = std::move(next);
        if (static_cast<std::int64_t>(cells.size()) >= o.maxSamples) break;
        if (seen > 0 && static_cast<double>(added) / static_cast<double>(seen) < o.minNewShare) break;
    }
    g.samples = 0;
    for (const auto& c : cells) g.samples += c.n;

    // ---- clustering (3.3): the one-sigma cells' means seed K-means under D ----
    std::vector<InteractionState> samples;  // the cell means, weighted by their counts
    std::vector<double> weight;
    for (const auto& c : cells) {
        InteractionState s;
        const double n = static_cast<double>(c.n);
        s.r = c.r / n, s.thetaA = c.a / n, s.thetaB = c.b / n;
        samples.push_back(s);
        weight.push_back(n);
    }
    std::vector<InteractionState> centres = samples;
    for (int it = 0; it < o.kmeansIterations; ++it) {
        StateGrid grid;
        grid.build(centres, sc);
        std::vector<double> sr(centres.size(), 0), sa(centres.size(), 0), sb(centres.size(), 0), sw(centres.size(), 0);
        for (std::size_t i = 0; i < samples.size(); ++i) {
            int c = grid.find(centres, samples[i], sc, 1e300, 1);
            if (c < 0) c = static_cast<int>(i);
            const auto u = static_cast<std::size_t>(c);
            sr[u] += weight[i] * samples[i].r, sa[u] += weight[i] * samples[i].thetaA, sb[u] += weight[i] * samples[i].thetaB, sw[u] += weight[i];
        }
        std::vector<InteractionState> moved;
        for (std::size_t c = 0; c < centres.size(); ++c) {
            if (sw[c] <= 0) continue;
            InteractionState s;
            s.r = sr[c] / sw[c], s.thetaA = sa[c] / sw[c], s.thetaB = sb[c] / sw[c];
            moved.push_back(s);
        }
        centres = std::move(moved);
    }
    g.states = std::move(centres);
    StateGrid grid;
    grid.build(g.states, sc);
    if (progress && !progress(0.5, "carry graph: edges")) return cancelled();

    // ---- edges (3.3): every pair of actions (variants spread over each name) from every state ----
    std::vector<std::vector<int>> variants(static_cast<std::size_t>(nNames));
    for (int n = 0; n < nNames; ++n) {
        const auto& all = byName[static_cast<std::size_t>(n)];
        const int v = o.variantsPerClass <= 0 ? static_cast<int>(all.size()) : std::min<int>(o.variantsPerClass, static_cast<int>(all.size()));
        for (int k = 0; k < v; ++k) variants[static_cast<std::size_t>(n)].push_back(all[static_cast<std::size_t>((2 * k + 1) * static_cast<int>(all.size()) / (2 * v))]);
    }
    const int reach = static_cast<int>(std::ceil(o.joinRadius));  // D <= joinRadius: no term more than that many sigmas, so cells that far
    std::vector<std::vector<CarryEdge>> out(g.states.size());
    auto connect = [&](std::size_t i) {
        std::map<std::tuple<int, int, int>, CarryEdge> best;  // (name A, name B, target) -> the edge with the smallest grip error
        for (int na = 0; na < nNames; ++na)
            for (int nb = 0; nb < nNames; ++nb)
                for (int ia : variants[static_cast<std::size_t>(na)])
                    for (int ib : variants[static_cast<std::size_t>(nb)]) {
                        Sim sm = simulate(tracks, g.states[i], ia, ib, L);
                        const int j = grid.find(g.states, sm.next, sc, o.joinRadius, reach);
                        if (j < 0) continue;
                        sm.edge.to = j;
                        sm.edge.actionA = static_cast<std::int16_t>(g.actions[static_cast<std::size_t>(ia)]);
                        sm.edge.actionB = static_cast<std::int16_t>(g.actions[static_cast<std::size_t>(ib)]);
                        auto [it, added] = best.emplace(std::make_tuple(na, nb, j), sm.edge);
                        if (!added && sm.edge.gripError < it->second.gripError) it->second = sm.edge;
                    }
        for (const auto& [k, e] : best) out[i].push_back(e);
    };
    if (o.parallel)
        tbb::parallel_for(std::size_t{0}, g.states.size(), connect);
    else
        for (std::size_t i = 0; i < g.states.size(); ++i) connect(i);
    g.firstEdge.assign(g.states.size() + 1, 0);
    for (std::size_t i = 0; i < g.states.size(); ++i) {
        g.firstEdge[i + 1] = g.firstEdge[i] + static_cast<std::uint32_t>(out[i].size());
        g.edges.insert(g.edges.end(), out[i].begin(), out[i].end());
        g.simulated += static_cast<std::int64_t>(nNames) * nNames;
    }
    g.seconds = since(t0);
    return g;
}

// ---- policies ----------------------------------------------------------------------

Status validate(const CarryWeights& w) {
    const std::pair<const char*, double> fields[] = {{"w_theta", w.wTheta}, {"w_d", w.wD}, {"w_v", w.wV}, {"speed", w.speed}, {"gamma", w.gamma}};
    for (const auto& [name, v] : fields) {
        if (!std::isfinite(v)) return makeError(std::string("reward weight ") + name + " is not a finite number");
        if (v < 0) return makeError(std::string("reward weight ") + name + " is negative");
    }
    if (w.gamma > 1) return makeError("reward weight gamma must be in [0, 1]");
    if (w.speed > 5) return makeError("reward weight speed must be at most 5 m/s");
    return {};
}

Status applyCarryEdit(CarryWeights& w, std::string_view edit) {
    const auto eq = edit.find('=');
    if (eq == std::string_view::npos) return makeError("reward edit '" + std::string(edit) + "': expected name=value");
    const std::string name(edit.substr(0, eq)), value(edit.substr(eq + 1));
    CarryWeights t = w;
    double* field = name == "w_theta" ? &t.wTheta : name == "w_d" ? &t.wD : name == "w_v" ? &t.wV : name == "speed" ? &t.speed
                  : name == "gamma" ? &t.gamma : nullptr;
    if (!field) return makeError("reward edit '" + std::string(edit) + "': unknown weight '" + name + "' (w_theta, w_d, w_v, speed, gamma)");
    char* end = nullptr;
    const double v = std::strtod(value.c_str(), &end);
    if (value.empty() || end != value.c_str() + value.size()) return makeError("reward weight " + name + " is not a finite number");
    *field = v;
    if (auto st = validate(t); !st) return st;
    w = t;
    return {};
}

glm::vec2 carryDirection(int k) {
    const double a = k * kPi / 4.0;
    return {static_cast<float>(std::sin(a)), static_cast<float>(std::cos(a))};
}

double carryEdgeReward(const CarryGraph& g, const CarryEdge& e, const CarryWeights& w, int direction) {
    const InteractionState& to = g.states[static_cast<std::size_t>(e.to)];
    const double secs = std::max(1e-3, static_cast<double>(e.seconds));
    const glm::vec2 v = glm::vec2(e.boxX, e.boxZ) / static_cast<float>(secs);
    const glm::vec2 vp = carryDirection(direction) * static_cast<float>(w.speed);
    const glm::vec2 dv = v - vp;
    const double ge = e.gripError;
    return -(w.wTheta * (to.thetaA * to.thetaA + to.thetaB * to.thetaB) + w.wD * ge * ge + w.wV * static_cast<double>(glm::dot(dv, dv)));
}

Result<CarryPolicy> computeCarryPolicy(const CarryGraph& g, const CarryWeights& w, int direction, int depth, const ProgressFn& progress) {
    if (auto st = validate(w); !st) return st.error();
    if (direction < 0 || direction >= kCarryDirections) return makeError("carry policy: direction must be 0-7");
    if (depth < 1 || depth > 64) return makeError("carry policy: depth must be 1-64");
    const auto t0 = Clock::now();
    const std::size_t n = g.states.size();
    CarryPolicy p;
    p.direction = direction, p.depth = depth, p.weights = w;
    std::vector<double> v(n, 0.0), nv(n, 0.0);
    std::vector<double> reward(g.edges.size());
    for (std::size_t e = 0; e < g.edges.size(); ++e) reward[e] = carryEdgeReward(g, g.edges[e], w, direction);
    const glm::vec2 vp = carryDirection(direction) * static_cast<float>(w.speed);
    p.best.assign(n, -1);
    for (int d = 0; d < depth; ++d) {
        if (progress && !progress(static_cast<double>(d) / depth, "carry policy")) return cancelled();
        for (std::size_t i = 0; i < n; ++i) {
            double best = -1e300;
            std::int32_t arg = -1;
            for (std::uint32_t e = g.firstEdge[i]; e < g.firstEdge[i + 1]; ++e) {
                const double q = reward[e] + w.gamma * v[static_cast<std::size_t>(g.edges[e].to)];
                if (q > best) best = q, arg = static_cast<std::int32_t>(e);
            }
            if (arg < 0) {
                // No edge: valued as standing still where it is.
                const auto& s = g.states[i];
                best = -(w.wTheta * (s.thetaA * s.thetaA + s.thetaB * s.thetaB) + w.wV * static_cast<double>(glm::dot(vp, vp))) + w.gamma * v[i];
            }
            nv[i] = best;
            p.best[i] = arg;
        }
        std::swap(v, nv);
    }
    p.value = std::move(v);
    p.seconds = since(t0);
    return p;
}

// ---- paths ---------------------------------------------------------------------------

Result<CarryPath> parseCarryPath(std::string_view spec) {
    const std::string s(spec);
    if (s.rfind("circle:", 0) != 0) return makeError("path '" + s + "': expected circle:R or a JSON file");
    char* end = nullptr;
    const std::string num = s.substr(7);
    const double r = std::strtod(num.c_str(), &end);
    if (num.empty() || end != num.c_str() + num.size() || !std::isfinite(r) || r < 0.5 || r > 1000)
        return makeError("path '" + s + "': the radius must be a number in [0.5, 1000] m");
    CarryPath p;
    p.loop = true;
    const int n = std::clamp(static_cast<int>(std::ceil(2 * kPi * r / 0.1)), 32, 4096);
    for (int i = 0; i < n; ++i) {
        const double a = 2 * kPi * i / n;
        p.points.emplace_back(static_cast<float>(r * std::cos(a)), static_cast<float>(r * std::sin(a)));
    }
    return p;
}

Result<CarryPath> carryPathFromJson(std::string_view text, std::string_view fileName) {
    const std::string f(fileName);
    auto j = nlohmann::json::parse(text, nullptr, false);
    if (j.is_discarded() || !j.is_object()) return makeError(f + ": not a JSON object");
    if (!j.contains("version") || j["version"] != 1) return makeError(f + ": /version: must be 1");
    CarryPath p;
    if (j.contains("loop")) {
        if (!j["loop"].is_boolean()) return makeError(f + ": /loop: must be true or false");
        p.loop = j["loop"].get<bool>();
    }
    const auto pts = j.find("points");
    if (pts == j.end() || !pts->is_array() || pts->size() < 2 || pts->size() > 100000)
        return makeError(f + ": /points: must be an array of 2 to 100000 [x, z] points");
    for (std::size_t i = 0; i < pts->size(); ++i) {
        const auto& q = (*pts)[i];
        const std::string where = f + ": /points/" + std::to_string(i);
        if (!q.is_array() || q.size() != 2 || !q[0].is_number() || !q[1].is_number()) return makeError(where + ": must be [x, z] (metres)");
        const double x = q[0].get<double>(), z = q[1].get<double>();
        if (!std::isfinite(x) || !std::isfinite(z) || std::abs(x) > sim::kMaxCoordinate || std::abs(z) > sim::kMaxCoordinate)
            return makeError(where + ": coordinates must be finite and within 10 km");
        p.points.emplace_back(static_cast<float>(x), static_cast<float>(z));
    }
    return p;
}

namespace {

// Closest point of a path: segment index, fraction, distance.
struct OnPath {
    std::size_t seg = 0;
    double u = 0, d = 1e300;
};
std::size_t segments(const CarryPath& p) { return p.loop ? p.points.size() : p.points.size() - 1; }
glm::vec2 segA(const CarryPath& p, std::size_t i) { return p.points[i]; }
glm::vec2 segB(const CarryPath& p, std::size_t i) { return p.points[(i + 1) % p.points.size()]; }
OnPath closest(const CarryPath& p, glm::vec2 q) {
    OnPath best;
    for (std::size_t i = 0; i < segments(p); ++i) {
        const glm::vec2 a = segA(p, i), ab = segB(p, i) - a;
        const float l2 = glm::dot(ab, ab);
        const double u = l2 > 0 ? std::clamp(static_cast<double>(glm::dot(q - a, ab) / l2), 0.0, 1.0) : 0.0;
        const double d = static_cast<double>(glm::length(q - (a + ab * static_cast<float>(u))));
        if (d < best.d) best = {i, u, d};
    }
    return best;
}
// The point `ahead` m along the path from a closest point (clamped at an open path's end).
glm::vec2 along(const CarryPath& p, OnPath at, double ahead, bool& atEnd) {
    atEnd = false;
    std::size_t i = at.seg;
    double u = at.u;
    for (std::size_t guard = 0; guard < 2 * segments(p) + 2; ++guard) {
        const glm::vec2 a = segA(p, i), b = segB(p, i);
        const double len = static_cast<double>(glm::length(b - a));
        const double left = (1.0 - u) * len;
        if (ahead <= left || (!p.loop && i + 1 == segments(p))) {
            const double t = len > 0 ? std::min(1.0, u + ahead / len) : 1.0;
            if (!p.loop && i + 1 == segments(p) && ahead >= left) atEnd = true;
            return a + (b - a) * static_cast<float>(t);
        }
        ahead -= left;
        u = 0;
        i = (i + 1) % segments(p);
    }
    return segB(p, i);
}

}  // namespace

double distanceToCarryPath(const CarryPath& path, glm::vec2 p) { return path.points.size() < 2 ? 0.0 : closest(path, p).d; }

// ---- run time ------------------------------------------------------------------------

Result<CarryRun> runCarry(const sim::ActionLibrary& lib, const CarryGraph& g, const std::vector<CarryPolicy>& policies, const CarryPath& path,
                          const CarryRunOptions& o, const ProgressFn& progress) {
    if (policies.size() != static_cast<std::size_t>(kCarryDirections)) return makeError("carry: one policy per direction (8) is needed");
    for (int k = 0; k < kCarryDirections; ++k)
        if (policies[static_cast<std::size_t>(k)].direction != k || policies[static_cast<std::size_t>(k)].best.size() != g.states.size())
            return makeError("carry: the policies do not belong to this graph");
    if (path.points.size() < 2) return makeError("carry: the path needs two points or more");
    if (!(o.duration > 0 && o.duration <= sim::kMaxSceneSeconds)) return makeError("carry: the duration must be in (0, 3600] s");
    if (g.states.empty()) return makeError("carry: the graph has no states");
    for (int a : {g.hold}) {
        if (a < 0 || a >= lib.size()) return makeError("carry: the graph does not belong to this library");
    }
    for (const auto& e : g.edges)
        if (e.actionA >= lib.size() || e.actionB >= lib.size()) return makeError("carry: the graph does not belong to this library");
    CarryRun run;
    sim::Scene& scene = run.scene;
    scene.duration = o.duration;
    scene.seed = o.seed;
    scene.spec = o.record;
    const double L = g.options.boxLength;
    const double half = 0.5 * L + g.gripReach;
    // Start: the box's middle on the path's first point, along the path's first direction.
    const glm::vec2 p0 = path.points[0];
    glm::vec2 u = path.points[1] - p0;
    u = glm::length(u) > 1e-6f ? glm::normalize(u) : glm::vec2(0, 1);
    RootXf a, b;
    a.pos = p0 - u * static_cast<float>(half);
    a.heading = sim::angleOf(u);
    b.pos = p0 + u * static_cast<float>(half);
    b.heading = sim::angleOf(-u);
    scene.characters.resize(3);
    const char* names[] = {"carrier A", "carrier B"};
    for (int c = 0; c < 2; ++c) {
        auto& sc = scene.characters[static_cast<std::size_t>(c)];
        sc.name = names[c];
        sc.side = 0;
        sc.group = 0;
        sc.preset = "carry";
        sc.depth = policies[0].depth;
    }
    scene.characters[2].name = "box";
    scene.characters[2].body = "box";
    sim::FloorMark mark{"path", path.points};
    if (path.loop) mark.points.push_back(path.points.front());
    scene.marks.push_back(std::move(mark));
    double t = 0;
    while (t < o.duration - 1e-9) {
        if (progress && !progress(t / o.duration, "carrying")) return cancelled();
        const auto d0 = Clock::now();
        const InteractionState s = pairState(a, b);
        int state = g.find(s, false);
        if (state < 0) {
            ++run.stats.offGraph;
            state = g.find(s, true);
        }
        // The way to the path ahead of the box's middle, in A's frame: the nearest of the 8 directions.
        const glm::vec2 mid = 0.5f * (floorOf(a.apply(gripAt(lib, g.hold, 0))) + floorOf(b.apply(gripAt(lib, g.hold, 0))));
        bool atEnd = false;
        const glm::vec2 target = along(path, closest(path, mid), o.lookahead, atEnd);
        const glm::vec2 local = sim::rotateFloor(target - mid, -a.heading);
        int k = static_cast<int>(std::lround(std::atan2(static_cast<double>(local.x), static_cast<double>(local.y)) / (kPi / 4.0)));
        k = ((k % kCarryDirections) + kCarryDirections) % kCarryDirections;
        int actA = g.hold, actB = g.hold;
        const bool arrived = atEnd && glm::length(target - mid) < 0.15f;
        if (state >= 0 && !arrived) {
            const std::int32_t e = policies[static_cast<std::size_t>(k)].best[static_cast<std::size_t>(state)];
            if (e >= 0) actA = g.edges[static_cast<std::size_t>(e)].actionA, actB = g.edges[static_cast<std::size_t>(e)].actionB;
        }
        if (actA == g.hold && actB == g.hold) ++run.stats.holds;
        ++run.stats.decisions;
        run.stats.decideSeconds += since(d0);
        const double da = lib.action(actA).duration, db = lib.action(actB).duration;
        scene.characters[0].track.push_back({actA, t, 0.0, t + da, a, false, false});
        scene.characters[1].track.push_back({actB, t, 0.0, t + db, b, false, false});
        a = a * lib.action(actA).end;
        b = b * lib.action(actB).end;
        t += std::max(da, db);
    }
    // The box, and what the run measured: every 1/30 s.
    auto& box = scene.characters[2];
    const int n = static_cast<int>(std::floor(o.duration * sim::kSampleRate)) + 1;
    double pathSum = 0;
    for (int i = 0; i < n; ++i) {
        const double tt = i / sim::kSampleRate;
        const BoxSample bs = boxAt(lib, scene, tt);
        const glm::vec3* grip = bs.grip;
        box.keys.push_back(bs.key);
        const double e = distanceToCarryPath(path, bs.middle);
        pathSum += e;
        run.stats.pathErrorMax = std::max(run.stats.pathErrorMax, e);
        run.stats.gripErrorMax = std::max(run.stats.gripErrorMax, std::abs(static_cast<double>(glm::length(grip[0] - grip[1])) - L) / L);
    }
    run.stats.pathErrorMean = pathSum / n;
    return run;
}

// ---- the pair in real time ------------------------------------------------------------

namespace {
Status checkPolicySet(const CarryGraph& g, const CarryPolicySet* p) {
    if (!p || p->policies.size() != static_cast<std::size_t>(kCarryDirections)) return makeError("carry: one policy per direction (8) is needed");
    for (int k = 0; k < kCarryDirections; ++k) {
        const auto& q = p->policies[static_cast<std::size_t>(k)];
        if (q.direction != k || q.best.size() != g.states.size()) return makeError("carry: the policies do not belong to this graph");
    }
    return {};
}
}  // namespace

CarryDriver::CarryDriver(const sim::ActionLibrary& lib, std::shared_ptr<const CarryGraph> g, std::shared_ptr<const CarryPolicySet> p)
    : lib_(lib), graph_(std::move(g)), policies_(std::move(p)) {}

Result<std::unique_ptr<CarryDriver>> CarryDriver::make(const sim::ActionLibrary& lib, std::shared_ptr<const CarryGraph> g,
                                                       std::shared_ptr<const CarryPolicySet> policies, std::optional<CarryPath> path,
                                                       glm::vec2 start, double heading, double lookahead) {
    if (!g || g->states.empty()) return makeError("carry: the graph has no states");
    if (auto st = checkPolicySet(*g, policies.get()); !st) return st.error();
    if (g->hold < 0 || g->hold >= lib.size()) return makeError("carry: the graph does not belong to this library");
    for (const auto& e : g->edges)
        if (e.actionA >= lib.size() || e.actionB >= lib.size()) return makeError("carry: the graph does not belong to this library");
    if (path && path->points.size() < 2) return makeError("carry: the path needs two points or more");
    if (!(lookahead > 0 && lookahead < 100) || !std::isfinite(heading) || !std::isfinite(start.x) || !std::isfinite(start.y))
        return makeError("carry: the start and the lookahead must be finite");
    std::unique_ptr<CarryDriver> d(new CarryDriver(lib, std::move(g), std::move(policies)));
    d->lookahead_ = lookahead;
    d->path_ = std::move(path);
    const double half = 0.5 * d->graph_->options.boxLength + d->graph_->gripReach;
    glm::vec2 p0 = start, u(static_cast<float>(std::sin(heading)), static_cast<float>(std::cos(heading)));
    if (d->path_) {  // as runCarry: the box's middle on the first point, along the first direction
        p0 = d->path_->points[0];
        u = d->path_->points[1] - p0;
        u = glm::length(u) > 1e-6f ? glm::normalize(u) : glm::vec2(0, 1);
    }
    d->a_.pos = p0 - u * static_cast<float>(half);
    d->a_.heading = sim::angleOf(u);
    d->b_.pos = p0 + u * static_cast<float>(half);
    d->b_.heading = sim::angleOf(-u);
    d->desired_ = d->a_.heading;
    sim::Scene& scene = d->scene_;
    scene.characters.resize(3);
    const char* names[] = {"carrier A", "carrier B"};
    for (int c = 0; c < 2; ++c) {
        auto& sc = scene.characters[static_cast<std::size_t>(c)];
        sc.name = names[c];
        sc.preset = "carry";
        sc.depth = d->policies_->depth;
    }
    scene.characters[2].name = "box";
    scene.characters[2].body = "box";
    if (d->path_) {
        sim::FloorMark mark{"path", d->path_->points};
        if (d->path_->loop) mark.points.push_back(d->path_->points.front());
        scene.marks.push_back(std::move(mark));
    }
    d->decide();
    d->sampleBox(0.0);
    return d;
}

Status CarryDriver::setPolicies(std::shared_ptr<const CarryPolicySet> policies) {
    if (auto st = checkPolicySet(*graph_, policies.get()); !st) return st;
    policies_ = std::move(policies);
    return {};
}

void CarryDriver::steer(double worldAngle, bool moving) {
    if (std::isfinite(worldAngle)) desired_ = sim::wrapAngle(worldAngle);
    moving_ = moving;
}

void CarryDriver::decide() {
    const CarryGraph& g = *graph_;
    const auto d0 = Clock::now();
    const InteractionState s = pairState(a_, b_);
    int state = g.find(s, false);
    now_.offGraph = state < 0;
    if (state < 0) {
        ++stats_.offGraph;
        state = g.find(s, true);
    }
    now_.state = state;
    const glm::vec2 mid = 0.5f * (floorOf(a_.apply(gripAt(lib_, g.hold, 0))) + floorOf(b_.apply(gripAt(lib_, g.hold, 0))));
    // The way to go in the world: to the path ahead of the box's middle, or the steered direction.
    glm::vec2 way(0.0f);
    bool go = false;
    if (path_) {
        bool atEnd = false;
        const glm::vec2 target = along(*path_, closest(*path_, mid), lookahead_, atEnd);
        way = target - mid;
        go = !(atEnd && glm::length(way) < 0.15f);
    } else {
        way = glm::vec2(static_cast<float>(std::sin(desired_)), static_cast<float>(std::cos(desired_)));
        go = moving_;
    }
    const glm::vec2 local = sim::rotateFloor(way, -a_.heading);
    int k = static_cast<int>(std::lround(std::atan2(static_cast<double>(local.x), static_cast<double>(local.y)) / (kPi / 4.0)));
    k = ((k % kCarryDirections) + kCarryDirections) % kCarryDirections;
    int actA = g.hold, actB = g.hold;
    now_.direction = -1;
    if (state >= 0 && go) {
        const std::int32_t e = policies_->policies[static_cast<std::size_t>(k)].best[static_cast<std::size_t>(state)];
        if (e >= 0) actA = g.edges[static_cast<std::size_t>(e)].actionA, actB = g.edges[static_cast<std::size_t>(e)].actionB, now_.direction = k;
    }
    if (actA == g.hold && actB == g.hold) ++stats_.holds;
    ++stats_.decisions;
    now_.heading = a_.heading;
    const double da = lib_.action(actA).duration, db = lib_.action(actB).duration;
    scene_.characters[0].track.push_back({actA, next_, 0.0, next_ + da, a_, false, false});
    scene_.characters[1].track.push_back({actB, next_, 0.0, next_ + db, b_, false, false});
    a_ = a_ * lib_.action(actA).end;
    b_ = b_ * lib_.action(actB).end;
    next_ += std::max({da, db, 1.0 / sim::kSampleRate});
    stats_.decideSeconds += since(d0);
}

void CarryDriver::sampleBox(double tt) {
    const double L = graph_->options.boxLength;
    const BoxSample bs = boxAt(lib_, scene_, tt);
    scene_.characters[2].keys.push_back(bs.key);
    now_.boxMiddle = bs.middle;
    now_.gripDistance = static_cast<double>(glm::length(bs.grip[0] - bs.grip[1]));
    ++samples_;
    if (path_) {
        now_.pathError = distanceToCarryPath(*path_, now_.boxMiddle);
        pathSum_ += now_.pathError;
        stats_.pathErrorMax = std::max(stats_.pathErrorMax, now_.pathError);
        stats_.pathErrorMean = pathSum_ / static_cast<double>(samples_);
    }
    stats_.gripErrorMax = std::max(stats_.gripErrorMax, std::abs(now_.gripDistance - L) / L);
}

void CarryDriver::advance(double dt) {
    if (!(dt > 0) || !std::isfinite(dt)) return;
    const double end = std::min(time_ + dt, sim::kMaxSceneSeconds);
    // Box keys every 1/30 s up to `end`; a decision whenever the actions playing end.
    for (;;) {
        const double nextKey = static_cast<double>(samples_) / sim::kSampleRate;
        if (nextKey > end + 1e-9) break;
        while (next_ <= nextKey + 1e-9) decide();
        sampleBox(nextKey);
    }
    while (next_ <= end + 1e-9) decide();
    time_ = end;
    scene_.duration = time_;
}

}  // namespace fray::igraph
