// The rules a graph character plays by, and the duel simulation every part
// of the Interaction Graph shares (sampling, edges, coverage, matches).
#include <algorithm>
#include <cmath>
#include <map>

#include "fray/sim/planner.h"
#include "game.h"

namespace fray::igraph {

using sim::ActionLibrary;

namespace {

constexpr std::uint32_t kChoosable = sim::kPunch | sim::kKick | sim::kBlock | sim::kAvoid | sim::kStep | sim::kIdle |
                                     sim::kTransition | sim::kTurn;

std::uint64_t fnv(std::uint64_t h, std::uint64_t v) {
    for (int k = 0; k < 8; ++k) {
        h ^= (v >> (8 * k)) & 0xff;
        h *= 1099511628211ull;
    }
    return h;
}

}  // namespace

Rules::~Rules() = default;

Result<std::shared_ptr<const Rules>> Rules::make(const ActionLibrary& lib, std::vector<int> actions) {
    bool anyAttack = true;
    if (actions.empty()) {
        // The fighting captures: motions with an attack in them (not the
        // walks, runs and carries beside them).
        std::vector<char> fighting(static_cast<std::size_t>(lib.motionCount()), 0);
        for (const auto& la : lib.actions()) {
            if (la.is(sim::kAttack) && la.effector >= 0) fighting[static_cast<std::size_t>(la.motion)] = 1;
        }
        anyAttack = std::any_of(fighting.begin(), fighting.end(), [](char f) { return f != 0; });
        for (int a = 0; a < lib.size(); ++a) {
            const auto& la = lib.action(a);
            if (la.is(kChoosable) && !la.is(sim::kReactive) && fighting[static_cast<std::size_t>(la.motion)]) actions.push_back(a);
        }
    }
    std::sort(actions.begin(), actions.end());
    actions.erase(std::unique(actions.begin(), actions.end()), actions.end());
    for (int a : actions) {
        if (a < 0 || a >= lib.size()) return makeError("Interaction Graph: action index " + std::to_string(a) + " is out of range");
        if (lib.action(a).is(sim::kReactive)) {
            return makeError("Interaction Graph: " + lib.action(a).label() + " is a reaction (pushed or falling): it cannot be chosen");
        }
    }
    if (lib.size() > Edge::kMaxAction) return makeError("Interaction Graph: the library has more than 32767 actions");
    if (!anyAttack) {
        return makeError("Interaction Graph: the project has no attack actions (punch or kick); annotate some actions as punches or kicks "
                         "first (two carriers of a box: igraph play --kind carry)");
    }
    if (actions.empty()) return makeError("Interaction Graph: the project has no actions a boxer can choose (punch, kick, block, avoid, step, idle)");
    if (std::none_of(actions.begin(), actions.end(), [&](int a) { return lib.action(a).is(sim::kAttack) && lib.action(a).effector >= 0; })) {
        return makeError("Interaction Graph: the project has no attack actions (punch or kick) among the chosen actions; "
                         "annotate some actions as punches or kicks first");
    }
    std::shared_ptr<Rules> r(new Rules());
    r->lib_ = &lib;
    r->actions_ = actions;
    std::vector<char> chosen(static_cast<std::size_t>(lib.size()), 0);
    for (int a : actions) chosen[static_cast<std::size_t>(a)] = 1;
    for (int a : actions) {
        if (lib.action(a).is(sim::kIdle)) r->idle_.push_back(a);
    }
    if (r->idle_.empty()) r->idle_ = actions;
    // Next sets, by value.
    std::map<std::vector<int>, int> ids;
    r->nextSetOf_.assign(static_cast<std::size_t>(lib.size()), 0);
    std::size_t usable = 0;
    for (int a = 0; a < lib.size(); ++a) {
        std::vector<int> next;
        for (int b : lib.next()[static_cast<std::size_t>(a)]) {
            if (chosen[static_cast<std::size_t>(b)]) next.push_back(b);
        }
        if (!next.empty() && chosen[static_cast<std::size_t>(a)]) ++usable;
        if (next.empty()) next = r->idle_;
        auto [it, added] = ids.emplace(next, static_cast<int>(r->nextSets_.size()));
        if (added) r->nextSets_.push_back(next);
        r->nextSetOf_[static_cast<std::size_t>(a)] = it->second;
    }
    if (usable == 0) return makeError("Interaction Graph: no chosen action can follow another in the motion graph");
    for (const auto& set : r->nextSets_) {
        std::vector<int> folded;
        std::vector<int> seen;
        for (int a : set) {
            const int cls = lib.variantClass()[static_cast<std::size_t>(a)];
            if (std::find(seen.begin(), seen.end(), cls) != seen.end()) continue;
            seen.push_back(cls);
            folded.push_back(a);
        }
        r->folded_.push_back(std::move(folded));
    }
    r->engine_ = std::make_unique<sim::detail::InteractionEngine>(lib);
    std::vector<int> reactions;
    for (int a = 0; a < lib.size(); ++a) {
        if (lib.action(a).is(sim::kReactive)) reactions.push_back(a);
    }
    r->pool_ = r->engine_->addPool(reactions);
    r->fallImpulse_ = sim::SimOptions{}.fallImpulse;
    std::uint64_t h = 1469598103934665603ull;
    for (int a : actions) h = fnv(h, static_cast<std::uint64_t>(a));
    r->key_ = h;
    return std::shared_ptr<const Rules>(std::move(r));
}

double distance(const InteractionState& a, const InteractionState& b, const DistanceScale& s) {
    if (a.nextSet != b.nextSet || a.actionB != b.actionB || !(std::fabs(a.frameB - b.frameB) < s.frameSigma)) {
        return std::numeric_limits<double>::infinity();
    }
    return std::fabs(a.r - b.r) / s.sigmaR + std::fabs(sim::wrapAngle(a.thetaA - b.thetaA)) / s.sigmaTheta +
           std::fabs(sim::wrapAngle(a.thetaB - b.thetaB)) / s.sigmaTheta;
}

Edge Edge::make(int action, int to, bool same, double given, double received) {
    auto q = [](double v) { return static_cast<std::uint8_t>(std::clamp(std::lround(v * 10), 0L, 255L)); };
    Edge e;
    e.to = to;
    e.actionBits = static_cast<std::uint16_t>(action | (same ? 0x8000 : 0));
    e.givenQ = q(given);
    e.receivedQ = q(received);
    return e;
}

namespace detail {

InteractionState stateOf(const Rules& rules, const Body& me, const Body& other, double t) {
    const auto& lib = rules.library();
    const sim::RootXf pm = me.placement(lib, t), po = other.placement(lib, t);
    const glm::vec2 d = po.pos - pm.pos;
    InteractionState s;
    s.r = static_cast<double>(glm::length(d));
    s.thetaA = s.r > 1e-6 ? sim::wrapAngle(sim::angleOf(d) - pm.heading) : 0.0;
    s.thetaB = s.r > 1e-6 ? sim::wrapAngle(sim::angleOf(-d) - po.heading) : 0.0;
    s.nextSet = rules.nextSetOf(me.action);
    s.actionB = other.action;
    const double dur = lib.action(other.action).duration;
    s.frameB = std::clamp(other.clipTime(t), 0.0, dur) * sim::kSampleRate;
    return s;
}

Body bodyAt(const ActionLibrary& lib, int action, double clip, const sim::RootXf& at, double t) {
    Body b;
    b.action = action;
    b.offset = clip;
    b.start = t;
    b.end = t + std::max(lib.action(action).duration - clip, 1.0 / sim::kSampleRate);
    b.root = at * lib.rootAt(action, clip).inverse();
    b.reacting = lib.action(action).is(sim::kReactive);
    return b;
}

sim::detail::ForcedReaction applyBlow(const Rules& rules, Body& attacker, Body& victim, const sim::detail::HitCandidate& hit, double t) {
    attacker.spent = true;
    if (hit.blocked) return {};
    const auto& lib = rules.library();
    const double impulse = sim::detail::InteractionEngine::impulse(hit);
    const auto reaction = rules.engine().react(victim.playing(), attacker.placement(lib, t), t, impulse > rules.fallImpulse(), rules.pool());
    if (reaction.action >= 0) {
        victim.action = reaction.action;
        victim.start = t;
        victim.offset = reaction.offset;
        victim.end = reaction.end;
        victim.root = reaction.root;
        victim.spent = true;
        victim.reacting = true;
    }
    return reaction;
}

double advanceDuel(const Rules& rules, std::array<Body, 2>& b, double t0, Outcome& out) {
    for (int guard = 0; guard < 16; ++guard) {
        const double t1 = std::min(b[0].end, b[1].end);
        sim::detail::HitCandidate best;
        int att = -1;
        for (int a = 0; a < 2; ++a) {
            const auto h = rules.engine().strike(b[static_cast<std::size_t>(a)].playing(), b[static_cast<std::size_t>(a)].spent,
                                                 b[static_cast<std::size_t>(1 - a)].playing(), b[static_cast<std::size_t>(1 - a)].reacting,
                                                 t0, t1);
            if (h.before(best)) best = h, att = a;
        }
        if (att < 0) return t1;
        const auto ua = static_cast<std::size_t>(att), ud = static_cast<std::size_t>(1 - att);
        if (best.blocked) {
            ++out.blocked[ud];
        } else {
            out.given[ua] += static_cast<float>(best.speed);
            out.received[ud] += static_cast<float>(best.speed);
            ++out.landed[ua];
            ++out.suffered[ud];
        }
        applyBlow(rules, b[ua], b[ud], best, best.time);
        t0 = best.time;
    }
    return std::min(b[0].end, b[1].end);
}

}  // namespace detail

}  // namespace fray::igraph
