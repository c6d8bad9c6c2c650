// Tree expansion's rules (SPEC 2.1-2.3): advancing a group from one node to
// the next (hits, forced reactions, catches, checkpoints) and the edge
// scores F_comp and F_coop. The search over them is planner_search.cpp.
#include <algorithm>
#include <cmath>
#include <limits>

#include "planner_state.h"

namespace fray::sim::planner {

// How much more a metre off the path costs than a metre behind the schedule
// along it (docs/TREE_EXPANSION.md "Following a path"): along the path the
// schedule moves on while a blow or a knock-down keeps the character in
// place, so some lateness is unavoidable and is made up afterwards, whereas
// nothing forces it off the path; at 1 the search cut corners (the chord of a
// circle) to make up lateness and missed checkpoints by 0.7 m.
constexpr double kOffPath = 3.0;

PathPlan makePathPlan(const CharacterSpec& spec) {
    PathPlan plan;
    if (spec.path.empty() || !(spec.weights.wPath > 0) || spec.loopPath) return plan;
    plan.active = true;
    plan.knotTime.push_back(0.0);
    plan.knotAlong.push_back(0.0);
    double along = 0;
    for (std::size_t k = 0; k < spec.path.size(); ++k) {
        const auto& cp = spec.path[k];
        if (k > 0) along += static_cast<double>(glm::length(cp.pos - spec.path[k - 1].pos));
        plan.points.push_back(cp.pos);
        plan.along.push_back(along);
        if (cp.time) {
            plan.knotTime.push_back(std::max(*cp.time, plan.knotTime.back()));
            plan.knotAlong.push_back(along);
        }
    }
    // Beyond the last timed checkpoint the rest of the path at the pace of
    // the last leg, not all at once: a goal that jumps to the end the moment
    // the last time comes drew the search across the chord of a circle,
    // past the last checkpoint, in the actions before it.
    const std::size_t n = plan.knotTime.size();
    if (n >= 2 && plan.knotAlong.back() < along) {
        const double dt = plan.knotTime[n - 1] - plan.knotTime[n - 2], ds = plan.knotAlong[n - 1] - plan.knotAlong[n - 2];
        if (dt > 0 && ds > 0) {
            plan.knotTime.push_back(plan.knotTime.back() + (along - plan.knotAlong.back()) * dt / ds);
            plan.knotAlong.push_back(along);
        }
    }
    return plan;
}

double PathPlan::goal(double t) const {
    // Between two timed checkpoints (or the start and the first): as far as
    // the time elapsed; after the last one the end of the path (checkpoints
    // without a time: whenever, so the sooner the better).
    if (t >= knotTime.back()) return along.back();
    const auto j = static_cast<std::size_t>(std::upper_bound(knotTime.begin(), knotTime.end(), t) - knotTime.begin());
    const double t0 = knotTime[j - 1], t1 = knotTime[j];
    const double u = t1 > t0 ? (t - t0) / (t1 - t0) : 1.0;
    return knotAlong[j - 1] + u * (knotAlong[j] - knotAlong[j - 1]);
}

void PathPlan::project(glm::vec2 p, int next, double& s, double& lateral) const {
    const int n = static_cast<int>(points.size());
    s = 0;
    lateral = static_cast<double>(glm::length(p - points[0]));
    if (n < 2) return;
    // The segments around the next checkpoint only: a closed or crossing
    // path passes near the same floor twice.
    const int k = std::clamp(next, 0, n - 1);
    float best = std::numeric_limits<float>::max();
    for (int j = std::max(0, k - 2); j <= std::min(n - 2, k + 2); ++j) {
        const glm::vec2 a = points[static_cast<std::size_t>(j)], b = points[static_cast<std::size_t>(j) + 1];
        const glm::vec2 ab = b - a;
        const float len2 = glm::dot(ab, ab);
        const float u = len2 > 1e-12f ? std::clamp(glm::dot(p - a, ab) / len2, 0.0f, 1.0f) : 0.0f;
        const glm::vec2 d = p - (a + u * ab);
        const float dd = glm::dot(d, d);
        if (dd < best) {
            best = dd;
            s = along[static_cast<std::size_t>(j)] + static_cast<double>(u) * (along[static_cast<std::size_t>(j) + 1] - along[static_cast<std::size_t>(j)]);
            lateral = std::sqrt(static_cast<double>(dd));
        }
    }
}

void updateCheckpoints(const Context& ctx, GroupState& g, double t) {
    for (int i = 0; i < g.n; ++i) {
        const auto& spec = specOf(ctx, i);
        auto& s = g.c[static_cast<std::size_t>(i)];
        if (spec.path.empty()) continue;
        const glm::vec2 p = placement(ctx, s, t).pos;
        // Following a path (PathPlan): a checkpoint without an action is
        // also passed once the character is beyond it along the path (a
        // timed one once its time has come too), so one missed by a little
        // more than the radius does not hold the schedule's projection.
        const auto& plan = ctx.members[static_cast<std::size_t>(i)].path;
        double along = -1, lateral = 0;
        if (plan.active) plan.project(p, s.checkpoint, along, lateral);
        for (int guard = 0; guard < static_cast<int>(spec.path.size()); ++guard) {
            if (!spec.loopPath && s.checkpoint >= static_cast<int>(spec.path.size())) break;
            const auto& cp = spec.path[static_cast<std::size_t>(s.checkpoint) % spec.path.size()];
            const bool timeOk = !cp.time || t >= *cp.time;
            const bool passed = plan.active && cp.action.empty() &&
                                along >= plan.along[static_cast<std::size_t>(s.checkpoint)];
            if (!timeOk || (!passed && static_cast<double>(glm::length(p - cp.pos)) > ctx.opt->checkpointRadius)) break;
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
    const auto& plan = ctx.members[static_cast<std::size_t>(who)].path;
    if (plan.active) {
        // Following a path (docs/TREE_EXPANSION.md): how far the character is
        // from where the schedule wants it by then, along the path and off it,
        // as a change over the edge (where the action ends against where it
        // starts), so a branch's sum is where it ends, however many actions
        // it took to get there.
        const auto offSchedule = [&](const CharState& c, glm::vec2 p, double at) {
            double along = 0, lateral = 0;
            plan.project(p, c.checkpoint, along, lateral);
            const double behind = plan.goal(at) - along;
            const double off = kOffPath * lateral;
            return behind * behind + off * off;
        };
        const auto& was = before.c[static_cast<std::size_t>(who)];
        const glm::vec2 wasAt = placement(ctx, was, before.time).pos;
        v.coop -= w.wPath * (offSchedule(me, pm.pos, t) - offSchedule(was, wasAt, before.time));
        // A fighting pair goes round together: beyond fighting distance (its
        // preferred distance or its reach, whichever is longer) the gap to
        // the opponent costs like distance from the schedule. Cooperative,
        // so the opponent's search, which counts this character's path term
        // too (SPEC 2.2), gains by keeping up instead of standing off while
        // the movement terms cancel out.
        const int oppBefore = opponentOf(ctx, before, who, before.time);
        if (opp >= 0 && oppBefore >= 0) {
            const double reach = std::max(w.rD, w.attackRange);
            const auto apart = [&](glm::vec2 a, glm::vec2 b) {
                const double gap = std::max(0.0, static_cast<double>(glm::length(a - b)) - reach);
                return gap * gap;
            };
            const auto& os = after.c[static_cast<std::size_t>(opp)];
            const glm::vec2 oppNow = oppAt(ctx, os, std::min(t, os.end)).pos;
            const glm::vec2 oppWas = placement(ctx, before.c[static_cast<std::size_t>(oppBefore)], before.time).pos;
            v.coop -= w.wPath * (apart(pm.pos, oppNow) - apart(wasAt, oppWas));
        }
        const int k = me.checkpoint;
        if (w.wPsi > 0 && k < static_cast<int>(spec.path.size())) {
            const glm::vec2 d = spec.path[static_cast<std::size_t>(k)].pos - pm.pos;
            if (glm::dot(d, d) > 1e-6f) {
                const double psi = wrapAngle(pm.heading - angleOf(d));
                v.coop -= moveScale * w.wPsi * psi * psi;
            }
        }
    } else if (!spec.path.empty() && (w.wPath > 0 || w.wPsi > 0)) {
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
