#include "fray/sim/patches.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <tuple>
#include <mutex>
#include <numbers>

#include <tbb/parallel_for.h>

#include "interaction.h"

namespace fray::sim {

namespace {

using detail::Playing;

constexpr double kDegree = std::numbers::pi / 180.0;
constexpr double kStep = 1.0 / kSampleRate;     // s between body tests: every sample of the tracks
constexpr float kShrink = 0.82f;                 // grazing contact is not penetration (a little stricter than the metrics' 0.8)
constexpr double kReachMargin = 0.35;            // m beyond an attack's reach (as the planner)
constexpr double kNearMiss = 0.45;               // m: an attack this close to a defender that avoided it counts
constexpr double kHandsMeet = 0.15;              // m: hands this close in a hand-over meet
constexpr double kHandsSlack = 0.30;             // m: beyond meeting, the contact criterion falls to 0 over this
constexpr double kHandsReach = 0.35;             // m: a hand-over whose hands never come closer is discarded
constexpr double kHitGrace = 0.25;               // s after a blow during which bodies may touch
constexpr int kMaxEntries = 12;
constexpr double kCollisionMass = 10.0;          // kg behind a colliding body segment

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

// ---------------------------------------------------------------------------
// Evaluation (SPEC 4.2): contact, relative distance/orientation, timing.

struct Scores {
    double contact = 1, distance = 1, timing = 1;
};

Playing playingOf(const ActionInstance& i) { return {i.action, i.start, i.offset, i.root}; }

const ActionInstance* instanceAt(const std::vector<ActionInstance>& track, double t) {
    const int i = instanceIndexAt(track, t + 1e-9);
    return i < 0 ? nullptr : &track[static_cast<std::size_t>(i)];
}

RootXf placeAt(const ActionLibrary& lib, const std::vector<ActionInstance>& track, double t) {
    const auto* i = instanceAt(track, t);
    return playingOf(*i).placement(lib, std::min(t, i->end));
}

// The middle of a body's two hands (the far ends of its forearm boxes), where
// an item held in both hands is.
glm::vec3 handsAt(const ActionLibrary& lib, const ActionInstance& inst, double t) {
    const Playing p = playingOf(inst);
    const double at = std::min(t, inst.end);
    glm::vec3 sum(0.0f);
    for (int seg : {kLeftForearm, kRightForearm}) sum += segmentTip(p.box(lib, at, seg), seg);
    return 0.5f * sum;
}

// How close the hands of the two characters come while entry e (a receive)
// plays: the hand-over's contact.
double closestHands(const Engine& eng, const State& s, std::size_t e) {
    const auto& pe = eng.pattern.entries[e];
    const auto& mine = s.tracks[static_cast<std::size_t>(pe.character)];
    const auto& theirs = s.tracks[static_cast<std::size_t>(1 - pe.character)];
    const ActionInstance* recv = instanceAt(mine, s.entryStart[e]);
    double closest = std::numeric_limits<double>::max();
    if (recv == nullptr) return closest;
    for (double t = recv->start; t <= recv->end + 1e-9; t += 1.0 / kSampleRate) {
        const ActionInstance* other = instanceAt(theirs, t);
        if (other == nullptr) continue;
        closest = std::min(closest, static_cast<double>(glm::length(handsAt(eng.lib, *recv, t) - handsAt(eng.lib, *other, t))));
    }
    return closest;
}

Scores evaluate(const Engine& eng, const State& s) {
    const auto& lib = eng.lib;
    Scores sc;
    // Contact: every reactive entry was caused (the engine guarantees it);
    // every defence entry avoided an attack that came close.
    double sum = 0;
    int items = 0;
    for (std::size_t e = 0; e < eng.pattern.entries.size(); ++e) {
        const auto& pe = eng.pattern.entries[e];
        if (isResponse(eng.pattern, e)) {
            sum += 1, ++items;
            continue;
        }
        if (pe.annotation == "receive") {
            // A hand-over: the hands must meet.
            ++items;
            const double closest = closestHands(eng, s, e);
            sum += std::clamp((kHandsMeet + kHandsSlack - closest) / kHandsSlack, 0.0, 1.0);
            continue;
        }
        if (pe.annotation != "defence" && pe.annotation != "avoid" && pe.annotation != "dodge") continue;
        ++items;
        const auto& mine = s.tracks[static_cast<std::size_t>(pe.character)];
        const auto& theirs = s.tracks[static_cast<std::size_t>(1 - pe.character)];
        const double t0 = s.entryStart[e];
        const ActionInstance* def = instanceAt(mine, t0);
        double closest = std::numeric_limits<double>::max();
        for (const auto& att : theirs) {
            const auto& A = lib.actions()[static_cast<std::size_t>(att.action)];
            if (!A.is(kAttack) || A.effector < 0) continue;
            for (int smp = A.activeBegin; smp < A.activeEnd; ++smp) {
                const double t = att.start + smp / kSampleRate - att.offset;
                if (t < def->start || t > def->end || t > att.end) continue;
                const glm::vec3 eff = lib.boxesAt(att.action, smp)[A.effector].placed(att.root).centre;
                for (int target : {kHead, kTorso}) {
                    const glm::vec3 c = playingOf(*def).box(lib, t, target).centre;
                    closest = std::min(closest, static_cast<double>(glm::length(eff - c)));
                }
            }
        }
        sum += std::clamp((kNearMiss + 0.35 - closest) / 0.35, 0.0, 1.0);
    }
    if (items > 0) sc.contact = sum / items;

    // Distance and orientation while both are on their feet, 10 Hz.
    double end = 0;
    for (const auto& t : s.tracks) end = std::max(end, t.back().end);
    double dsum = 0;
    int n = 0;
    for (double t = 0; t <= end; t += 0.1) {
        const RootXf p = placeAt(lib, s.tracks[0], t), q = placeAt(lib, s.tracks[1], t);
        const glm::vec2 d = q.pos - p.pos;
        const double r = glm::length(d);
        const double g = r > 1.5 ? std::exp(-(r - 1.5) * (r - 1.5) / 0.25) : r < 0.4 ? r / 0.4 : 1.0;
        double face = 0;
        int k = 0;
        for (int c = 0; c < 2; ++c) {
            const auto* inst = instanceAt(s.tracks[static_cast<std::size_t>(c)], t);
            if (inst->forced) continue;
            const RootXf me = c == 0 ? p : q;
            const glm::vec2 to = c == 0 ? d : -d;
            face += 0.5 * (1.0 + std::cos(r > 1e-6 ? wrapAngle(angleOf(to) - me.heading) : 0.0)), ++k;
        }
        dsum += k > 0 ? 0.5 * g + 0.5 * face / k : g;
        ++n;
    }
    if (n > 0) sc.distance = dsum / n;

    // Timing: consecutive entries of different characters start close together.
    double tsum = 0;
    int m = 0;
    for (std::size_t e = 1; e < eng.pattern.entries.size(); ++e) {
        if (eng.pattern.entries[e].character == eng.pattern.entries[e - 1].character) continue;
        const double gap = s.entryStart[e] - s.entryStart[e - 1];
        const double over = std::max(0.0, gap - 0.5);
        tsum += std::exp(-over * over / 0.25), ++m;
    }
    if (m > 0) sc.timing = tsum / m;
    return sc;
}

void fillSwept(const ActionLibrary& lib, Patch& p) {
    for (int c = 0; c < 2; ++c) {
        auto& out = p.swept[static_cast<std::size_t>(c)];
        const auto& track = p.tracks[static_cast<std::size_t>(c)];
        const int slices = std::max(1, static_cast<int>(std::ceil(p.duration / kSweptSlice)));
        out.assign(static_cast<std::size_t>(slices), SweptBox{});
        for (int k = 0; k < slices; ++k) {
            SweptBox box = SweptBox::empty();
            for (int j = 0; j <= 3; ++j) {
                const double t = std::min((k + j / 3.0) * kSweptSlice, p.duration);
                const auto* inst = instanceAt(track, t);
                const Playing pl = playingOf(*inst);
                const double tt = std::min(t, inst->end);
                for (int seg = 0; seg < kSegmentCount; ++seg) box.add(floorBox(pl.box(lib, tt, seg)));
            }
            out[static_cast<std::size_t>(k)] = box;
        }
    }
}

Patch makePatch(const Engine& eng, const State& s, int patternIndex, const PatchConfig& ic, const Scores& sc, double score) {
    Patch p;
    p.pattern = patternIndex;
    p.tracks = s.tracks;
    p.hits = s.hits;
    p.initial = ic;
    p.contact = sc.contact, p.distance = sc.distance, p.timing = sc.timing;
    p.score = score;
    for (const auto& t : p.tracks) p.duration = std::max(p.duration, t.back().end);
    const RootXf e0 = p.endPlacement(eng.lib, 0), e1 = p.endPlacement(eng.lib, 1);
    p.final = configOf(e0, e1);
    fillSwept(eng.lib, p);
    return p;
}

State initialState(const PatchConfig& ic) {
    State s;
    const auto places = placeConfig(ic);
    for (int c = 0; c < 2; ++c) {
        auto& x = s.a[static_cast<std::size_t>(c)];
        x.cur.root = places[static_cast<std::size_t>(c)];
    }
    return s;
}

// Starts both characters: character 1 its first entry at 0 (a choice),
// character 2 its first entry at the delay, or a hold when that entry is a reaction.
struct Expansion {
    const Engine& eng;
    int patternIndex;
    PatchConfig ic;
    GenerateStats stats;
    std::vector<Patch> kept;

    void finish(const State& s, Verdict v) {
        ++stats.paths;
        switch (v) {
            case Verdict::TooClose: ++stats.tooClose; return;
            case Verdict::WrongOrder: ++stats.wrongOrder; return;
            case Verdict::UnintendedHit: ++stats.unintendedHit; return;
            case Verdict::MissedContact: ++stats.missedContact; return;
            case Verdict::Ok: break;
        }
        for (std::size_t e = 0; e < eng.pattern.entries.size(); ++e) {
            if (!s.started[e]) {
                ++stats.missedContact;
                return;
            }
        }
        // A hand-over whose hands never come within reach passes nothing.
        for (std::size_t e = 0; e < eng.pattern.entries.size(); ++e) {
            if (eng.pattern.entries[e].annotation == "receive" && closestHands(eng, s, e) > kHandsReach) {
                ++stats.missedContact;
                return;
            }
        }
        const Scores sc = evaluate(eng, s);
        const auto& w = eng.pattern.weights;
        const double total = w.contact + w.distance + w.timing;
        const double score = (w.contact * sc.contact + w.distance * sc.distance + w.timing * sc.timing) / total;
        if (score < eng.pattern.threshold) {
            ++stats.belowThreshold;
            return;
        }
        kept.push_back(makePatch(eng, s, patternIndex, ic, sc, score));
    }

    // Continues from a state where character `who` must choose for its pending entry.
    void expand(const State& s, int who) {
        const int e = eng.pendingEntry(s.a[static_cast<std::size_t>(who)], who);
        std::vector<int> cands;
        eng.candidates(s, who, e, cands);
        if (cands.empty()) {
            ++stats.paths, ++stats.missedContact;
            return;
        }
        for (int a : cands) {
            State next = s;
            const bool first = next.a[static_cast<std::size_t>(who)].last < 0;
            eng.launch(next, who, a, e, next.time, first);
            run(std::move(next));
        }
    }

    void run(State s) {
        Verdict v = Verdict::Ok;
        const int who = eng.advance(s, v);
        if (who >= 0) return expand(s, who);
        finish(s, v);
    }

    void start() {
        State s = initialState(ic);
        const int e1 = eng.entriesOf[1].front();
        const bool reactiveFirst = isResponse(eng.pattern, static_cast<std::size_t>(e1));
        // Character 2 first: a hold from 0, or its first action at the delay
        // (a placeholder until then: the first sample of that action). When
        // its first entry follows another of character 1's than the first, it
        // waits in a guard until that entry starts, then the delay.
        const int e0first = eng.entriesOf[0].front();
        const bool deferred = !reactiveFirst && e1 - 1 != e0first;
        if (reactiveFirst || deferred) {
            if (eng.hold < 0) {
                ++stats.paths, ++stats.missedContact;
                return;
            }
            eng.launch(s, 1, deferred ? eng.holdBefore[static_cast<std::size_t>(e1)] : eng.hold, -1, 0.0, true);
            if (deferred) s.a[1].waitFor = e1 - 1, s.a[1].waitDelay = ic.delay;
        }
        // Character 1 chooses its first action at time 0.
        const int e0 = eng.entriesOf[0].front();
        std::vector<int> c0;
        eng.candidates(s, 0, e0, c0);
        if (c0.empty()) {
            ++stats.paths, ++stats.missedContact;
            return;
        }
        for (int a0 : c0) {
            State s0 = s;
            eng.launch(s0, 0, a0, e0, 0.0, true);
            if (reactiveFirst || deferred) {
                run(std::move(s0));
                continue;
            }
            std::vector<int> c1;
            s0.time = ic.delay;
            eng.candidates(s0, 1, e1, c1);
            s0.time = 0;
            for (int a1 : c1) {
                State s1 = s0;
                eng.launch(s1, 1, a1, e1, ic.delay, true);
                if (!eng.orderOk(s1, e1)) {
                    ++stats.paths, ++stats.wrongOrder;
                    continue;
                }
                run(std::move(s1));
            }
        }
    }
};

// Keeps the best keepPerPath patches of every distinct action sequence (by
// label), in generation order otherwise.
void keepBestPerPath(const ActionLibrary& lib, std::vector<Patch>& patches, int keepPerPath, bool spread, PatchLibrary& out) {
    std::map<std::string, std::vector<std::size_t>> groups;
    for (std::size_t i = 0; i < patches.size(); ++i) {
        std::string key;
        for (const auto& t : patches[i].tracks) {
            for (const auto& inst : t) key += lib.actions()[static_cast<std::size_t>(inst.action)].label() + (inst.forced ? "!" : "") + ",";
            key += "|";
        }
        groups[key].push_back(i);
    }
    std::vector<char> keep(patches.size(), keepPerPath <= 0 ? 1 : 0);
    if (keepPerPath > 0) {
        for (auto& [key, members] : groups) {
            std::stable_sort(members.begin(), members.end(),
                             [&](std::size_t a, std::size_t b) { return patches[a].score > patches[b].score; });
            const auto want = static_cast<std::size_t>(keepPerPath);
            if (!spread || members.size() <= want) {
                for (std::size_t k = 0; k < members.size() && k < want; ++k) keep[members[k]] = 1;
                continue;
            }
            // Farthest first among the near-best, from the best one on.
            std::vector<std::size_t> pool;
            for (std::size_t m : members) {
                if (patches[m].score >= patches[members.front()].score - 0.02) pool.push_back(m);
            }
            auto apart = [&](std::size_t a, std::size_t b) {
                const PatchConfig& x = patches[a].initial;
                const PatchConfig& y = patches[b].initial;
                const double dd = (x.delay - y.delay) / 0.3;
                return configDistance(x, y) + dd * dd;
            };
            std::vector<double> nearest(pool.size(), std::numeric_limits<double>::max());
            std::size_t pick = 0, kept = 0;
            while (kept < want && kept < pool.size()) {
                keep[pool[pick]] = 1;
                ++kept;
                nearest[pick] = -1;
                std::size_t next = pool.size();
                for (std::size_t q = 0; q < pool.size(); ++q) {
                    if (nearest[q] < 0) continue;
                    nearest[q] = std::min(nearest[q], apart(pool[q], pool[pick]));
                    if (next == pool.size() || nearest[q] > nearest[next]) next = q;
                }
                if (next == pool.size()) break;
                pick = next;
            }
            // Fewer near-best than asked for: the best of the rest.
            for (std::size_t m : members) {
                if (kept >= want) break;
                if (!keep[m]) keep[m] = 1, ++kept;
            }
        }
    }
    for (std::size_t i = 0; i < patches.size(); ++i) {
        if (keep[i]) {
            out.patches.push_back(std::move(patches[i]));
            ++out.stats.kept;
        } else {
            ++out.stats.duplicates;
        }
    }
}

std::vector<double> grid(double lo, double hi, double step) {
    std::vector<double> out;
    const int n = static_cast<int>(std::floor((hi - lo) / step + 1e-9));
    for (int i = 0; i <= n; ++i) out.push_back(lo + i * step);
    return out;
}

}  // namespace

// ---------------------------------------------------------------------------

double configDistance(const PatchConfig& a, const PatchConfig& b) {
    constexpr double cr = 0.30, ct = std::numbers::pi;
    const double dr = (a.r - b.r) / cr;
    const double d1 = wrapAngle(a.theta1 - b.theta1) / ct;
    const double d2 = wrapAngle(a.theta2 - b.theta2) / ct;
    return dr * dr + d1 * d1 + d2 * d2;
}

std::array<RootXf, 2> placeConfig(const PatchConfig& c) {
    RootXf a;  // origin, facing +Z
    const glm::vec2 dir = headingVector(c.theta1);
    RootXf b;
    b.pos = dir * static_cast<float>(c.r);
    b.heading = wrapAngle(angleOf(-dir) - c.theta2);
    return {a, b};
}

PatchConfig configOf(const RootXf& a, const RootXf& b) {
    PatchConfig c;
    const glm::vec2 d = b.pos - a.pos;
    c.r = glm::length(d);
    if (c.r < 1e-6) return c;
    c.theta1 = wrapAngle(angleOf(d) - a.heading);
    c.theta2 = wrapAngle(angleOf(-d) - b.heading);
    return c;
}

RootXf Patch::endPlacement(const ActionLibrary& lib, int character) const {
    const auto& last = tracks[static_cast<std::size_t>(character)].back();
    return last.placementAt(lib, last.offset + (last.end - last.start));
}

int PatchLibrary::nearestPose(const PatchConfig& c) const {
    int best = -1;
    double bestD = std::numeric_limits<double>::max();
    for (std::size_t i = 0; i < standardPoses.size(); ++i) {
        const double d = configDistance(c, standardPoses[i]);
        if (d < bestD) bestD = d, best = static_cast<int>(i);
    }
    return best;
}

Status generatePatches(const ActionLibrary& lib, const PatternList& pattern, const PatternSet& set, PatchLibrary& out,
                       const GenerateOptions& options, const ProgressFn& progress) {
    if (pattern.entries.size() > static_cast<std::size_t>(kMaxEntries)) {
        return makeError("pattern '" + pattern.name + "' has more than " + std::to_string(kMaxEntries) + " entries");
    }
    if (auto st = checkPattern(pattern, set, lib); !st) return st;
    const auto wallStart = std::chrono::steady_clock::now();
    const Engine eng(lib, pattern, options);
    if (eng.hold < 0) {
        for (std::size_t e = 0; e < pattern.entries.size(); ++e) {
            if (isResponse(pattern, e)) return makeError("the project has no idle action to wait for a blow in");
        }
    }
    for (std::size_t e = 0; e < pattern.entries.size(); ++e) {
        if (!isResponse(pattern, e) && eng.choices[e].empty()) {
            return makeError("pattern '" + pattern.name + "', entry " + std::to_string(e + 1) + ": no action to choose");
        }
    }
    // The initial-condition grid inside the intersection of the first actions' ranges.
    const auto& f1 = pattern.entries[static_cast<std::size_t>(eng.entriesOf[0].front())];
    const auto& f2 = pattern.entries[static_cast<std::size_t>(eng.entriesOf[1].front())];
    const InitialRange a = set.rangeFor(f1.annotation), b = set.rangeFor(f2.annotation);
    const auto rs = grid(std::max(a.minDistance, b.minDistance), std::min(a.maxDistance, b.maxDistance), options.distanceStep);
    const auto t1s = grid(a.minAngle, a.maxAngle, options.angleStepDegrees);
    const auto t2s = grid(b.minAngle, b.maxAngle, options.angleStepDegrees);
    const auto ds = isResponse(pattern, static_cast<std::size_t>(eng.entriesOf[1].front()))
                        ? std::vector<double>{0.0}
                        : grid(std::max(a.minDelay, b.minDelay), std::min(a.maxDelay, b.maxDelay), options.delayStep);
    std::vector<PatchConfig> ics;
    for (double r : rs)
        for (double t1 : t1s)
            for (double t2 : t2s)
                for (double d : ds) ics.push_back({r, t1 * kDegree, t2 * kDegree, d});
    if (ics.empty()) return makeError("pattern '" + pattern.name + "': the initial-condition grid is empty");

    const int patternIndex = static_cast<int>(out.patterns.size());
    std::vector<Expansion> results;
    results.reserve(ics.size());
    for (const auto& ic : ics) results.push_back(Expansion{eng, patternIndex, ic, {}, {}});
    std::atomic<std::size_t> done{0};
    std::atomic<bool> stop{false};
    std::mutex progressMutex;  // the callback is called from one thread at a time
    auto work = [&](std::size_t i) {
        if (stop.load(std::memory_order_relaxed) || (options.cancel && options.cancel->load())) {
            stop = true;
            return;
        }
        results[i].start();
        const std::size_t n = ++done;
        if (n % 16 != 0) return;
        const std::lock_guard<std::mutex> lock(progressMutex);
        if (!reportProgress(progress, static_cast<double>(n) / static_cast<double>(ics.size()), "patches")) {
            stop = true;
        }
    };
    if (options.parallel) {
        tbb::parallel_for(std::size_t{0}, ics.size(), work);
    } else {
        for (std::size_t i = 0; i < ics.size(); ++i) work(i);
    }
    if (stop.load() || (options.cancel && options.cancel->load())) return makeError("cancelled");
    out.patterns.push_back(pattern);
    std::vector<Patch> candidates;
    for (auto& r : results) {
        out.stats.add(r.stats);
        for (auto& p : r.kept) candidates.push_back(std::move(p));
    }
    keepBestPerPath(lib, candidates, options.keepPerPath >= 0 ? options.keepPerPath : pattern.keepPerPath, pattern.spread, out);
    out.stats.initialConditions += static_cast<std::int64_t>(ics.size());
    out.stats.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count();
    out.libraryKey = libraryFingerprint(lib);
    reportProgress(progress, 1.0, "patches");
    return {};
}

Status addHandMadePatch(const ActionLibrary& lib, const PatternList& pattern, const PatchConfig& initial,
                        const std::array<std::vector<int>, 2>& actions, PatchLibrary& out, const GenerateOptions& options) {
    const Engine eng(lib, pattern, options);
    for (int c = 0; c < 2; ++c) {
        std::size_t k = 0;
        for (int e : eng.entriesOf[static_cast<std::size_t>(c)]) {
            if (isResponse(pattern, static_cast<std::size_t>(e))) continue;
            const auto& list = actions[static_cast<std::size_t>(c)];
            if (k >= list.size()) {
                return makeError("hand-made patch: character " + std::to_string(c + 1) + " needs an action for entry " +
                                 std::to_string(e + 1) + " (" + eng.entry(e).annotation + ")");
            }
            const int a = list[k++];
            if (a < 0 || a >= lib.size()) return makeError("hand-made patch: action index " + std::to_string(a) + " is out of range");
            if (!matchesAnnotation(lib.actions()[static_cast<std::size_t>(a)], eng.entry(e).annotation)) {
                return makeError("hand-made patch: " + lib.actions()[static_cast<std::size_t>(a)].label() + " is not '" +
                                 eng.entry(e).annotation + "' (entry " + std::to_string(e + 1) + ")");
            }
        }
    }
    // Play the given choices through the engine: a one-path tree.
    std::array<std::size_t, 2> next{};
    const int patternIndex = static_cast<int>(out.patterns.size());
    State s = initialState(initial);
    const int e1 = eng.entriesOf[1].front();
    auto take = [&](int c) { return actions[static_cast<std::size_t>(c)][next[static_cast<std::size_t>(c)]++]; };
    eng.launch(s, 0, take(0), eng.entriesOf[0].front(), 0.0, true);
    if (isResponse(pattern, static_cast<std::size_t>(e1))) {
        eng.launch(s, 1, eng.hold, -1, 0.0, true);
    } else if (e1 - 1 != eng.entriesOf[0].front()) {
        if (eng.hold < 0) return makeError("hand-made patch: the project has no idle action to wait in");
        eng.launch(s, 1, eng.holdBefore[static_cast<std::size_t>(e1)], -1, 0.0, true);
        s.a[1].waitFor = e1 - 1, s.a[1].waitDelay = initial.delay;
    } else {
        eng.launch(s, 1, take(1), e1, initial.delay, true);
    }
    Verdict v = Verdict::Ok;
    for (int who = eng.advance(s, v); who >= 0; who = eng.advance(s, v)) {
        const int e = eng.pendingEntry(s.a[static_cast<std::size_t>(who)], who);
        eng.launch(s, who, take(who), e, s.time, false);
    }
    const char* why = v == Verdict::TooClose ? "the characters' bodies overlap"
                      : v == Verdict::WrongOrder ? "the actions do not start in the pattern's order"
                      : v == Verdict::UnintendedHit ? "a blow lands where the pattern has none"
                      : v == Verdict::MissedContact ? "a reaction in the pattern is never caused by a blow"
                                                    : nullptr;
    if (why) return makeError(std::string("hand-made patch: ") + why);
    const Scores sc = evaluate(eng, s);
    const auto& w = pattern.weights;
    const double score = (w.contact * sc.contact + w.distance * sc.distance + w.timing * sc.timing) /
                         (w.contact + w.distance + w.timing);
    Patch p = makePatch(eng, s, patternIndex, initial, sc, score);
    p.handMade = true;
    out.patterns.push_back(pattern);
    out.patches.push_back(std::move(p));
    out.libraryKey = libraryFingerprint(lib);
    return {};
}

std::uint64_t libraryFingerprint(const ActionLibrary& lib) {
    std::uint64_t h = 1469598103934665603ull;
    auto mix = [&](std::uint64_t v) {
        h ^= v;
        h *= 1099511628211ull;
    };
    for (const auto& a : lib.actions()) {
        for (char ch : a.motionId) mix(static_cast<unsigned char>(ch));
        mix(static_cast<std::uint64_t>(a.firstFrame));
        mix(static_cast<std::uint64_t>(a.lastFrame));
        mix(a.flags);
    }
    return h;
}

}  // namespace fray::sim
