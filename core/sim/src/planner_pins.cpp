// Pins in tree expansion (SceneSpec::pins, docs/TREE_EXPANSION.md "Pins"): the choice at
// a decision of a pinned character, forced to the pinned action at the pin's
// decision and steered before it so the motion graph reaches that action
// there: decide() is asked again with a filter on its root candidates. Inside
// the search's look-ahead the pin's node of a pinned character offers only the
// pinned actions (PinGuide::pinNode, applied by the Pruner).
#include <algorithm>
#include <cstdio>

#include "planner_state.h"

namespace fray::sim::planner {

namespace {

std::string seconds(double t) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2f s", t);
    return buf;
}

}  // namespace

PinGuide::PinGuide(const Context& ctx, const SceneSpec& spec) {
    for (std::size_t i = 0; i < spec.pins.size(); ++i) {
        for (std::size_t m = 0; m < ctx.members.size(); ++m) {
            if (ctx.members[m].global == spec.pins[i].character) {
                pins_.push_back({&spec.pins[i], static_cast<int>(i), static_cast<int>(m), false});
            }
        }
    }
    std::stable_sort(pins_.begin(), pins_.end(), [](const Entry& a, const Entry& b) {
        return a.member != b.member ? a.member < b.member : a.pin->time < b.pin->time;
    });
}

Error PinGuide::missed(const Context& ctx, const Entry& e, const GroupState* g) const {
    const ActionPin& p = *e.pin;
    std::string msg = "/pins/" + std::to_string(e.index) + "/action: '" + specOf(ctx, e.member).name + "' cannot start '" +
                      p.key + "' between " + seconds(p.time) + " and " + seconds(p.time + kPinLate);
    if (g) {
        const auto& s = g->c[static_cast<std::size_t>(e.member)];
        const auto& x = act(ctx, s.action);
        msg += ": it has no decision there from which the motion graph reaches it; the next one comes at " + seconds(g->time) +
               ", after '" + x.name + "'" + (x.is(kReactive) ? " (a reaction to a hit)" : "");
    } else {
        msg += ": it has no decision there before the scene ends";
    }
    return makeError(msg + "; move the pin or pick another action");
}

Result<int> PinGuide::choose(const Context& ctx, const GroupState& g, int who, int decided,
                             const std::function<int(const CandidateFilter&)>& redecide) {
    auto it = std::find_if(pins_.begin(), pins_.end(), [&](const Entry& e) { return e.member == who && !e.fired; });
    if (it == pins_.end()) return decided;
    Entry& e = *it;
    const ActionPin& p = *e.pin;
    const double t = g.time;
    const auto& legal = ctx.members[static_cast<std::size_t>(who)].legal;
    const auto pinned = [&](int a) { return std::binary_search(p.actions.begin(), p.actions.end(), a); };
    const auto reaches = [&](int a) {
        const auto& next = legal[static_cast<std::size_t>(a)];
        return std::any_of(next.begin(), next.end(), pinned);
    };
    const auto endOf = [&](int a) { return t + act(ctx, a).duration; };
    const auto keepIf = [](std::vector<int>& c, const auto& keep) {
        std::vector<int> kept;
        std::copy_if(c.begin(), c.end(), std::back_inserter(kept), keep);
        if (!kept.empty()) c.swap(kept);
    };
    if (t > p.time + kPinLate) return missed(ctx, e, &g);
    if (t >= p.time - kPinEarly) {
        // The pin's decision.
        if (pinned(decided)) {
            e.fired = true;
            return decided;
        }
        const auto& next = legal[static_cast<std::size_t>(g.c[static_cast<std::size_t>(who)].action)];
        std::vector<int> reachable;
        std::copy_if(next.begin(), next.end(), std::back_inserter(reachable), pinned);
        if (!reachable.empty()) {
            // The pinned actions that passed pruning; when none did, every
            // one the motion graph allows here (the user's choice wins).
            const CandidateFilter only = [&](std::vector<int>& c) {
                std::vector<int> kept;
                std::copy_if(c.begin(), c.end(), std::back_inserter(kept), pinned);
                c = kept.empty() ? reachable : kept;
            };
            e.fired = true;
            return redecide(only);
        }
        // Not reachable from here: a step from which it is, ending in time.
        const auto bridge = [&](int a) { return reaches(a) && endOf(a) <= p.time + kPinLate; };
        if (bridge(decided)) return decided;
        return redecide([&](std::vector<int>& c) { keepIf(c, bridge); });
    }
    // Before the pin: an action whose end brings the pin's decision must reach a pinned action.
    const auto fits = [&](int a) {
        const double end = endOf(a);
        return end < p.time - kPinEarly || (end <= p.time + kPinLate && reaches(a));
    };
    if (fits(decided)) return decided;
    return redecide([&](std::vector<int>& c) { keepIf(c, fits); });
}

void PinGuide::inTree(Context& ctx) const {
    ctx.treePins.assign(ctx.members.size(), nullptr);
    for (const Entry& e : pins_) {
        auto& slot = ctx.treePins[static_cast<std::size_t>(e.member)];
        if (!e.fired && !slot) slot = e.pin;
    }
}

bool PinGuide::pinNode(const ActionPin& pin, const GroupState& g, int who) {
    const auto& s = g.c[static_cast<std::size_t>(who)];
    return g.time >= pin.time - kPinEarly && g.time <= pin.time + kPinLate && (s.start < pin.time - kPinEarly || s.reacting);
}

std::vector<int> PinGuide::firedCounts(int members) const {
    std::vector<int> counts(static_cast<std::size_t>(members), 0);
    for (const Entry& e : pins_) {
        if (e.fired) ++counts[static_cast<std::size_t>(e.member)];
    }
    return counts;
}

void PinGuide::restoreFired(const std::vector<int>& counts) {
    std::vector<int> left = counts;
    for (Entry& e : pins_) {  // by member, then time: the first ones of each member fired
        int& n = left[static_cast<std::size_t>(e.member)];
        e.fired = n > 0;
        if (n > 0) --n;
    }
}

Status PinGuide::finish(const Context& ctx) const {
    for (const Entry& e : pins_) {
        if (!e.fired) return missed(ctx, e, nullptr);
    }
    return {};
}

}  // namespace fray::sim::planner
