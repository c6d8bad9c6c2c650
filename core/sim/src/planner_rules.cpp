// Tree expansion's rules (SPEC 2.1-2.3): advancing a group from one node to
// the next (hits, forced reactions, catches, checkpoints) and the edge
// scores F_comp and F_coop. The search over them is planner_search.cpp.
#include <algorithm>
#include <cmath>

#include "planner_state.h"

namespace fray::sim::planner {

void updateCheckpoints(const Context& ctx, GroupState& g, double t) {
    for (int i = 0; i < g.n; ++i) {
        const auto& spec = specOf(ctx, i);
        auto& s = g.c[static_cast<std::size_t>(i)];
        if (spec.path.empty()) continue;
        const glm::vec2 p = placement(ctx, s, t).pos;
        for (int guard = 0; guard < static_cast<int>(spec.path.size()); ++guard) {
            if (!spec.loopPath && s.checkpoint >= static_cast<int>(spec.path.size())) break;
            const auto& cp = spec.path[static_cast<std::size_t>(s.checkpoint) % spec.path.size()];
            const bool timeOk = !cp.time || t >= *cp.time;
            if (!timeOk || static_cast<double>(glm::length(p - cp.pos)) > ctx.opt->checkpointRadius) break;
            ++s.checkpoint;
            if (spec.loopPath) s.checkpoint %= static_cast<int>(spec.path.size());
        }
    }
}

void advance(const Context& ctx, GroupState& g, Events& ev, Recorder* rec) {
    double t0 = g.time;
    for (int guard = 0; guard < 64; ++guard) {
        double t1 = g.c[0].end;
        for (int i = 1; i < g.n; ++i) t1 = std::min(t1, g.c[static_cast<std::size_t>(i)].end);
        // Earliest event among all pairs.
        detail::HitCandidate best;
        int bestAtt = -1, bestDef = -1;
        bool isCatch = false;
        for (int a = 0; a < g.n; ++a) {
            const auto& as = g.c[static_cast<std::size_t>(a)];
            for (int d = 0; d < g.n; ++d) {
                if (d == a || !enemies(ctx, a, d)) continue;
                const auto& ds = g.c[static_cast<std::size_t>(d)];
                const auto h = ctx.engine->strike(playing(as), as.attackDone, playing(ds), ds.reacting, t0, t1);
                if (h.before(best)) best = h, bestAtt = a, bestDef = d, isCatch = false;
            }
        }
        for (int a = 0; a < g.n; ++a) {
            const auto& as = g.c[static_cast<std::size_t>(a)];
            if (!specOf(ctx, a).weights.catches || as.caught || specOf(ctx, a).weights.wHitShort <= 0) continue;
            for (int d = 0; d < g.n; ++d) {
                if (d == a || !enemies(ctx, a, d)) continue;
                const double limit = best.time >= 0 ? best.time : t1;
                for (double ts = t0; ts <= limit; ts += kCatchStep) {
                    const glm::vec2 diff = placement(ctx, as, ts).pos - placement(ctx, g.c[static_cast<std::size_t>(d)], ts).pos;
                    if (static_cast<double>(glm::length(diff)) <= ctx.opt->catchRadius) {
                        if (best.time < 0 || ts < best.time) {
                            best = detail::HitCandidate{};
                            best.time = ts;
                            bestAtt = a, bestDef = d, isCatch = true;
                        }
                        break;
                    }
                }
            }
        }
        if (best.time < 0) {
            g.time = t1;
            break;
        }
        auto& att = g.c[static_cast<std::size_t>(bestAtt)];
        auto& def = g.c[static_cast<std::size_t>(bestDef)];
        const double te = best.time;
        if (isCatch) {
            att.caught = true;
            ++ev.catches[static_cast<std::size_t>(bestAtt)];
            ++ev.caught[static_cast<std::size_t>(bestDef)];
            if (rec) {
                rec->scene->catches.push_back({te, rec->global[static_cast<std::size_t>(bestAtt)],
                                               rec->global[static_cast<std::size_t>(bestDef)]});
                if (ctx.opt->stopOnCatch) {
                    rec->stop = true;
                    g.time = te;
                    return;
                }
            }
            t0 = te;
            continue;
        }
        att.attackDone = true;
        const auto& attack = act(ctx, att.action);
        const double impulse = detail::InteractionEngine::impulse(best);
        if (!best.blocked) {
            (attack.is(kKick) ? ev.givenLong : ev.givenShort)[static_cast<std::size_t>(bestAtt)] += best.speed;
            ev.received[static_cast<std::size_t>(bestDef)] += best.speed;
        }
        if (rec) {
            rec->scene->hits.push_back({te, rec->global[static_cast<std::size_t>(bestAtt)],
                                        rec->global[static_cast<std::size_t>(bestDef)], att.action, best.effector,
                                        best.target, best.speed, impulse, best.blocked});
        }
        const auto& member = ctx.members[static_cast<std::size_t>(bestDef)];
        if (!best.blocked && !member.spec->reactions.empty()) {
            const auto reaction = ctx.engine->react(playing(def), placement(ctx, att, te), te, impulse > ctx.opt->fallImpulse, member.pool);
            if (reaction.action >= 0) {
                CharState ns = def;
                ns.action = reaction.action;
                ns.start = te;
                ns.offset = reaction.offset;
                ns.end = reaction.end;
                ns.root = reaction.root;
                ns.attackDone = true;
                ns.caught = false;
                ns.reacting = true;
                pushRecent(ctx, ns, reaction.action);
                if (rec) {
                    detail::cutIntoReaction(rec->scene->characters[static_cast<std::size_t>(rec->global[static_cast<std::size_t>(bestDef)])].track,
                                            te, reaction);
                    ++rec->scene->stats.forced;
                }
                def = ns;
            }
        }
        t0 = te;
    }
    updateCheckpoints(ctx, g, g.time);
}

// F_comp and F_coop of the edge "who launched action" (SPEC 2.3), evaluated
// at the next node with the events of the interval. oppAt: the node's memo of
// the opponent's placement.
Value edgeScore(const Context& ctx, const GroupState& before, const GroupState& after, int who, int action,
                const Events& ev, PlacementMemo& oppAt) {
    const auto& spec = specOf(ctx, who);
    const auto& w = spec.weights;
    // Movement is judged where the launched action leaves the character (its
    // end), against where the opponent's current action leaves it by then:
    // the next node can come a few frames later, before the action has done
    // anything.
    const auto& me = after.c[static_cast<std::size_t>(who)];
    const double t = me.end;
    const RootXf pm = placement(ctx, me, t);
    // Movement and path terms per half second of the launched action
    // (StyleWeights::perSecond), else per edge as in the thesis.
    const double moveScale = w.perSecond ? act(ctx, action).duration / kMovementSeconds : 1.0;
    Value v;
    const int opp = opponentOf(ctx, after, who, after.time);
    if (opp >= 0) {
        const auto& os = after.c[static_cast<std::size_t>(opp)];
        const RootXf po = oppAt(ctx, os, std::min(t, os.end));
        const glm::vec2 d = po.pos - pm.pos;
        const double r = glm::length(d);
        const double theta = r > 1e-6 ? wrapAngle(angleOf(d) - pm.heading) : 0.0;
        v.comp -= moveScale * (w.wTheta * theta * theta + w.wR * (r - w.rD) * (r - w.rD));
        const int oppBefore = opponentOf(ctx, before, who, before.time);
        if (oppBefore >= 0 && ctx.combo) {
            const int theirs = before.c[static_cast<std::size_t>(oppBefore)].action;
            v.comp += w.wCombo * static_cast<double>((*ctx.combo)[static_cast<std::size_t>(action) * static_cast<std::size_t>(ctx.comboN) +
                                              static_cast<std::size_t>(theirs)]);
        }
    }
    // Scoring: the whole team's blows and catches, with this character's weights.
    for (int i = 0; i < after.n; ++i) {
        if (enemies(ctx, who, i)) continue;
        const auto k = static_cast<std::size_t>(i);
        if (w.catches) {
            v.comp += w.wHitShort * ev.catches[k] - w.wDamage * ev.caught[k];
        } else {
            v.comp += w.wHitShort * ev.givenShort[k] + w.wHitLong * ev.givenLong[k] - w.wDamage * ev.received[k];
        }
    }
    v.comp -= w.wRecency * recency(ctx, before.c[static_cast<std::size_t>(who)], action);
    // The stage: ending near or beyond its edge costs like a lost blow per
    // metre squared, so the search turns a runner before the edge, where one
    // clip of look-ahead (the choice filter) is too late for a running turn.
    if (ctx.opt->arena.bounded()) {
        const double out = ctx.opt->arena.distanceFrom(pm.pos) - (ctx.opt->arena.radius - kArenaMargin);
        if (out > 0) v.comp -= kArenaWeight * out * out;
    }
    // Cooperative: checkpoints and required actions.
    if (!spec.path.empty() && (w.wPath > 0 || w.wPsi > 0)) {
        const int k = me.checkpoint;
        if (spec.loopPath || k < static_cast<int>(spec.path.size())) {
            const auto& cp = spec.path[static_cast<std::size_t>(k) % spec.path.size()];
            const glm::vec2 d = cp.pos - pm.pos;
            v.coop -= moveScale * w.wPath * static_cast<double>(glm::dot(d, d));
            if (w.wPsi > 0 && glm::dot(d, d) > 1e-6f) {
                const double psi = wrapAngle(pm.heading - angleOf(d));
                v.coop -= moveScale * w.wPsi * psi * psi;
            }
        }
    }
    if (w.wReq > 0) {
        if (std::binary_search(spec.required.begin(), spec.required.end(), action)) v.coop += w.wReq;
        if (std::binary_search(spec.forbidden.begin(), spec.forbidden.end(), action)) v.coop -= w.wReq;
        const int k = before.c[static_cast<std::size_t>(who)].checkpoint;
        if (!spec.path.empty() && (spec.loopPath || k < static_cast<int>(spec.path.size()))) {
            const auto& cp = spec.path[static_cast<std::size_t>(k) % spec.path.size()];
            if (!cp.action.empty()) {
                const auto& a = act(ctx, action);
                const bool match = cp.action[0] == '@' ? a.has(cp.action.substr(1)) : a.name == cp.action;
                if (match) v.coop += w.wReq;
            }
        }
    }
    return v;
}

}  // namespace fray::sim::planner
