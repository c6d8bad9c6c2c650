// Policies over the Interaction Graph (SPEC 3.4): per-edge competitive
// rewards, min-max to a depth with a discount, and a service that recomputes
// a policy in the background while the previous one stays in use.
#include <algorithm>
#include <array>
#include <charconv>
#include <chrono>
#include <cmath>
#include <limits>
#include <atomic>
#include <cstdlib>
#include <mutex>
#include <thread>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "fray/igraph/background.h"
#include "fray/igraph/igraph.h"

namespace fray::igraph {

namespace {

struct NamedWeight {
    const char* name;
    double RewardWeights::*field;
};
constexpr NamedWeight kWeights[] = {{"w_theta", &RewardWeights::wTheta}, {"w_d", &RewardWeights::wD}, {"d_p", &RewardWeights::dP},
                                    {"w_a", &RewardWeights::wA},         {"w_r", &RewardWeights::wR}, {"gamma", &RewardWeights::gamma},
                                    {"tau", &RewardWeights::tau},          {"opponent_mix", &RewardWeights::opponentMix},
                                    {"blur", &RewardWeights::blur}};

}  // namespace

Status validate(const RewardWeights& w) {
    for (const auto& nw : kWeights) {
        const double v = w.*nw.field;
        if (!std::isfinite(v)) return makeError(std::string("reward weight ") + nw.name + " is not a finite number");
        if (v < 0) return makeError(std::string("reward weight ") + nw.name + " is negative (" + std::to_string(v) + ")");
    }
    if (w.gamma > 1) return makeError("reward weight gamma must be in [0, 1], got " + std::to_string(w.gamma));
    if (w.blur > 1) return makeError("reward weight blur must be in [0, 1], got " + std::to_string(w.blur));
    if (w.opponentMix > 1) return makeError("reward weight opponent_mix must be in [0, 1], got " + std::to_string(w.opponentMix));
    return {};
}

double RewardWeights::discount(int frames) const {
    if (!(tau > 0) || frames <= 0) return gamma;
    return std::pow(gamma, frames / sim::kSampleRate / tau);
}

const std::vector<std::string>& styleNames() {
    static const std::vector<std::string> names = {"general", "infighter", "outboxer"};
    return names;
}

Result<RewardWeights> stylePreset(std::string_view name) {
    RewardWeights w;
    if (name == "general") return w;
    if (name == "infighter") {  // close in and trade blows
        w.dP = 0.6, w.wD = 2, w.wA = 3, w.wR = 1;
        return w;
    }
    if (name == "outboxer") {  // keep the distance, avoid blows
        w.dP = 1.3, w.wD = 2, w.wA = 1.5, w.wR = 4;
        return w;
    }
    return makeError("no boxing style named '" + std::string(name) + "' (general, infighter, outboxer)");
}

Status applyRewardEdit(RewardWeights& w, std::string_view edit) {
    const auto eq = edit.find('=');
    if (eq == std::string_view::npos) return makeError("'" + std::string(edit) + "': expected name=value");
    const std::string_view key = edit.substr(0, eq), text = edit.substr(eq + 1);
    if (key == "opponent") {
        if (text != "own" && text != "mine") return makeError("reward opponent: '" + std::string(text) + "' is not own or mine");
        w.opponentOwn = text == "own";
        return {};
    }
    for (const auto& nw : kWeights) {
        if (key != nw.name) continue;
        // strtod for nan and inf, which from_chars also reads: both are refused by validate.
        const std::string s(text);
        char* end = nullptr;
        const double v = std::strtod(s.c_str(), &end);
        if (s.empty() || end != s.c_str() + s.size()) return makeError("reward weight " + std::string(key) + ": '" + s + "' is not a number");
        RewardWeights probe = w;
        probe.*nw.field = v;
        if (auto st = validate(probe); !st) return st;
        w = probe;
        return {};
    }
    return makeError("no reward weight named '" + std::string(key) + "' (w_theta, w_d, d_p, w_a, w_r, gamma, tau, opponent_mix, blur, opponent)");
}

double edgeReward(const Graph& g, const Edge& e, const RewardWeights& w, bool chooserIsMine) {
    // The geometry where the edge leads: the state's chooser is A there.
    const auto& to = g.states[static_cast<std::size_t>(e.to)];
    const double d = to.r - w.dP;
    if (!chooserIsMine && w.opponentOwn) {
        // The opponent's own W of its edge, against the controlled character.
        const double theta = e.sameChooser() ? to.thetaA : to.thetaB;
        return -(-w.wTheta * theta * theta - w.wD * d * d + w.wA * e.given() - w.wR * e.received());
    }
    const bool mineIsA = e.sameChooser() == chooserIsMine;
    const double theta = mineIsA ? to.thetaA : to.thetaB;
    const double plus = chooserIsMine ? e.given() : e.received();
    const double minus = chooserIsMine ? e.received() : e.given();
    return -w.wTheta * theta * theta - w.wD * d * d + w.wA * plus - w.wR * minus;
}

double Policy::edgeValue(const Graph& g, const Edge& e) const {
    const auto to = static_cast<std::size_t>(e.to);
    const double below = e.sameChooser() ? (mineBelow.empty() ? 0.0 : mineBelow[to]) : (theirsBelow.empty() ? 0.0 : theirsBelow[to]);
    const auto k = static_cast<std::size_t>(&e - g.edges.data());
    return edgeReward(g, e, weights, true) + weights.discount(k < g.edgeFrames.size() ? g.edgeFrames[k] : 0) * below;
}

Result<Policy> computePolicy(const Graph& g, const RewardWeights& w, int depth, const ProgressFn& progress) {
    if (auto st = validate(w); !st) return st.error();
    if (depth < 1 || depth > 64) return makeError("policy depth must be between 1 and 64, got " + std::to_string(depth));
    const auto t0 = std::chrono::steady_clock::now();
    const std::size_t n = g.stateCount();
    Policy p;
    p.weights = w;
    p.depth = depth;
    // Per state, packed so an edge reads one cache line: the movement terms
    // of the reward for whoever is A there and B there, V where the
    // controlled character chooses there (vm) and where the opponent does (vt).
    struct alignas(32) Cell {
        double moveA, moveB, vm, vt;
    };
    std::vector<Cell> cur(n), nxt(n);
    for (std::size_t i = 0; i < n; ++i) {
        const auto& s = g.states[i];
        const double d = s.r - w.dP;
        cur[i] = {-w.wTheta * s.thetaA * s.thetaA - w.wD * d * d, -w.wTheta * s.thetaB * s.thetaB - w.wD * d * d, 0.0, 0.0};
    }
    nxt = cur;
    p.best.assign(n, -1);
    // The discount of an edge by its time to the next decision (RewardWeights::tau).
    const bool timed = w.tau > 0 && g.edgeFrames.size() == g.edges.size();
    const bool blurred = w.blur > 0 && g.nearFirst.size() == n + 1;
    std::array<double, 256> disc{};
    for (int f = 0; f < 256; ++f) disc[static_cast<std::size_t>(f)] = w.discount(f);
    for (int d = 0; d < depth; ++d) {
        if (!reportProgress(progress, static_cast<double>(d) / depth, "policy")) return cancelled();
        const bool last = d + 1 == depth;
        if (last) {
            p.mineBelow.resize(n), p.theirsBelow.resize(n);
            for (std::size_t i = 0; i < n; ++i) p.mineBelow[i] = cur[i].vm, p.theirsBelow[i] = cur[i].vt;
        }
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 2048), [&](const tbb::blocked_range<std::size_t>& range) {
            for (std::size_t i = range.begin(); i < range.end(); ++i) {
                const Edge* b = g.edgesBegin(static_cast<int>(i));
                const Edge* e = g.edgesEnd(static_cast<int>(i));
                if (b == e) {
                    // A dead end (no action lands in a state): valued as
                    // staying where it is, so it is neither a refuge nor a trap.
                    nxt[i].vm = cur[i].moveA + w.gamma * cur[i].vm;
                    nxt[i].vt = (w.opponentOwn ? -cur[i].moveA : cur[i].moveB) + w.gamma * cur[i].vt;
                    continue;
                }
                double best = -std::numeric_limits<double>::infinity(), worst = std::numeric_limits<double>::infinity(), sum = 0;
                std::int32_t bestEdge = -1;
                for (const Edge* x = b; x != e; ++x) {
                    const Cell& t = cur[static_cast<std::size_t>(x->to)];
                    const double given = x->given(), received = x->received();
                    const double gamma = timed ? disc[g.edgeFrames[static_cast<std::size_t>(x - g.edges.data())]] : w.gamma;
                    // = edgeReward(g, *x, w, true / false) + gamma V(next), inlined.
                    const double mine = x->sameChooser() ? t.moveA + w.wA * given - w.wR * received + gamma * t.vm
                                                         : t.moveB + w.wA * given - w.wR * received + gamma * t.vt;
                    if (mine > best) best = mine, bestEdge = static_cast<std::int32_t>(x - g.edges.data());
                    // = edgeReward(g, *x, w, false) + gamma V(next): the opponent's own W against us, or ours.
                    const double theirs =
                        w.opponentOwn ? (x->sameChooser() ? -(t.moveA + w.wA * given - w.wR * received) + gamma * t.vt
                                                          : -(t.moveB + w.wA * given - w.wR * received) + gamma * t.vm)
                                      : (x->sameChooser() ? t.moveB + w.wA * received - w.wR * given + gamma * t.vt
                                                          : t.moveA + w.wA * received - w.wR * given + gamma * t.vm);
                    worst = std::min(worst, theirs);
                    sum += theirs;
                }
                nxt[i].vm = best;
                nxt[i].vt = w.opponentMix > 0 ? (1 - w.opponentMix) * worst + w.opponentMix * sum / static_cast<double>(e - b) : worst;
                if (last) p.best[i] = bestEdge;
            }
        });
        std::swap(cur, nxt);
        if (blurred && !last) {
            // What the next level reads: each state's value blurred with its neighbours'.
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& range) {
                for (std::size_t i = range.begin(); i < range.end(); ++i) {
                    const auto k0 = g.nearFirst[i], k1 = g.nearFirst[i + 1];
                    nxt[i] = cur[i];
                    if (k0 == k1) continue;
                    double m = 0, t = 0;
                    for (auto k = k0; k < k1; ++k) m += cur[g.near[k]].vm, t += cur[g.near[k]].vt;
                    const double inv = 1.0 / static_cast<double>(k1 - k0);
                    nxt[i].vm = (1 - w.blur) * cur[i].vm + w.blur * m * inv;
                    nxt[i].vt = (1 - w.blur) * cur[i].vt + w.blur * t * inv;
                }
            });
            std::swap(cur, nxt);
        }
    }
    p.value.resize(n);
    for (std::size_t i = 0; i < n; ++i) p.value[i] = cur[i].vm;
    p.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    reportProgress(progress, 1.0, "policy");
    return p;
}

// The thread, the cancel flag and the swap are BackgroundRecompute's
// (fray/igraph/background.h), shared with the carriers' CarryPolicyService.
struct PolicyService::Impl {
    std::shared_ptr<const Graph> graph;
    BackgroundRecompute<Policy> work;
    Impl(std::shared_ptr<const Graph> g, std::shared_ptr<const Policy> initial) : graph(std::move(g)), work(std::move(initial)) {}
};

PolicyService::PolicyService(std::shared_ptr<const Graph> graph, std::shared_ptr<const Policy> initial)
    : impl_(std::make_unique<Impl>(std::move(graph), std::move(initial))) {}

PolicyService::~PolicyService() { impl_->work.stop(); }

std::shared_ptr<const Policy> PolicyService::current() const { return impl_->work.current(); }

Status PolicyService::request(const RewardWeights& w, int depth) {
    if (auto st = validate(w); !st) return st;
    if (depth < 1 || depth > 64) return makeError("policy depth must be between 1 and 64, got " + std::to_string(depth));
    impl_->work.start([graph = impl_->graph, w, depth](const ProgressFn& progress) { return computePolicy(*graph, w, depth, progress); });
    return {};
}

bool PolicyService::busy() const { return impl_->work.busy(); }

Status PolicyService::wait() { return impl_->work.wait(); }

}  // namespace fray::igraph
