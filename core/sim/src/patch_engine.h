#pragma once
// Interaction Patch generation's engine (SPEC 4.2): two characters playing a
// PatternList, one action each at a time, the blows and forced reactions
// through the interaction engine, and the verdict on a path. Internal to
// fray_sim (patches.cpp).
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <tuple>
#include <vector>

#include "fray/sim/patches.h"
#include "interaction.h"

namespace fray::sim::patchgen {

using detail::Playing;

inline constexpr double kDegree = std::numbers::pi / 180.0;
inline constexpr double kStep = 1.0 / kSampleRate;     // s between body tests: every sample of the tracks
inline constexpr float kShrink = 0.82f;                 // grazing contact is not penetration (a little stricter than the metrics' 0.8)
inline constexpr double kReachMargin = 0.35;            // m beyond an attack's reach (as the planner)
inline constexpr double kNearMiss = 0.45;               // m: an attack this close to a defender that avoided it counts
inline constexpr double kHandsMeet = 0.15;              // m: hands this close in a hand-over meet
inline constexpr double kHandsSlack = 0.30;             // m: beyond meeting, the contact criterion falls to 0 over this
inline constexpr double kHandsReach = 0.35;             // m: a hand-over whose hands never come closer is discarded
inline constexpr double kHitGrace = 0.25;               // s after a blow during which bodies may touch
inline constexpr int kMaxEntries = 12;
inline constexpr double kCollisionMass = 10.0;          // kg behind a colliding body segment

// ---------------------------------------------------------------------------
// The engine: two characters playing a pattern, one action each at a time.

struct Actor {
    Playing cur;
    double end = 0;
    int entry = -1;        // pattern entry of the current action; -1: waiting (hold) or not started
    int pos = 0;           // next position in this character's entry list
    int last = -1;         // last action launched (motion-graph continuity)
    bool attackDone = false, reacting = false, finished = false;
    double reactUntil = -1;  // bodies may touch until then (just after a blow)
    // Character 2 whose first entry comes after several of character 1's
    // (luggage: receive after hand) waits in a guard until entry waitFor has
    // started, then waitDelay more.
    int waitFor = -1;
    double waitDelay = 0;
};

struct State {
    double time = 0;
    std::array<Actor, 2> a;
    std::array<std::vector<ActionInstance>, 2> tracks;
    std::vector<HitEvent> hits;
    std::array<double, kMaxEntries> entryStart{};
    std::array<bool, kMaxEntries> started{};
};

enum class Verdict { Ok, TooClose, WrongOrder, UnintendedHit, MissedContact };

struct Engine {
    const ActionLibrary& lib;
    const PatternList& pattern;
    const GenerateOptions& opt;
    detail::InteractionEngine rules;                // hits and forced reactions
    std::array<std::vector<int>, 2> entriesOf;     // per character: its entry indices in order
    std::vector<std::vector<int>> choices;         // per entry: candidate actions (representatives)
    std::vector<int> pools;                        // per entry: its reactive pool in `rules`
    int hold = -1;                                 // idle action played while waiting for a blow
    std::vector<int> holdBefore;                   // per entry: the idle to wait in before it (motion-graph continuity)

    Engine(const ActionLibrary& l, const PatternList& p, const GenerateOptions& o) : lib(l), pattern(p), opt(o), rules(l) {
        choices.resize(p.entries.size());
        std::vector<std::vector<int>> pool(p.entries.size());  // per entry: reactive clips (ascending)
        for (std::size_t e = 0; e < p.entries.size(); ++e) {
            const auto& pe = p.entries[e];
            entriesOf[static_cast<std::size_t>(pe.character)].push_back(static_cast<int>(e));
            // (variant class, start node, end node) -> first action. The end node
            // only counts for run steps: it is the foot the step ends on, and
            // which cut can follow depends on it.
            std::map<std::tuple<int, int, int>, int> reps;
            for (int i = 0; i < lib.size(); ++i) {
                const auto& act = lib.actions()[static_cast<std::size_t>(i)];
                if (!matchesAnnotation(act, pe.annotation)) continue;
                if (isResponse(p, e)) {
                    pool[e].push_back(i);
                    continue;
                }
                if (isReactiveAnnotation(pe.annotation)) {
                    // Already falling (domino): every clip, so a chain can
                    // continue from whichever reaction the last blow chose.
                    choices[e].push_back(i);
                    continue;
                }
                reps.emplace(std::make_tuple(lib.variantClass()[static_cast<std::size_t>(i)], lib.startNode()[static_cast<std::size_t>(i)],
                                             act.is(kRun) ? lib.endNode()[static_cast<std::size_t>(i)] : -1),
                             i);
            }
            pools.push_back(rules.addPool(pool[e]));
            for (const auto& [key, i] : reps) choices[e].push_back(i);
            std::sort(choices[e].begin(), choices[e].end());
            if (opt.maxChoicesPerEntry > 0 && static_cast<int>(choices[e].size()) > opt.maxChoicesPerEntry) {
                // Evenly spread over the list so every kind stays represented.
                std::vector<int> kept;
                const std::size_t n = choices[e].size(), k = static_cast<std::size_t>(opt.maxChoicesPerEntry);
                for (std::size_t j = 0; j < k; ++j) kept.push_back(choices[e][j * n / k]);
                choices[e] = kept;
            }
        }
        double best = -1;
        for (int i = 0; i < lib.size(); ++i) {
            const auto& act = lib.actions()[static_cast<std::size_t>(i)];
            if (act.is(kIdle) && act.duration > best) best = act.duration, hold = i;
        }
        // Before a chosen entry, the idle most of its choices can follow.
        holdBefore.assign(p.entries.size(), hold);
        for (std::size_t e = 0; e < p.entries.size(); ++e) {
            int bestCount = 0;
            double bestLength = -1;
            for (int i = 0; i < lib.size(); ++i) {
                const auto& idle = lib.actions()[static_cast<std::size_t>(i)];
                if (!idle.is(kIdle)) continue;
                int count = 0;
                for (int a : choices[e]) count += lib.continuesInto(i, a) ? 1 : 0;
                if (count > bestCount || (count == bestCount && count > 0 && idle.duration > bestLength)) {
                    bestCount = count, bestLength = idle.duration, holdBefore[e] = i;
                }
            }
        }
    }

    const LibraryAction& act(int a) const { return lib.actions()[static_cast<std::size_t>(a)]; }
    const PatternEntry& entry(int e) const { return pattern.entries[static_cast<std::size_t>(e)]; }
    int pendingEntry(const Actor& x, int c) const {
        const auto& list = entriesOf[static_cast<std::size_t>(c)];
        return x.pos < static_cast<int>(list.size()) ? list[static_cast<std::size_t>(x.pos)] : -1;
    }

    // Starts an action for character c at time t where its current one leaves it.
    void launch(State& s, int c, int action, int entryIndex, double t, bool first) const {
        auto& x = s.a[static_cast<std::size_t>(c)];
        // Where the current action leaves the character: its end, or where it
        // is now when the action was cut short (a guard left early).
        const bool cut = !first && x.end < x.cur.start - x.cur.offset + act(x.cur.action).duration - 1e-6;
        const RootXf root = first ? x.cur.root : cut ? x.cur.placement(lib, t) : x.cur.root * act(x.cur.action).end;
        x.cur = {action, t, 0.0, root};
        x.end = t + act(action).duration;
        x.entry = entryIndex;
        x.attackDone = false;
        // Character 1 starting in a fall (domino) pushes whoever its body hits.
        x.reacting = entryIndex == 0 && isReactiveAnnotation(entry(0).annotation);
        x.last = action;
        s.tracks[static_cast<std::size_t>(c)].push_back({action, t, 0.0, x.end, root, false, false});
        if (entryIndex >= 0) {
            s.entryStart[static_cast<std::size_t>(entryIndex)] = t;
            s.started[static_cast<std::size_t>(entryIndex)] = true;
            ++x.pos;
        }
    }

    bool orderOk(const State& s, int entryIndex) const {
        for (int i = 0; i < entryIndex; ++i) {
            if (!s.started[static_cast<std::size_t>(i)]) return false;
        }
        return true;
    }

    // Candidate actions for character c's next entry at time t (motion-graph
    // continuity; attacks only within reach of the other, roughly in front).
    void candidates(const State& s, int c, int e, std::vector<int>& out) const {
        out.clear();
        const auto& x = s.a[static_cast<std::size_t>(c)];
        const auto& y = s.a[static_cast<std::size_t>(1 - c)];
        const RootXf here = x.last >= 0 ? x.cur.root * act(x.cur.action).end : x.cur.root;
        const RootXf there = y.cur.placement(lib, s.time);
        const glm::vec2 d = there.pos - here.pos;
        const double r = glm::length(d);
        const double bearing = r > 1e-6 ? std::fabs(wrapAngle(angleOf(d) - here.heading)) : 0.0;
        for (int a : choices[static_cast<std::size_t>(e)]) {
            if (x.last >= 0 && !lib.continuesInto(x.last, a)) continue;
            const auto& A = act(a);
            if (A.is(kAttack) && (r > A.reach + kReachMargin || bearing > 60 * kDegree)) continue;
            out.push_back(a);
        }
    }

    bool corePenetrates(const State& s, double t) const {
        return detail::coreBodiesOverlap(lib, detail::bodyAt(s.a[0].cur, t), detail::bodyAt(s.a[1].cur, t), kShrink);
    }

    // A reacting character's body segment hitting the other fast enough to push it.
    detail::HitCandidate findCollision(const State& s, int c, double t0, double t1) const {
        detail::HitCandidate hit;
        const auto& x = s.a[static_cast<std::size_t>(c)];
        const auto& y = s.a[static_cast<std::size_t>(1 - c)];
        for (double t = t0; t <= t1 + 1e-9; t += kStep) {
            const glm::vec2 d = x.cur.placement(lib, t).pos - y.cur.placement(lib, t).pos;
            if (glm::dot(d, d) > 1.6f * 1.6f) continue;
            for (int seg : {kTorso, kPelvis, kHead}) {
                const Obb now = x.cur.box(lib, t, seg);
                const Obb before = x.cur.box(lib, t - kStep, seg);
                const double speed = static_cast<double>(glm::length(now.centre - before.centre)) / kStep;
                if (speed < opt.collisionSpeed) continue;
                for (int target : kCoreSegments) {
                    if (!overlaps(now, y.cur.box(lib, t, target))) continue;
                    hit.time = t, hit.effector = seg, hit.target = target, hit.speed = speed;
                    return hit;
                }
            }
        }
        return hit;
    }

    // Plays until the next moment a character needs a choice (returned) or
    // the patch ends (-1). Sets verdict when the path is invalid.
    int advance(State& s, Verdict& verdict) const {
        for (int guard = 0; guard < 64; ++guard) {
            double t1 = std::numeric_limits<double>::max();
            for (const auto& x : s.a) {
                if (!x.finished) t1 = std::min(t1, x.end);
                if (x.waitFor >= 0 && s.started[static_cast<std::size_t>(x.waitFor)]) {
                    t1 = std::min(t1, std::max(s.time, s.entryStart[static_cast<std::size_t>(x.waitFor)] + x.waitDelay));
                }
            }
            if (t1 == std::numeric_limits<double>::max()) return -1;
            // Earliest blow or collision in (time, t1].
            detail::HitCandidate best;
            int att = -1;
            bool collision = false;
            for (int c = 0; c < 2; ++c) {
                const auto& x = s.a[static_cast<std::size_t>(c)];
                const auto& y = s.a[static_cast<std::size_t>(1 - c)];
                if (y.reacting) continue;
                // Only a pattern entry's attack lands (not a guard played while waiting).
                if (const auto h = rules.strike(x.cur, x.attackDone || x.entry < 0, y.cur, y.reacting, s.time, t1); h.before(best)) {
                    best = h, att = c, collision = false;
                }
                if (x.reacting && !x.attackDone) {
                    const auto h = findCollision(s, c, s.time, best.time >= 0 ? best.time : t1);
                    if (h.before(best)) best = h, att = c, collision = true;
                }
            }
            const double until = best.time >= 0 ? best.time : t1;
            for (double t = s.time; t <= until + 1e-9; t += kStep) {
                // Bodies may touch only right after a blow (the metrics' intended-contact window).
                const bool grace = t < s.a[0].reactUntil || t < s.a[1].reactUntil;
                if (!grace && corePenetrates(s, t)) {
                    verdict = Verdict::TooClose;
                    return -1;
                }
            }
            if (best.time < 0) {
                s.time = t1;
                // A waiting character whose moment has come leaves its guard now.
                for (int c = 0; c < 2; ++c) {
                    auto& x = s.a[static_cast<std::size_t>(c)];
                    if (x.waitFor < 0 || !s.started[static_cast<std::size_t>(x.waitFor)] ||
                        s.entryStart[static_cast<std::size_t>(x.waitFor)] + x.waitDelay > t1 + 1e-9) {
                        continue;
                    }
                    x.waitFor = -1;
                    x.end = t1;
                    s.tracks[static_cast<std::size_t>(c)].back().end = t1;
                    const int e = pendingEntry(x, c);
                    if (!orderOk(s, e)) {
                        verdict = Verdict::WrongOrder;
                        return -1;
                    }
                    return c;
                }
                // Whoever ends now: the next entry (a choice, a hold, or the end).
                for (int c = 0; c < 2; ++c) {
                    auto& x = s.a[static_cast<std::size_t>(c)];
                    if (x.finished || x.end > t1 + 1e-9) continue;
                    if (x.waitFor >= 0) {  // still waiting: another guard
                        launch(s, c, x.cur.action, -1, t1, false);
                        continue;
                    }
                    const int e = pendingEntry(x, c);
                    if (e < 0) {
                        x.finished = true;
                        continue;
                    }
                    if (isResponse(pattern, static_cast<std::size_t>(e))) {
                        if (x.entry < 0 && x.cur.action == hold && x.last == hold) {
                            verdict = Verdict::MissedContact;  // waited a whole hold for a blow that never came
                            return -1;
                        }
                        launch(s, c, hold, -1, t1, false);
                        continue;
                    }
                    if (!orderOk(s, e)) {
                        verdict = Verdict::WrongOrder;
                        return -1;
                    }
                    return c;
                }
                continue;
            }
            // A blow or a collision at best.time.
            auto& x = s.a[static_cast<std::size_t>(att)];
            auto& y = s.a[static_cast<std::size_t>(1 - att)];
            const double te = best.time;
            s.time = te;
            x.attackDone = true;
            const double impulse = collision ? best.speed * kCollisionMass : detail::InteractionEngine::impulse(best);
            s.hits.push_back({te, att, 1 - att, x.cur.action, best.effector, best.target, best.speed, impulse, best.blocked});
            if (best.blocked) {
                x.reactUntil = y.reactUntil = te + kHitGrace;
                continue;
            }
            const int e = pendingEntry(y, 1 - att);
            const bool avoiding = y.entry >= 0 && (act(y.cur.action).has("avoid") || act(y.cur.action).has("dodge"));
            if (e < 0 || !isResponse(pattern, static_cast<std::size_t>(e)) || avoiding) {
                verdict = Verdict::UnintendedHit;
                return -1;
            }
            if (!orderOk(s, e)) {
                verdict = Verdict::WrongOrder;
                return -1;
            }
            const auto reaction = rules.react(y.cur, x.cur.placement(lib, te), te, impulse > opt.fallImpulse,
                                              pools[static_cast<std::size_t>(e)]);
            if (reaction.action < 0) {
                verdict = Verdict::MissedContact;
                return -1;
            }
            detail::cutIntoReaction(s.tracks[static_cast<std::size_t>(1 - att)], te, reaction);
            y.cur = {reaction.action, te, reaction.offset, reaction.root};
            y.end = reaction.end;
            y.entry = e;
            y.last = reaction.action;
            y.reacting = true;
            y.attackDone = false;  // a falling body can push in turn
            x.reactUntil = y.reactUntil = te + kHitGrace;
            ++y.pos;
            s.entryStart[static_cast<std::size_t>(e)] = te;
            s.started[static_cast<std::size_t>(e)] = true;
        }
        verdict = Verdict::MissedContact;  // too many events: not a clean interaction
        return -1;
    }
};

}  // namespace fray::sim::patchgen
