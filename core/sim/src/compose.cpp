#include "fray/sim/compose.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <random>
#include <set>
#include <tuple>

#include <tbb/parallel_for.h>

#include "fray/prep/json_reader.h"
#include "interaction.h"

namespace fray::sim {

namespace {

using json = nlohmann::ordered_json;

constexpr double kArriveDistance = 0.25;          // m: locomotion is done this close to its target
constexpr double kArriveHeading = 25 * std::numbers::pi / 180;
constexpr int kMaxLocomotionSteps = 60;
constexpr float kClearance = 0.2f;               // m between a new patch's newcomer and anyone present

// ---------------------------------------------------------------------------
// Building the timeline.

struct Composer {
    const ActionLibrary& lib;
    const PatchLibrary& patches;
    const ComposeSpec& spec;
    ComposeStats& stats;
    Scene scene;
    std::vector<int> locomotion;   // representatives of walk/run/step/turn actions
    int hold = -1;                 // idle action for waiting
    std::vector<double> usage;     // f_p per patch
    std::vector<char> allowed;     // per patch: its pattern is in the spec
    // Walkers keep this far (m) from other bodies' boxes; the luggage chain,
    // where porters stand close, relies on the body test (penetrates) instead.
    float nearDistance = 0.45f;
    // Characters whose track has ended stand where it stopped (the luggage
    // porters wait in place between hand-overs) rather than being absent.
    bool standWhenDone = false;
    std::mt19937_64 rng;

    Composer(const ActionLibrary& l, const PatchLibrary& p, const ComposeSpec& s, ComposeStats& st)
        : lib(l), patches(p), spec(s), stats(st), rng(s.seed) {
        std::map<std::pair<int, int>, int> reps;
        double best = -1;
        for (int i = 0; i < lib.size(); ++i) {
            const auto& a = lib.actions[static_cast<std::size_t>(i)];
            if (a.is(kIdle) && a.duration > best) best = a.duration, hold = i;
            if (!a.is(kWalk | kStep | kTurn | kRun) || a.has("carry") || a.is(kReactive) || a.is(kAttack)) continue;
            reps.emplace(std::make_pair(lib.variantClass[static_cast<std::size_t>(i)], lib.startNode[static_cast<std::size_t>(i)]), i);
        }
        for (const auto& [key, i] : reps) locomotion.push_back(i);
        usage.assign(patches.patches.size(), 0.0);
        allowed.assign(patches.patches.size(), 1);
        if (!spec.patterns.empty()) {
            for (std::size_t i = 0; i < patches.patches.size(); ++i) {
                const auto& name = patches.patterns[static_cast<std::size_t>(patches.patches[i].pattern)].name;
                allowed[i] = std::find(spec.patterns.begin(), spec.patterns.end(), name) != spec.patterns.end();
            }
        }
    }

    const LibraryAction& act(int a) const { return lib.actions[static_cast<std::size_t>(a)]; }

    int addCharacter(std::string name, int side) {
        SceneCharacter c;
        c.name = std::move(name);
        c.side = side;
        c.preset = "patches";
        scene.characters.push_back(std::move(c));
        return static_cast<int>(scene.characters.size()) - 1;
    }
    std::vector<ActionInstance>& track(int c) { return scene.characters[static_cast<std::size_t>(c)].track; }

    // Where a character's last action leaves it, and when.
    RootXf leaves(int c) const {
        const auto& t = scene.characters[static_cast<std::size_t>(c)].track;
        const auto& i = t.back();
        const double natural = i.start + act(i.action).duration - i.offset;
        if (i.end < natural - 1e-6) return i.placementAt(lib, i.offset + (i.end - i.start));
        return i.root * act(i.action).end;
    }
    double freeAt(int c) const { return scene.characters[static_cast<std::size_t>(c)].track.back().end; }

    void append(int c, int action, double start, const RootXf& root, double offset = 0, double end = -1, bool forced = false) {
        ActionInstance inst{action, start, offset, end >= 0 ? end : start + act(action).duration - offset, root, forced, false};
        track(c).push_back(inst);
    }

    // Idles in place from the character's free time until t.
    void waitUntil(int c, double t) {
        while (freeAt(c) < t - 1e-6) {
            const double from = freeAt(c);
            const RootXf at = leaves(c);
            const int idle = idleAfter(track(c).back().action);
            const double end = std::min(t, from + act(idle).duration);
            append(c, idle, from, at * lib.rootAt(idle, 0).inverse(), 0, end);
        }
    }

    // The idle that continues an action in the motion graph (the longest such),
    // else the general guard: a porter waits standing, a boxer in guard.
    int idleAfter(int action) const {
        int best = -1;
        for (int i = 0; i < lib.size(); ++i) {
            if (!act(i).is(kIdle) || lib.startNode[static_cast<std::size_t>(i)] != lib.endNode[static_cast<std::size_t>(action)]) continue;
            if (best < 0 || act(i).duration > act(best).duration) best = i;
        }
        return best >= 0 ? best : hold;
    }

    // The instance character c plays at time t (its track must not be empty).
    const ActionInstance& playingAt(int c, double t) const {
        return scene.characters[static_cast<std::size_t>(c)].track[static_cast<std::size_t>(scene.instanceAt(c, t))];
    }

    // Floor rectangle around character c's whole body at time t.
    SweptBox bodyBox(int c, double t) const {
        const auto& inst = playingAt(c, t);
        const Obb* boxes = lib.boxesAt(inst.action, lib.sampleAt(inst.action, inst.clipTimeAt(t)));
        SweptBox out = SweptBox::empty();
        for (int seg = 0; seg < kSegmentCount; ++seg) out.add(floorBox(boxes[seg].placed(inst.root)));
        return out;
    }
    static float rectDistance(const SweptBox& r, const glm::vec2& p) {
        const glm::vec2 d = glm::max(glm::max(r.lo - p, p - r.hi), glm::vec2(0.0f));
        return glm::length(d);
    }
    // Someone (other than self and partner) is closer than nearDistance to p at time t.
    bool occupied(int self, int partner, const glm::vec2& p, double t) const {
        for (int c = 0; c < static_cast<int>(scene.characters.size()); ++c) {
            if (c == self || c == partner || scene.characters[static_cast<std::size_t>(c)].track.empty()) continue;
            if (rectDistance(bodyBox(c, t), p) < nearDistance) return true;
        }
        return false;
    }

    // Stepping from `from` to p at time t would come too close to someone
    // (walking away from someone already close is allowed).
    bool blocked(int self, int partner, const glm::vec2& from, const glm::vec2& p, double t) const {
        for (int c = 0; c < static_cast<int>(scene.characters.size()); ++c) {
            if (c == self || c == partner || scene.characters[static_cast<std::size_t>(c)].track.empty()) continue;
            const SweptBox box = bodyBox(c, t);
            const float dn = rectDistance(box, p);
            if (dn < nearDistance && dn < rectDistance(box, from) - 1e-3f) return true;
        }
        if (partner >= 0) {
            // The one it is walking up to: no closer than touching distance.
            const SweptBox box = bodyBox(partner, t);
            const float dn = rectDistance(box, p);
            if (dn < 0.15f && dn < rectDistance(box, from) - 1e-3f) return true;
        }
        return false;
    }

    // Would a planned list of actions for character `self` put its body inside
    // anyone else's (the metrics' test, at every 30 Hz sample)?
    bool penetrates(const std::vector<ActionInstance>& walk, int self) const {
        constexpr float kShrink = 0.82f;
        for (const auto& w : walk) {
            auto touches = [&](double t) {
                const detail::BodyPose me{w.action, w.offset + (t - w.start), w.root};
                for (int c = 0; c < static_cast<int>(scene.characters.size()); ++c) {
                    if (c == self) continue;
                    detail::BodyPose other;
                    if (standWhenDone && !track0(c).empty() && t > track0(c).back().end) {
                        // Waiting where its track stopped, as waitUntil will
                        // have it: the idle that follows, looped from there.
                        // (Tested first: a track that has ended is still
                        // present, held at its last frame.)
                        const auto& last = track0(c).back();
                        const int idle = idleAfter(last.action);
                        const RootXf at = leaves(c);
                        other = {idle, std::fmod(t - last.end, act(idle).duration), at * lib.rootAt(idle, 0).inverse()};
                    } else if (scene.present(c, t)) {
                        const auto& inst = playingAt(c, t);
                        other = {inst.action, inst.clipTimeAt(t), inst.root};
                    } else {
                        continue;
                    }
                    if (detail::coreBodiesOverlap(lib, me, other, kShrink)) return true;
                }
                return false;
            };
            for (double t = w.start; t <= w.end + 1e-9; t += 1.0 / kSampleRate) {
                if (touches(t)) return true;
            }
        }
        return false;
    }

    // Greedy collision-free locomotion (SPEC 4.4) from a placement at t0 to a
    // target. Appends the actions to `out` (times from t0); returns where and when it ends.
    std::pair<RootXf, double> locomote(int self, int partner, RootXf at, double t0, int last, const RootXf& target, double timeShift,
                                       std::vector<ActionInstance>& out) {
        double t = t0;
        auto cost = [&](const RootXf& p) {
            const glm::vec2 d = target.pos - p.pos;
            const double dist = static_cast<double>(glm::length(d));
            const double facing = dist > 1.0 ? std::fabs(wrapAngle(angleOf(d) - p.heading)) : std::fabs(wrapAngle(target.heading - p.heading));
            return dist + 0.3 * facing;
        };
        for (int step = 0; step < kMaxLocomotionSteps; ++step) {
            const double dist = static_cast<double>(glm::length(target.pos - at.pos));
            if (dist < kArriveDistance && std::fabs(wrapAngle(target.heading - at.heading)) < kArriveHeading) break;
            const double now = cost(at);
            int best = -1;
            double bestCost = now - 0.02;
            for (int a : locomotion) {
                const auto& A = act(a);
                const RootXf end = at * A.end;
                const RootXf mid = at * lib.rootAt(a, 0.5 * A.duration);
                double c = cost(end);
                if (last >= 0 && lib.startNode[static_cast<std::size_t>(a)] != lib.endNode[static_cast<std::size_t>(last)]) c += 0.05;
                if (c >= bestCost) continue;
                if (!blocked(self, partner, at.pos, mid.pos, t + 0.5 * A.duration + timeShift) &&
                    !blocked(self, partner, at.pos, end.pos, t + A.duration + timeShift)) {
                    best = a, bestCost = c;
                }
            }
            if (best < 0) break;
            out.push_back({best, t, 0.0, t + act(best).duration, at, false, false});
            at = at * act(best).end;
            t += act(best).duration;
            last = best;
        }
        return {at, t};
    }

    // Places patch p's character `role` as scene character c, the patch starting at t
    // in the frame xf; appends its actions and the hits of that character as attacker.
    static std::vector<ActionInstance> placed(const Patch& p, int role, double t, const RootXf& xf) {
        std::vector<ActionInstance> out;
        for (const auto& inst : p.tracks[static_cast<std::size_t>(role)]) {
            ActionInstance w = inst;
            w.start += t, w.end += t;
            w.root = xf * inst.root;
            out.push_back(w);
        }
        return out;
    }
    void placeTrack(const Patch& p, int role, int c, double t, const RootXf& xf) {
        for (const auto& w : placed(p, role, t, xf)) track(c).push_back(w);
    }
    void placeHits(const Patch& p, const std::array<int, 2>& who, double t) {
        for (auto h : p.hits) {
            h.time += t;
            h.attacker = who[static_cast<std::size_t>(h.attacker)];
            h.defender = who[static_cast<std::size_t>(h.defender)];
            scene.hits.push_back(h);
        }
    }

    void used(std::size_t chosen) {
        for (auto& f : usage) f *= 0.9;
        usage[chosen] += 1.0;
        ++stats.patchesUsed;
    }

    // s_u(p): the main character's actions in p carry the annotation the user asks for at t.
    double userPreference(const Patch& p, int role, double t) const {
        const UserCommand* cmd = nullptr;
        for (const auto& c : spec.commands) {
            if (c.time <= t) cmd = &c;
        }
        if (!cmd) return 0;
        for (const auto& inst : p.tracks[static_cast<std::size_t>(role)]) {
            if (matchesAnnotation(act(inst.action), cmd->annotation)) return 1;
        }
        return 0;
    }

    double score(std::size_t i, double density, double user) {
        const double jitter = std::uniform_real_distribution<double>(0.0, 1e-3)(rng);
        return spec.wDensity / (spec.densityScale * density + 1.0) + spec.wUsage * (1.0 - std::min(usage[i], 1.0)) +
               spec.wUser * user + jitter;
    }

    // The newcomer of patch p enters from outside along the radial direction
    // through its start (or up to 90 degrees off it when the way is blocked)
    // and arrives there exactly when its part begins. Returns the walk, or
    // nothing when no entry gets within kMaxJunction of the start.
    std::optional<std::vector<ActionInstance>> planEntry(int c, int partner, const Patch& p, int role, double t, const RootXf& xf,
                                                         const glm::vec2& centre) {
        constexpr double kMaxJunction = 0.3;
        const auto& first = p.tracks[static_cast<std::size_t>(role)].front();
        const RootXf goal = xf * first.root;
        glm::vec2 radial = goal.pos - centre;
        if (glm::length(radial) < 1e-3f) radial = -headingVector(goal.heading);
        radial = glm::normalize(radial);
        const double arrive = t + first.start;
        for (double turn : {0.0, 0.5, -0.5, 1.0, -1.0, 1.5, -1.5}) {
            const glm::vec2 dir = rotateFloor(radial, turn);
            RootXf start;
            start.pos = goal.pos + dir * static_cast<float>(spec.entryRadius);
            start.heading = angleOf(-dir);
            // Plan to learn how long the walk takes, then again with the
            // timing that makes it end on time (others move meanwhile), until
            // the plan keeps its length.
            std::vector<ActionInstance> walk;
            double timeShift = arrive - spec.entryRadius / 1.2;
            RootXf end;
            double when = 0;
            bool settled = false;
            for (int pass = 0; pass < 4 && !settled; ++pass) {
                if (occupied(c, partner, start.pos, timeShift)) break;  // someone stands at the entry
                walk.clear();
                std::tie(end, when) = locomote(c, partner, start, 0.0, -1, goal, timeShift, walk);
                const double next = arrive - when;
                settled = std::fabs(next - timeShift) < 1e-9;
                timeShift = next;
            }
            if (!settled) continue;
            const double error = static_cast<double>(glm::length(end.pos - goal.pos));
            if (error > kMaxJunction) continue;
            const double shift = timeShift;
            std::vector<ActionInstance> out;
            for (auto& w : walk) {
                w.start += shift, w.end += shift;
                if (w.end <= 0) continue;  // walked before the scene starts: it enters already under way
                if (w.start < 0) w.offset = -w.start, w.start = 0;
                out.push_back(w);
            }
            if (penetrates(out, c)) continue;
            stats.maxJunctionError = std::max(stats.maxJunctionError, error);
            stats.locomotionSteps += static_cast<int>(out.size());
            return out;
        }
        return std::nullopt;
    }

    // Where everyone but `ignore` is, from t on: their bodies now and where
    // they end up (those who fell stay down).
    std::vector<SweptBox> obstacles(double t, int ignore) const {
        std::vector<SweptBox> out;
        for (int c = 0; c < static_cast<int>(scene.characters.size()); ++c) {
            if (c == ignore || scene.characters[static_cast<std::size_t>(c)].track.empty()) continue;
            SweptBox a = bodyBox(c, t);
            const SweptBox b = bodyBox(c, std::max(t, freeAt(c)));
            a.lo = glm::min(a.lo, b.lo), a.hi = glm::max(a.hi, b.hi);
            out.push_back(a);
        }
        return out;
    }

    // A patch placed by xf would touch one of the obstacles (both characters' swept boxes).
    static bool collides(const Patch& p, const RootXf& xf, const std::vector<SweptBox>& obstacles) {
        for (int r = 0; r < 2; ++r) {
            for (const auto& s : p.swept[static_cast<std::size_t>(r)]) {
                const glm::vec2 c0 = xf.apply((s.lo + s.hi) * 0.5f);
                const glm::vec2 h = (s.hi - s.lo) * 0.5f;
                const float e = std::max(h.x, h.y);
                const SweptBox w{c0 - glm::vec2(e), c0 + glm::vec2(e)};
                for (const auto& o : obstacles) {
                    if (w.overlaps(o, kClearance)) return true;
                }
            }
        }
        return false;
    }

    // Characters standing within 2.5 m of p at time t (d_p of SPEC 4.4).
    int densityAround(const glm::vec2& p, double t) const {
        int n = 0;
        for (int c = 0; c < static_cast<int>(scene.characters.size()); ++c) {
            if (scene.characters[static_cast<std::size_t>(c)].track.empty()) continue;
            const auto& inst = playingAt(c, t);
            n += glm::length(inst.placementAt(lib, inst.clipTimeAt(t)).pos - p) < 2.5f ? 1 : 0;
        }
        return n;
    }

    // ---- one vs many: the main character meets the enemies one after another.
    Status oneVsMany(const ProgressFn& progress) {
        const int mainC = addCharacter("main", 0);
        append(mainC, hold, 0.0, RootXf{}, 0, 1.0);
        int prev = -1;
        int moves = 0;
        for (int k = 0; k < spec.enemies; ++k) {
            const double t0 = freeAt(mainC);
            if (t0 >= spec.duration) break;
            const RootXf at = leaves(mainC);
            const int lastMain = track(mainC).back().action;
            // Candidates: temporal links where the main character continues, else any (recycling).
            std::vector<std::size_t> cands;
            if (prev >= 0) {
                for (const auto& l : patches.temporal[static_cast<std::size_t>(prev)]) {
                    if (l.shared == 0 && l.roles == 0 && allowed[static_cast<std::size_t>(l.to)]) cands.push_back(static_cast<std::size_t>(l.to));
                }
            }
            const bool linked = !cands.empty();
            if (!linked) {
                for (std::size_t i = 0; i < patches.patches.size(); ++i) {
                    if (allowed[i] && patches.patches[i].tracks[0].front().start == 0.0) cands.push_back(i);
                }
            }
            // The main character may first take one locomotion step (turn,
            // step) so the patch fits beside those already down.
            struct Option {
                double score;
                std::size_t patch;
                int move;
            };
            std::vector<Option> options;
            std::vector<int> moves0 = {-1};
            moves0.insert(moves0.end(), locomotion.begin(), locomotion.end());
            const auto obstacleBoxes = obstacles(t0, mainC);
            for (int mv : moves0) {
                RootXf from = at;
                double tm = t0;
                if (mv >= 0) {
                    from = at * act(mv).end;
                    tm = t0 + act(mv).duration;
                    if (blocked(mainC, -1, at.pos, from.pos, tm) ||
                        blocked(mainC, -1, at.pos, (at * lib.rootAt(mv, 0.5 * act(mv).duration)).pos, t0) ||
                        penetrates({ActionInstance{mv, t0, 0.0, tm, at, false, false}}, mainC)) {
                        continue;
                    }
                }
                const int lastA = mv >= 0 ? mv : lastMain;
                for (std::size_t i : cands) {
                    const Patch& p = patches.patches[i];
                    const RootXf xf = from * p.tracks[0].front().root.inverse();
                    if (collides(p, xf, obstacleBoxes)) continue;
                    const double s = score(i, densityAround(xf.apply(p.tracks[1].front().root.pos), tm), userPreference(p, 0, tm)) +
                                     (lib.startNode[static_cast<std::size_t>(p.tracks[0].front().action)] ==
                                              lib.endNode[static_cast<std::size_t>(lastA)] ? 1.0 : 0.0) -
                                     (mv >= 0 ? 5.0 : 0.0);
                    options.push_back({s, i, mv});
                }
            }
            std::stable_sort(options.begin(), options.end(), [](const Option& x, const Option& y) { return x.score > y.score; });
            // The best option whose newcomer can walk in.
            int bestI = -1, bestMove = -1;
            std::vector<ActionInstance> entry;
            const int enemy = addCharacter("enemy-" + std::to_string(k + 1), 1);
            for (std::size_t o = 0; o < options.size() && o < 40 && bestI < 0; ++o) {
                const Patch& p = patches.patches[options[o].patch];
                const int mv = options[o].move;
                const RootXf from = mv >= 0 ? at * act(mv).end : at;
                const double t = mv >= 0 ? t0 + act(mv).duration : t0;
                const RootXf xf = from * p.tracks[0].front().root.inverse();
                if (auto walk = planEntry(enemy, mainC, p, 1, t, xf, from.pos)) {
                    bestI = static_cast<int>(options[o].patch), bestMove = mv, entry = std::move(*walk);
                }
            }
            if (bestI < 0) scene.characters.pop_back();
            if (bestI < 0) {
                // Crowded: the main character walks into open space and tries again.
                if (++moves > 8) return makeError("one-vs-many: no patch fits around the main character at " + std::to_string(t0) + " s");
                // Candidate spots around, best first: most room, then nearest the scene centre.
                const auto boxes = obstacles(t0, mainC);
                std::vector<std::pair<double, RootXf>> spots;
                for (float dist : {2.5f, 4.0f, 6.0f}) {
                    for (int dir = 0; dir < 12; ++dir) {
                        RootXf goal;
                        goal.heading = wrapAngle(at.heading + dir * std::numbers::pi / 6);
                        goal.pos = at.pos + headingVector(goal.heading) * dist;
                        float room = 10.0f;
                        for (const auto& o : boxes) room = std::min(room, rectDistance(o, goal.pos));
                        if (room < 2.0f) continue;
                        spots.push_back({-static_cast<double>(std::min(room, 3.0f)) + 0.2 * static_cast<double>(glm::length(goal.pos)), goal});
                    }
                }
                std::stable_sort(spots.begin(), spots.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
                std::vector<ActionInstance> walk;
                for (const auto& [rank, goal] : spots) {
                    walk.clear();
                    locomote(mainC, -1, at, t0, lastMain, goal, 0.0, walk);
                    if (!walk.empty() && !penetrates(walk, mainC)) break;
                    walk.clear();
                }
                if (walk.empty()) return makeError("one-vs-many: the main character is boxed in at " + std::to_string(t0) + " s");
                for (auto& w : walk) track(mainC).push_back(w);
                stats.locomotionSteps += static_cast<int>(walk.size());
                --k;
                continue;
            }
            moves = 0;
            (linked ? stats.temporalLinks : stats.recycled) += 1;
            const Patch& p = patches.patches[static_cast<std::size_t>(bestI)];
            RootXf from = at;
            double t = t0;
            if (bestMove >= 0) {
                append(mainC, bestMove, t, at);
                ++stats.locomotionSteps;
                from = leaves(mainC);
                t = freeAt(mainC);
            }
            const RootXf xf = from * p.tracks[0].front().root.inverse();
            for (auto& w : entry) track(enemy).push_back(w);
            placeTrack(p, 0, mainC, t, xf);
            placeTrack(p, 1, enemy, t, xf);
            placeHits(p, {mainC, enemy}, t);
            used(static_cast<std::size_t>(bestI));
            prev = bestI;
            if (!reportProgress(progress, static_cast<double>(k + 1) / spec.enemies, "compose")) return makeError("cancelled");
        }
        return {};
    }

    // ---- American football (SPEC 4.5): the carrier runs for the goal line
    // (+Z, spec.goal m out) in the direction the user sets over time; tacklers
    // dive at it one after another from patches of {run, TACKLE, avoid}.
    double wantedHeading(double t) const {
        double h = 0;
        for (const auto& d : spec.directions) {
            if (d.time <= t + 1e-9) h = d.heading;
        }
        return h;
    }

    // The run step that continues `last` and keeps closest to heading `want`
    // (any run when none continues: a dead end of the graph).
    int nextRun(int last, const RootXf& at, double want) const {
        int best = -1;
        double bestErr = 0;
        for (int pass = 0; pass < 2 && best < 0; ++pass) {
            for (int a : locomotion) {
                if (!act(a).is(kRun) || (pass == 0 && last >= 0 && !lib.continuesInto(last, a))) continue;
                const double err = std::fabs(wrapAngle(want - (at * act(a).end).heading));
                if (best < 0 || err < bestErr - 1e-9) best = a, bestErr = err;
            }
        }
        return best;
    }

    // The tackler's run-up, planned backward from its first patch action
    // (placed at `at`, starting at scene time t): the straightest, longest run
    // steps that lead into it, until it starts entryRadius away; or from a
    // stand when the capture started the run from one. Before time 0 it is
    // already under way.
    std::vector<ActionInstance> runUp(int first, const RootXf& at, double t) const {
        std::vector<ActionInstance> rev;
        int cur = first;
        RootXf root = at;
        double start = t;
        while (start > 1e-9 && static_cast<double>(glm::length(root.pos - at.pos)) < spec.entryRadius && rev.size() < 64) {
            int best = -1;
            double bestKey = 0;
            for (int q = 0; q < lib.size(); ++q) {
                const auto& Q = act(q);
                const bool cut = Q.is(kAvoid) && !Q.is(kAttack);  // a running cut is a run step too
                if (!(Q.is(kRun | kIdle) || cut) || Q.is(kAttack) || !lib.continuesInto(q, cur)) continue;
                // Running first (a cut if nothing else leads on), then straightest, then the longest stride.
                const double key = (Q.is(kRun) ? 0.0 : cut ? 500.0 : 1000.0) + std::round(std::fabs(Q.end.heading) / 0.05) * 10.0 -
                                   static_cast<double>(glm::length(Q.end.pos));
                if (best < 0 || key < bestKey - 1e-9) best = q, bestKey = key;
            }
            if (best < 0) break;
            root = root * act(best).end.inverse();
            const double s0 = start - act(best).duration;
            rev.push_back({best, s0, 0.0, start, root, false, false});
            cur = best;
            start = s0;
            if (act(best).is(kIdle)) break;  // it stood there until it set off
        }
        std::vector<ActionInstance> out;
        for (auto it = rev.rbegin(); it != rev.rend(); ++it) {
            ActionInstance w = *it;
            if (w.end <= 0) continue;
            if (w.start < 0) w.offset = -w.start, w.start = 0;
            out.push_back(w);
        }
        return out;
    }

    // A second tackler at once (SPEC 4.3 spatial concatenation, the thesis'
    // own example): a patch whose carrier plays the very same run and cut as
    // patch `a` (placed by xf at scene time t) from its start, its tackler
    // never meeting a's. Returns whether one came in.
    bool secondTackler(std::size_t a, double t, const RootXf& xf, int number) {
        const Patch& pa = patches.patches[a];
        const int carrier = 0;
        for (const auto& l : patches.spatial[a]) {
            const Patch& pb = patches.patches[static_cast<std::size_t>(l.to)];
            if (l.sharedA != 0 || l.sharedB != 0 || !allowed[static_cast<std::size_t>(l.to)] || pb.tracks[1].empty() ||
                !act(pb.tracks[1].front().action).is(kTackle)) {
                continue;
            }
            // The shared run must cover all of b's carrier (the carrier plays a's).
            const auto offset = static_cast<double>(l.offset);
            std::size_t j = 0;
            while (j < pa.tracks[0].size() && std::fabs(pa.tracks[0][j].start - offset - pb.tracks[0].front().start) > 1e-4) ++j;
            if (j == pa.tracks[0].size() || pa.tracks[0].size() - j < pb.tracks[0].size()) continue;
            const RootXf xb = xf * pa.tracks[0][j].root * pb.tracks[0].front().root.inverse();
            const double tb = t + offset;
            const auto& dive = pb.tracks[1].front();
            const int tackler = addCharacter("tackler-" + std::to_string(number), 1);
            auto walk = runUp(dive.action, xb * dive.root, tb + dive.start);
            bool ok = !(walk.empty() && tb + dive.start > 1e-9) && !penetrates(walk, tackler);
            if (ok) {
                const auto part = placed(pb, 1, tb, xb);
                ok = !penetrates(part, tackler);
                if (ok) {
                    for (auto& w : walk) track(tackler).push_back(w);
                    for (const auto& w : part) track(tackler).push_back(w);
                }
            }
            if (!ok) {
                scene.characters.pop_back();
                continue;
            }
            placeHits(pb, {carrier, tackler}, tb);
            stats.locomotionSteps += static_cast<int>(walk.size());
            ++stats.secondTacklers;
            stats.tacklersPassed += pb.hits.empty() ? 1 : 0;
            used(static_cast<std::size_t>(l.to));
            getUpAndStand(tackler);
            return true;
        }
        return false;
    }

    // A tackler gets up where it landed (the capture's own continuation) and stays.
    void getUpAndStand(int tackler) {
        const int down = track(tackler).back().action;
        for (int n : lib.next[static_cast<std::size_t>(down)]) {
            if (!act(n).is(kTransition)) continue;
            append(tackler, n, freeAt(tackler), leaves(tackler));
            break;
        }
        append(tackler, idleAfter(track(tackler).back().action), freeAt(tackler), leaves(tackler));
    }

    Status football(const ProgressFn& progress) {
        bool any = false;
        for (std::size_t i = 0; i < patches.patches.size() && !any; ++i) {
            const auto& p = patches.patches[i];
            any = allowed[i] && !p.tracks[1].empty() && act(p.tracks[1].front().action).is(kTackle);
        }
        if (!any) {
            return makeError("football: no tackle patch in the library (a PatternList like {run, TACKLE, avoid} on a project "
                             "with tackles, e.g. fray-cli demo-library DIR --set football)");
        }
        const int carrier = addCharacter("carrier", 0);
        {
            const RootXf at{{0.0f, 0.0f}, wantedHeading(0)};
            const int first = nextRun(-1, at, at.heading);
            if (first < 0) return makeError("football: the project has no run action for the carrier");
            append(carrier, first, 0.0, at);
        }
        constexpr int kMinLead = 2;   // run steps between two tackles
        constexpr int kMaxLead = 8;
        constexpr double kLeadCost = 300;  // per extra run step before a tackle
        auto forward = [](const RootXf& x) { return static_cast<double>(x.pos.y); };
        auto runStep = [&](std::vector<ActionInstance>& out, RootXf& at, double& t, int& last) {
            const int a = nextRun(last, at, wantedHeading(t));
            out.push_back({a, t, 0.0, t + act(a).duration, at, false, false});
            at = at * act(a).end;
            t += act(a).duration;
            last = a;
        };
        for (int k = 0; k < spec.tacklers; ++k) {
            if (freeAt(carrier) >= spec.duration || forward(leaves(carrier)) >= spec.goal) break;
            // The carrier's run for up to kMaxLead steps; after each (from the
            // kMinLead-th on) every tackle patch whose run continues it.
            struct Option {
                double score;
                std::size_t patch;
                int lead;
            };
            std::vector<Option> options;
            std::vector<ActionInstance> lead;
            RootXf at = leaves(carrier);
            double t = freeAt(carrier);
            int last = track(carrier).back().action;
            for (int n = 1; n <= kMaxLead; ++n) {
                runStep(lead, at, t, last);
                // The carrier runs round nobody: a step into someone (a tackler
                // still getting up) ends the run here.
                if (penetrates({lead.back()}, carrier)) {
                    lead.pop_back();
                    break;
                }
                if (n < kMinLead || forward(at) >= spec.goal) continue;
                const double want = wantedHeading(t);
                const auto boxes = obstacles(t, carrier);
                for (std::size_t i = 0; i < patches.patches.size(); ++i) {
                    const Patch& p = patches.patches[i];
                    if (!allowed[i] || p.tracks[0].front().start != 0.0 || p.tracks[1].empty()) continue;
                    if (!act(p.tracks[1].front().action).is(kTackle)) continue;
                    if (!lib.continuesInto(last, p.tracks[0].front().action)) continue;
                    const RootXf xf = at * p.tracks[0].front().root.inverse();
                    if (collides(p, xf, boxes)) continue;
                    // s_u: the carrier leaves the patch running the way the user points.
                    const double err = std::fabs(wrapAngle(want - (xf * p.endPlacement(lib, 0)).heading));
                    const double user = 1.0 - err / std::numbers::pi;
                    options.push_back({score(i, densityAround(xf.apply(p.tracks[1].front().root.pos), t), user) - kLeadCost * (n - kMinLead), i, n});
                }
            }
            std::stable_sort(options.begin(), options.end(), [](const Option& x, const Option& y) { return x.score > y.score; });
            const int tackler = addCharacter("tackler-" + std::to_string(k + 1), 1);
            const std::size_t base = track(carrier).size();
            bool placed = false;
            struct Placed {
                std::size_t patch = 0;
                double time = 0;
                RootXf xf;
            } chosen;
            for (std::size_t o = 0; o < options.size() && o < 60 && !placed; ++o) {
                const Option& op = options[o];
                track(carrier).resize(base);
                for (int n = 0; n < op.lead; ++n) track(carrier).push_back(lead[static_cast<std::size_t>(n)]);
                const Patch& p = patches.patches[op.patch];
                const double tp = freeAt(carrier);
                const RootXf xf = leaves(carrier) * p.tracks[0].front().root.inverse();
                const auto& dive = p.tracks[1].front();
                auto walk = runUp(dive.action, xf * dive.root, tp + dive.start);
                if (walk.empty() && tp + dive.start > 1e-9) continue;  // nothing leads into this tackle
                if (penetrates(walk, tackler)) continue;
                for (auto& w : walk) track(tackler).push_back(w);
                placeTrack(p, 1, tackler, tp, xf);
                placeTrack(p, 0, carrier, tp, xf);
                placeHits(p, {carrier, tackler}, tp);
                stats.locomotionSteps += static_cast<int>(walk.size()) + op.lead;
                ++stats.graphJoined;
                stats.tacklersPassed += p.hits.empty() ? 1 : 0;
                used(op.patch);
                placed = true;
                chosen = {op.patch, tp, xf};
            }
            if (!placed) {
                // Nobody can come in here: run on and try again further up the field.
                scene.characters.pop_back();
                track(carrier).resize(base);
                if (lead.empty()) {  // boxed in: the step is taken anyway (the metrics will show it)
                    RootXf a0 = leaves(carrier);
                    double t0 = freeAt(carrier);
                    int l0 = track(carrier).back().action;
                    runStep(lead, a0, t0, l0);
                }
                for (const auto& w : lead) track(carrier).push_back(w);
                stats.locomotionSteps += static_cast<int>(lead.size());
                --k;
                if (track(carrier).size() > 2000) return makeError("football: no tackle fits along the carrier's run");
                continue;
            }
            getUpAndStand(tackler);
            if (spec.doubles && k + 1 < spec.tacklers && secondTackler(chosen.patch, chosen.time, chosen.xf, k + 2)) ++k;
            if (!reportProgress(progress, static_cast<double>(k + 1) / spec.tacklers, "compose")) return makeError("cancelled");
        }
        // Then on to the goal line.
        for (int guard = 0; guard < 400 && forward(leaves(carrier)) < spec.goal + 1.0 && freeAt(carrier) < spec.duration; ++guard) {
            std::vector<ActionInstance> one;
            RootXf at = leaves(carrier);
            double t = freeAt(carrier);
            int last = track(carrier).back().action;
            runStep(one, at, t, last);
            track(carrier).push_back(one.front());
            ++stats.locomotionSteps;
        }
        // The floor marks: the goal line across the run, and the user's arrows
        // where the carrier was when each one was set.
        float lo = 0.0f, hi = 0.0f;
        for (const auto& inst : track(carrier)) {
            const float x = inst.root.pos.x;
            lo = std::min(lo, x), hi = std::max(hi, x);
        }
        const auto goal = static_cast<float>(spec.goal);
        scene.marks.push_back({"goal", {glm::vec2(lo - 8.0f, goal), glm::vec2(hi + 8.0f, goal)}});
        for (const auto& d : spec.directions) {
            const auto& i = track(carrier)[static_cast<std::size_t>(scene.instanceAt(carrier, d.time))];
            const glm::vec2 at = i.placementAt(lib, i.clipTimeAt(d.time)).pos;
            const glm::vec2 dir = headingVector(d.heading);
            const glm::vec2 tail = at + dir * 1.0f, tip = at + dir * 4.0f;
            scene.marks.push_back({"arrow", {tail, tip, tip - rotateFloor(dir, 0.5) * 0.8f, tip, tip - rotateFloor(dir, -0.5) * 0.8f}});
        }
        for (const auto& inst : track(carrier)) {
            const double into = inst.clipTimeAt(inst.end);
            for (double tau = inst.offset; tau <= into + 1e-9; tau += 1.0 / kSampleRate) {
                if (forward(inst.placementAt(lib, tau)) >= spec.goal) {
                    stats.goalReached = inst.start + (tau - inst.offset);
                    return {};
                }
            }
        }
        return {};
    }

    // ---- one vs one: two characters fight on, patch after patch.
    Status oneVsOne(const ProgressFn& progress) {
        const std::array<int, 2> who = {addCharacter("a", 0), addCharacter("b", 1)};
        int prev = -1;
        std::array<int, 2> roleOf = {0, 1};  // scene character -> role in the previous patch
        while (true) {
            const double ta = freeAt0(who[0]), tb = freeAt0(who[1]);
            const double t = std::max(ta, tb);
            if (prev >= 0 && t >= spec.duration) break;
            struct Choice {
                std::size_t patch;
                int roles;  // 0: a plays character 1
            };
            std::vector<Choice> cands;
            if (prev >= 0) {
                for (const auto& l : patches.temporal[static_cast<std::size_t>(prev)]) {
                    if (l.shared == -1 && allowed[static_cast<std::size_t>(l.to)]) {
                        // a's role in prev maps through the link's roles.
                        const int aRole = roleOf[0] ^ l.roles;
                        cands.push_back({static_cast<std::size_t>(l.to), aRole});
                    }
                }
            }
            const bool linked = !cands.empty();
            if (!linked) {
                // Recycling: patches starting from the standard pose nearest to where the two are now.
                PatchConfig now{};
                if (prev >= 0) now = configOf(leaves(who[0]), leaves(who[1]));
                for (int roles = 0; roles < 2; ++roles) {
                    const PatchConfig c = roles ? PatchConfig{now.r, now.theta2, now.theta1, 0} : now;
                    const int pose = prev >= 0 ? nearestStartingPose(c) : -1;
                    for (std::size_t i = 0; i < patches.patches.size(); ++i) {
                        if (!allowed[i]) continue;
                        if (pose >= 0 && patches.initialPose[i] != pose) continue;
                        cands.push_back({i, roles});
                    }
                }
            }
            if (cands.empty()) return makeError("one-vs-one: no patch can follow at " + std::to_string(t) + " s");
            int best = -1;
            double bestS = -std::numeric_limits<double>::max();
            for (std::size_t k = 0; k < cands.size(); ++k) {
                const auto& c = cands[k];
                const double s = score(c.patch, 0, userPreference(patches.patches[c.patch], c.roles, t));
                if (s > bestS) bestS = s, best = static_cast<int>(k);
            }
            const Choice ch = cands[static_cast<std::size_t>(best)];
            const Patch& p = patches.patches[ch.patch];
            (linked ? stats.temporalLinks : stats.recycled) += 1;
            // Scene character of each role.
            const std::array<int, 2> sc = ch.roles == 0 ? who : std::array<int, 2>{who[1], who[0]};
            double start = t;
            RootXf xf;
            if (prev < 0) {
                xf = RootXf{};
            } else {
                // The later character anchors the patch; the earlier walks into
                // place (one step usually) and both wait for each other.
                const int anchorRole = freeAt(sc[0]) >= freeAt(sc[1]) ? 0 : 1;
                const int anchor = sc[static_cast<std::size_t>(anchorRole)];
                const int mover = sc[static_cast<std::size_t>(1 - anchorRole)];
                xf = leaves(anchor) * p.tracks[static_cast<std::size_t>(anchorRole)].front().root.inverse();
                const RootXf goal = xf * p.tracks[static_cast<std::size_t>(1 - anchorRole)].front().root;
                std::vector<ActionInstance> walk;
                auto [end, when] = locomote(mover, anchor, leaves(mover), freeAt(mover), track(mover).back().action, goal, 0.0, walk);
                for (auto& w : walk) track(mover).push_back(w);
                stats.locomotionSteps += static_cast<int>(walk.size());
                stats.maxJunctionError = std::max(stats.maxJunctionError, static_cast<double>(glm::length(end.pos - goal.pos)));
                start = std::max(freeAt(anchor) - p.tracks[static_cast<std::size_t>(anchorRole)].front().start,
                                 when - p.tracks[static_cast<std::size_t>(1 - anchorRole)].front().start);
            }
            for (int r = 0; r < 2; ++r) {
                const int c = sc[static_cast<std::size_t>(r)];
                if (!track(c).empty()) waitUntil(c, start + p.tracks[static_cast<std::size_t>(r)].front().start);
                placeTrack(p, r, c, start, xf);
            }
            placeHits(p, sc, start);
            used(ch.patch);
            prev = static_cast<int>(ch.patch);
            roleOf = ch.roles == 0 ? std::array<int, 2>{0, 1} : std::array<int, 2>{1, 0};
            if (!reportProgress(progress, std::min(t / spec.duration, 1.0), "compose")) return makeError("cancelled");
            if (stats.patchesUsed > 10000) break;
        }
        return {};
    }

    // ---- rat: people step out of the way of a rat running along the user's
    // trajectory (SPEC 4.5), and bump into their neighbours doing so. The rat
    // is a one-joint creature with no captured actions, so its {run, AVOID}
    // patches are generated here for the scene's rat speed (makeRatPatches),
    // not read from the project's patch library. A bump pushes the neighbour
    // into the forced reaction that best matches its posture and the push,
    // the response rule of patch generation ({any, AVOID, PUSHED}), applied
    // where the neighbours actually stand.
    struct Bystander {
        glm::vec2 spot{0.0f};
        RootXf at;                           // standing placement
        double passTime = 0, passDistance = 1e9;  // the rat's closest approach
        bool near = false;
        std::vector<ActionInstance> plan;    // empty: stands all along
    };

    static double distanceToPolyline(glm::vec2 p, const std::vector<glm::vec2>& line) {
        double best = std::numeric_limits<double>::max();
        for (std::size_t i = 0; i + 1 < line.size(); ++i) best = std::min(best, distanceToSegment(p, line[i], line[i + 1]));
        return best;
    }

    // The rat's keys: it waits at the first point until ratStart, then runs
    // the polyline at ratSpeed, facing along it (corners rounded over 0.3 m).
    std::vector<RootKey> ratKeys() const {
        const auto& P = spec.ratPath;
        std::vector<double> cum{0.0};
        for (std::size_t i = 0; i + 1 < P.size(); ++i) cum.push_back(cum.back() + static_cast<double>(glm::length(P[i + 1] - P[i])));
        const double length = cum.back();
        auto at = [&](double s) {
            s = std::clamp(s, 0.0, length);
            std::size_t i = static_cast<std::size_t>(std::upper_bound(cum.begin(), cum.end(), s) - cum.begin());
            i = std::clamp<std::size_t>(i, 1, P.size() - 1);
            const double seg = cum[i] - cum[i - 1];
            const float u = seg > 0 ? static_cast<float>((s - cum[i - 1]) / seg) : 0.0f;
            return P[i - 1] + u * (P[i] - P[i - 1]);
        };
        std::vector<RootKey> keys;
        double heading = 0;
        auto key = [&](double t, double s) {
            const glm::vec2 d = at(s + 0.15) - at(s - 0.15);
            if (glm::length(d) > 1e-4f) heading = angleOf(d);
            keys.push_back({t, {at(s), heading}});
        };
        if (spec.ratStart > 0) key(0.0, 0.0);
        constexpr double kKeyStep = 0.1;  // s
        const int steps = static_cast<int>(std::ceil(length / spec.ratSpeed / kKeyStep));
        for (int k = 0; k <= steps; ++k) {
            const double s = std::min(length, k * kKeyStep * spec.ratSpeed);
            key(spec.ratStart + s / spec.ratSpeed, s);
        }
        return keys;
    }

    // The body of someone following `plan` (or standing at `at` when it is empty) at time t.
    detail::BodyPose bodyIn(const std::vector<ActionInstance>& plan, const RootXf& at, double t) const {
        if (plan.empty()) {
            const double tau = std::fmod(std::max(t, 0.0), act(hold).duration);
            return {hold, tau, at * lib.rootAt(hold, 0).inverse()};
        }
        const auto& inst = plan[static_cast<std::size_t>(instanceIndexAt(plan, t))];
        return {inst.action, inst.clipTimeAt(t), inst.root};
    }

    // The floor boxes of the feet and shins of someone following `plan`
    // (standing at `at` when it is empty) at every sample from 0.6 s before
    // the rat's closest approach `pass` to 0.6 s after it.
    using FootBoxes = std::vector<std::array<SweptBox, 4>>;
    FootBoxes footBoxes(const std::vector<ActionInstance>& plan, const RootXf& at, double pass) const {
        FootBoxes out;
        for (double t = pass - 0.6; t <= pass + 0.6; t += 1.0 / kSampleRate) {
            const detail::BodyPose body = bodyIn(plan, at, t);
            const Obb* boxes = lib.boxesAt(body.action, lib.sampleAt(body.action, body.tau));
            auto& feet = out.emplace_back();
            int k = 0;
            for (int seg : {kLeftFoot, kRightFoot, kLeftShin, kRightShin}) feet[static_cast<std::size_t>(k++)] = floorBox(boxes[seg].placed(body.root));
        }
        return out;
    }

    // Closest the rat's body (ratAt(t): its root) comes to those boxes (m;
    // negative: it runs into them). Stops as soon as it is below `enough`.
    template <class RatAt>
    static double clearanceOf(const FootBoxes& feet, RatAt&& ratAt, double pass, double enough = -1e9) {
        double best = std::numeric_limits<double>::max();
        double t = pass - 0.6;
        for (const auto& sample : feet) {
            const RootXf r = ratAt(t);
            const glm::vec2 fwd = headingVector(r.heading);
            for (const SweptBox& box : sample) {
                for (float along : {0.0f, 0.5f, 1.0f}) {
                    const double d = static_cast<double>(rectDistance(box, r.pos + fwd * (along * kRatLength))) - 0.04;  // the rat's girth
                    best = std::min(best, d);
                }
            }
            if (best < enough) break;
            t += 1.0 / kSampleRate;
        }
        return best;
    }

    // Closest the rat's body comes to the feet and shins of someone following
    // `plan` while it passes them (m; negative: it runs into them).
    double ratClearance(const Bystander& b, const std::vector<ActionInstance>& plan) const {
        return clearanceOf(footBoxes(plan, b.at, b.passTime), [&](double t) { return creatureAt(ratBody, t); }, b.passTime);
    }

    // Ways out of the rat's path: an avoid or a step that can start from
    // standing, alone or followed by a second one that continues it in the
    // motion graph (a guard step moves 0.3 m; two get the feet clear of a
    // rat running right under someone). One representative per variant
    // class and start node. False when there are none.
    static constexpr const char* kNoWays = "rat: the project has no avoid or step action (people need one to get out of the rat's way)";
    bool findWays() {
        std::map<std::pair<int, int>, int> reps;
        for (int a = 0; a < lib.size(); ++a) {
            const auto& A = act(a);
            if (!A.is(kAvoid | kStep) || A.is(kReactive | kAttack | kRun | kWalk) || A.has("carry")) continue;
            reps.emplace(std::make_pair(lib.variantClass[static_cast<std::size_t>(a)], lib.startNode[static_cast<std::size_t>(a)]), a);
        }
        ways.clear();
        for (int pass = 0; pass < 2 && ways.empty(); ++pass) {
            for (const auto& [key, a] : reps) {
                if (pass == 0 && !lib.continuesInto(hold, a)) continue;
                ways.push_back({a});
                for (const auto& [key2, b] : reps) {
                    if (lib.continuesInto(a, b) && glm::length(act(b).end.pos) > 0.1f) ways.push_back({a, b});
                }
            }
        }
        return !ways.empty();
    }

    // {run, AVOID} patches (SPEC 4.5, the rat scene's third PatternList): the
    // rat runs straight at the scene's speed past someone standing in the
    // guard `lateral` m to the side of its line (positive: on its left) and
    // turned `facing` from its heading; every way out, started `lead` s
    // before the rat's closest approach, that keeps the rat clear of the feet
    // and shins is a patch. The initial conditions are the SPEC grid (0.2 m,
    // 20 degrees, 0.1 s). The rat has no captured actions to make patches
    // from, so its run is made for the scene's speed and the table is
    // generated per scene (in parallel; each cell on its own, so the same
    // table every time). The composer looks each bystander up in it.
    struct RatPatch {
        int way = 0;           // index into `ways`
        double lead = 0;       // s
        double clearance = 0;  // m, against the straight rat
        double score() const { return std::min(clearance, 0.25) - 0.01 * lead; }  // clear by a safe margin, at the last moment
    };
    static constexpr double kRatLateralStep = 0.2, kRatLeadStep = 0.1;
    static constexpr int kRatFacings = 18;  // 20 degrees apart
    int ratLaterals = 0;                    // cells either side of the line
    std::vector<std::vector<RatPatch>> ratTable;  // per (lateral, facing) cell, best first
    std::vector<std::vector<int>> ways;      // ways out: one or two avoiding or stepping actions

    static glm::vec2 leftOf(double heading) { return headingVector(heading + 0.5 * std::numbers::pi); }
    static double ratFacingAt(int f) { return wrapAngle((f - kRatFacings / 2) * 2 * std::numbers::pi / kRatFacings); }
    std::size_t ratCell(int lateral, int facing) const {
        return static_cast<std::size_t>((lateral + ratLaterals) * kRatFacings + facing);
    }

    void makeRatPatches() {
        ratLaterals = static_cast<int>(std::ceil(spec.reach / kRatLateralStep - 1e-9)) + 1;  // a cell beyond reach, to look up either side
        ratTable.assign(static_cast<std::size_t>((2 * ratLaterals + 1) * kRatFacings), {});
        constexpr double kPass = 3.0;  // patch time of the rat's closest approach
        tbb::parallel_for(0, kRatFacings, [&](int f) {
            const RootXf at{glm::vec2(0.0f), ratFacingAt(f)};
            for (std::size_t w = 0; w < ways.size(); ++w) {
                const auto& way = ways[w];
                const RootXf root = at * lib.rootAt(way.front(), 0).inverse();
                double duration = 0;
                for (int a : way) duration += act(a).duration;
                for (int k = 1; k * kRatLeadStep <= std::min(duration + 0.6, kPass - 0.2) + 1e-9; ++k) {
                    const double lead = k * kRatLeadStep;
                    const FootBoxes feet = footBoxes(planMove(at, kPass - lead, way, 0.0, root, false, kPass + 1.0), at, kPass);
                    for (int l = -ratLaterals; l <= ratLaterals; ++l) {
                        // The person stands l * 0.2 m to the left of the rat's line.
                        const glm::vec2 line = -static_cast<float>(l * kRatLateralStep) * leftOf(0.0);
                        const double clear = clearanceOf(
                            feet, [&](double t) { return RootXf{line + headingVector(0.0) * static_cast<float>(spec.ratSpeed * (t - kPass)), 0.0}; },
                            kPass, kRatClear);
                        if (clear >= kRatClear) ratTable[ratCell(l, f)].push_back({static_cast<int>(w), lead, clear});
                    }
                }
            }
        });
        for (auto& cell : ratTable) {
            std::stable_sort(cell.begin(), cell.end(), [](const RatPatch& a, const RatPatch& b) { return a.score() > b.score(); });
            stats.ratPatches += static_cast<int>(cell.size());
        }
    }

    // The patches of the cells nearest a bystander's configuration (the two
    // nearest lateral offsets by the two nearest facings), each way and lead once.
    std::vector<RatPatch> ratCandidates(const Bystander& b) const {
        const RootXf r = creatureAt(ratBody, b.passTime);
        const double lateral = static_cast<double>(glm::dot(b.spot - r.pos, leftOf(r.heading))) / kRatLateralStep;
        const double facing = (wrapAngle(b.at.heading - r.heading) + std::numbers::pi) / (2 * std::numbers::pi / kRatFacings);
        const int l0 = static_cast<int>(std::floor(lateral)), f0 = static_cast<int>(std::floor(facing));
        std::vector<RatPatch> out;
        std::set<std::pair<int, double>> seen;  // (way, lead): the cells share the 0.1 s lead grid exactly
        for (int l : {l0, l0 + 1}) {
            if (l < -ratLaterals || l > ratLaterals) continue;
            for (int f : {f0, f0 + 1}) {
                for (const RatPatch& p : ratTable[ratCell(l, ((f % kRatFacings) + kRatFacings) % kRatFacings)]) {
                    if (seen.emplace(p.way, p.lead).second) out.push_back(p);
                }
            }
        }
        return out;
    }

    // When a plan moves the body: from its first action that is not an idle
    // to the end of its last one; {+inf, -inf} for someone who only stands.
    std::pair<double, double> movingWindow(const std::vector<ActionInstance>& plan) const {
        std::pair<double, double> w{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
        for (const auto& inst : plan) {
            if (act(inst.action).is(kIdle)) continue;
            w.first = std::min(w.first, inst.start);
            w.second = std::max(w.second, inst.end);
        }
        return w;
    }

    // First time someone following `plan` from `from` to `until` touches
    // another bystander's body: {who, when}; {-1, 0} when nobody. Two people
    // standing still do not start touching, so once this plan has settled only
    // the others' moving windows are sampled.
    std::pair<int, double> firstTouch(const std::vector<Bystander>& crowd, std::size_t self, const std::vector<ActionInstance>& plan,
                                      double from, double until, std::size_t ignore = SIZE_MAX) const {
        constexpr float kShrink = 0.82f;  // as the composer's penetration test
        constexpr double dt = 1.0 / kSampleRate;
        std::vector<std::size_t> close;
        for (std::size_t o = 0; o < crowd.size(); ++o) {
            if (o != self && o != ignore && glm::length(crowd[o].spot - crowd[self].spot) < 3.0f) close.push_back(o);
        }
        auto touches = [&](std::size_t o, double t) {
            return detail::coreBodiesOverlap(lib, bodyIn(plan, crowd[self].at, t), bodyIn(crowd[o].plan, crowd[o].at, t), kShrink);
        };
        const double settle = std::min(until, std::max(from, movingWindow(plan).second) + dt);
        for (double t = from; t <= settle + 1e-9; t += dt) {
            for (std::size_t o : close) {
                if (touches(o, t)) return {static_cast<int>(o), t};
            }
        }
        std::pair<int, double> first{-1, std::numeric_limits<double>::infinity()};
        for (std::size_t o : close) {
            const auto [w0, w1] = movingWindow(crowd[o].plan);
            for (double t = std::max(settle, w0 - dt); t <= std::min({until, w1 + dt, first.second}) + 1e-9; t += dt) {
                if (touches(o, t)) {
                    first = {static_cast<int>(o), t};
                    break;
                }
            }
        }
        return first.first >= 0 ? first : std::pair<int, double>{-1, 0.0};
    }

    // Stands in the guard at `at` from 0 until `until` (the clip from its start each time round).
    std::vector<ActionInstance> standing(const RootXf& at, double until) const {
        std::vector<ActionInstance> plan;
        const RootXf root = at * lib.rootAt(hold, 0).inverse();
        for (double t = 0; t < until - 1e-6;) {
            const double end = std::min(until, t + act(hold).duration);
            plan.push_back({hold, t, 0.0, end, root, false, false});
            t = end;
        }
        return plan;
    }

    // Stands until `from`, plays `actions` one after another (the first from
    // clip time `offset`, placed at `root`), then stands where they leave off until `until`.
    std::vector<ActionInstance> planMove(const RootXf& at, double from, const std::vector<int>& actions, double offset,
                                         const RootXf& root, bool forced, double until) const {
        std::vector<ActionInstance> plan = standing(at, from);
        double t = from;
        RootXf place = root;
        for (std::size_t k = 0; k < actions.size(); ++k) {
            const double off = k == 0 ? offset : 0.0;
            const double end = t + act(actions[k]).duration - off;
            plan.push_back({actions[k], t, off, end, place, forced && k == 0, false});
            place = place * act(actions[k]).end;
            t = end;
        }
        const int idle = idleAfter(actions.back());
        while (t < until - 1e-6) {
            const double e = std::min(until, t + act(idle).duration);
            plan.push_back({idle, t, 0.0, e, place * lib.rootAt(idle, 0).inverse(), false, false});
            t = e;
        }
        return plan;
    }

    // Someone pushed into a reaction: by a bystander (index) or the rat (SIZE_MAX), when, and their new plan.
    struct Push {
        std::size_t who = 0, by = SIZE_MAX;
        double time = 0;
        std::vector<ActionInstance> plan;
    };

    // Pushes bystander q at time t away from `pusher` (bystander `by`, or the
    // rat when SIZE_MAX): the forced reaction matching its posture and the
    // push. Its neighbours may be pushed on in turn (depth levels). Returns the
    // changed plans, or nothing when the push would put anyone in the rat's
    // way or into someone who is already moving.
    std::optional<std::vector<Push>> push(const std::vector<Bystander>& crowd, std::size_t q, std::size_t by, const RootXf& pusher,
                                          double t, double until, int depth) const {
        const Bystander& b = crowd[q];
        if (!b.plan.empty()) return std::nullopt;  // it has moved, or will: its plan stands
        // Near the trajectory and not yet out of the way: it must get out of
        // the way itself before the rat has passed (pushed later, it would
        // have stood in the rat's way).
        if (by != SIZE_MAX && b.near && t >= b.passTime + 0.6) return std::nullopt;
        const detail::BodyPose body = bodyIn(b.plan, b.at, t);
        const auto reaction = rules->react({body.action, t, body.tau, body.root}, pusher, t, false, pushedPool);
        if (reaction.action < 0) return std::nullopt;
        auto plan = planMove(b.at, t, {reaction.action}, reaction.offset, reaction.root, true, until);
        // Pushed by someone else, it must not reel into the rat's way (pushed by the rat, it is in it).
        if (by != SIZE_MAX && b.near && t < b.passTime + 0.6 && ratClearance(b, plan) < kRatClear) return std::nullopt;
        std::vector<Push> changes;
        auto trial = crowd;
        trial[q].plan = plan;
        const double settled = until;  // both stand still afterwards: touching later counts too
        const auto [other, when] = firstTouch(trial, q, plan, t, settled, by);
        if (other >= 0) {
            if (depth <= 0) return std::nullopt;
            const detail::BodyPose mine = bodyIn(plan, b.at, when);
            auto more = push(trial, static_cast<std::size_t>(other), q, mine.root * lib.rootAt(mine.action, mine.tau), when,
                             until, depth - 1);
            if (!more) return std::nullopt;
            for (const auto& m : *more) trial[m.who].plan = m.plan;
            if (firstTouch(trial, q, plan, when, settled, static_cast<std::size_t>(other)).first >= 0) return std::nullopt;
            if (firstTouch(trial, q, plan, when + kContactWindow, settled, by).first >= 0) return std::nullopt;
            changes = std::move(*more);
        }
        changes.push_back({q, by, t, std::move(plan)});
        return changes;
    }

    // Takes a push into the crowd's plans (and the log of contacts).
    void commit(std::vector<Bystander>& crowd, Push&& m, std::vector<Push>& log) {
        Bystander& o = crowd[m.who];
        o.plan = m.plan;
        if (m.by != SIZE_MAX) ++stats.bumps;
        log.push_back(std::move(m));
    }

    static constexpr double kRatClear = 0.08;
    static constexpr double kContactWindow = 0.2;  // s a bump may keep two bodies touching (MetricsOptions::hitWindow)  // m between the rat and an avoider's feet and shins
    std::optional<detail::InteractionEngine> rules;  // forced reactions of the pushed
    int pushedPool = 0;
    SceneCharacter ratBody;  // the rat's keys

    Status rat(const ProgressFn& progress) {
        ratBody.body = "rat";
        ratBody.keys = ratKeys();
        const auto& keys = ratBody.keys;
        const double ratEnd = keys.back().time;
        const double until = ratEnd + 2.0;  // reactions and steps settle
        std::vector<int> pushed;
        for (int a = 0; a < lib.size(); ++a) {
            if (act(a).is(kPushed) && !act(a).is(kFalling)) pushed.push_back(a);
        }
        if (pushed.empty()) {
            for (int a = 0; a < lib.size(); ++a) {
                if (act(a).is(kPushed)) pushed.push_back(a);
            }
        }
        pushedPool = rules.emplace(lib).addPool(pushed);
        if (!findWays()) return makeError(kNoWays);
        makeRatPatches();

        // The crowd: people standing within `band` of the trajectory, `spacing` apart.
        std::vector<Bystander> crowd;
        glm::vec2 lo = spec.ratPath.front(), hi = lo;
        for (const auto& p : spec.ratPath) lo = glm::min(lo, p), hi = glm::max(hi, p);
        const auto band = static_cast<float>(spec.band);
        lo -= glm::vec2(band), hi += glm::vec2(band);
        std::uniform_real_distribution<double> unit(0.0, 1.0);
        for (int tries = 0; static_cast<int>(crowd.size()) < spec.crowd && tries < 400 * spec.crowd; ++tries) {
            const glm::vec2 q(lo.x + static_cast<float>(unit(rng)) * (hi.x - lo.x), lo.y + static_cast<float>(unit(rng)) * (hi.y - lo.y));
            const double heading = wrapAngle(unit(rng) * 2 * std::numbers::pi);
            if (distanceToPolyline(q, spec.ratPath) > spec.band) continue;
            if (glm::length(q - spec.ratPath.front()) < 1.5f) continue;  // not on the rat's hole
            if (std::any_of(crowd.begin(), crowd.end(), [&](const Bystander& b) { return static_cast<double>(glm::length(b.spot - q)) < spec.spacing; })) continue;
            Bystander b;
            b.spot = q;
            b.at = {q, heading};
            crowd.push_back(b);
        }
        if (crowd.empty()) return makeError("rat: nobody could stand near the trajectory (widen band or lower spacing)");
        for (auto& b : crowd) {
            for (double t = spec.ratStart; t <= ratEnd + 1e-9; t += 0.02) {
                const double d = static_cast<double>(glm::length(creatureAt(ratBody, t).pos - b.spot));
                if (d < b.passDistance) b.passDistance = d, b.passTime = t;
            }
            b.near = b.passDistance < spec.reach;
            stats.ratNear += b.near ? 1 : 0;
        }
        std::vector<std::size_t> order;
        for (std::size_t i = 0; i < crowd.size(); ++i) order.push_back(i);
        std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return crowd[a].passTime < crowd[b].passTime; });

        std::vector<Push> log;  // every push, for the scene's contacts
        int done = 0;
        for (std::size_t i : order) {
            Bystander& b = crowd[i];
            if (!reportProgress(progress, static_cast<double>(done++) / static_cast<double>(crowd.size()), "compose")) {
                return makeError("cancelled");
            }
            if (!b.near || !b.plan.empty()) continue;  // far off, or already pushed out of the way
            // The {run, AVOID} patches of the nearest configurations, placed
            // where the person stands and tried against the rat's actual run
            // (it may curve) and the neighbours: candidates minus colliding ones.
            struct Option {
                double score = -std::numeric_limits<double>::max();
                std::vector<ActionInstance> plan;
                double start = 0, clearance = 0;
                std::vector<Push> pushes;
            } best;
            for (const RatPatch& patch : ratCandidates(b)) {
                const auto& way = ways[static_cast<std::size_t>(patch.way)];
                const double ts = b.passTime - patch.lead;
                if (ts < 0.2) continue;
                const RootXf root = b.at * lib.rootAt(way.front(), 0).inverse();
                auto plan = planMove(b.at, ts, way, 0.0, root, false, until);
                const double clear = ratClearance(b, plan);
                if (clear < kRatClear) continue;
                // Clear of the rat by a safe margin; bumping a neighbour as
                // the spec likes it (0: avoid it, 1: seek it); the latest
                // start (people react at the last moment).
                const double bumpBonus = 0.2 * spec.bumps - 0.05;
                const double base = std::min(clear, 0.25) + 0.01 * (ts - b.passTime) + 1e-4 * unit(rng);
                if (base + std::max(0.0, bumpBonus) <= best.score) continue;  // cannot win: skip the body tests
                const double settled = until;  // everyone stands still afterwards: touching later counts too
                const auto [other, when] = firstTouch(crowd, i, plan, ts, settled);
                std::vector<Push> pushes;
                if (other >= 0) {
                    auto trial = crowd;
                    trial[i].plan = plan;
                    const detail::BodyPose mine = bodyIn(plan, b.at, when);
                    auto chain = push(trial, static_cast<std::size_t>(other), i, mine.root * lib.rootAt(mine.action, mine.tau),
                                      when, until, 1);
                    if (!chain) continue;
                    // With the pushed ones moving, the rest of the way out
                    // touches nobody, the pushed one included once the
                    // contact is over.
                    for (const auto& m : *chain) trial[m.who].plan = m.plan;
                    if (firstTouch(trial, i, plan, when, settled, static_cast<std::size_t>(other)).first >= 0) continue;
                    if (firstTouch(trial, i, plan, when + kContactWindow, settled).first >= 0) continue;
                    pushes = std::move(*chain);
                }
                const double score = base + (pushes.empty() ? 0.0 : bumpBonus);
                if (score > best.score) best = {score, std::move(plan), ts, clear, std::move(pushes)};
            }
            if (!best.plan.empty()) {
                b.plan = std::move(best.plan);
                ++stats.ratAvoided;
                ++stats.patchesUsed;
                stats.ratClearance = stats.ratClearance < 0 ? best.clearance : std::min(stats.ratClearance, best.clearance);
                for (auto& m : best.pushes) {
                    if (crowd[m.who].near) ++stats.ratPushed;
                    commit(crowd, std::move(m), log);
                }
                continue;
            }
            // No way out: it reels back as the rat runs into its feet (a push
            // from the rat, a little before it arrives).
            bool reeled = false;
            for (double lead : {0.1, 0.3, 0.5}) {
                const double t = std::max(0.2, b.passTime - lead);
                auto chain = push(crowd, i, SIZE_MAX, creatureAt(ratBody, t), t, until, 1);
                if (!chain) continue;
                for (auto& m : *chain) commit(crowd, std::move(m), log);
                reeled = true;
                break;
            }
            ++(reeled ? stats.ratStartled : stats.ratRunOver);
        }

        // The timeline: the rat first, then everyone, standing where they have no plan.
        auto& rat = scene.characters[static_cast<std::size_t>(addCharacter("rat", 1))];
        rat.body = "rat";
        rat.keys = keys;
        rat.preset = "creature";
        std::vector<int> index(crowd.size());
        for (std::size_t k = 0; k < crowd.size(); ++k) {
            auto& b = crowd[k];
            const int c = addCharacter("person-" + std::to_string(k + 1), 0);
            index[k] = c;
            track(c) = b.plan.empty() ? standing(b.at, until) : b.plan;
        }
        // The bumps as contacts (who pushed whom, when), for metrics and viewers.
        for (const auto& m : log) {
            if (m.by == SIZE_MAX) continue;  // reeled back from the rat: no one pushed it
            const detail::BodyPose pusher = bodyIn(crowd[m.by].plan, crowd[m.by].at, m.time);
            HitEvent h;
            h.time = m.time;
            h.attacker = index[m.by];
            h.defender = index[m.who];
            h.attackAction = pusher.action;
            h.effector = kTorso, h.target = kTorso;  // body against body
            h.speed = 1.0;                           // a walking-pace shove (m/s)
            h.impulse = detail::InteractionEngine::impulse(h.speed, kTorso);
            scene.hits.push_back(h);
        }
        scene.marks.push_back({"trail", spec.ratPath});
        return {};
    }

    // ---- domino: falling bodies knock the next people over, inside the painted area.
    struct Faller {
        int c = 0;
        double clipStart = 0;  // scene time of the clip's time 0
        int action = 0;
        RootXf root;           // placement of the clip's first frame
        double offset = 0;     // clip time the fall started at
        int patch = -1;        // the patch it fell in (as its character 2), -1: a start
    };

    SweptBox standingBox(const glm::vec2& p) const { return {p - glm::vec2(0.35f), p + glm::vec2(0.35f)}; }


    // Floor area a character covers: the box around all of it, and the
    // boxes of its body per quarter second (their union in time).
    struct Print {
        SweptBox all = SweptBox::empty();
        std::vector<SweptBox> parts;
        void add(const SweptBox& b) {
            all.add(b);
            parts.push_back(b);
        }
        bool overlaps(const Print& o, float margin) const {
            if (!all.overlaps(o.all, margin)) return false;
            for (const auto& a : parts) {
                if (!a.overlaps(o.all, margin)) continue;
                for (const auto& b : o.parts) {
                    if (a.overlaps(b, margin)) return true;
                }
            }
            return false;
        }
    };

    // Where patch character `role` goes over the whole patch, placed by xf.
    static Print footprint(const Patch& p, int role, const RootXf& xf) {
        Print out;
        for (const auto& s : p.swept[static_cast<std::size_t>(role)]) out.add(placedBox(s, xf));
        return out;
    }

    // Stands character c in the guard from its first free moment until `until`,
    // the last guard timed so that its clip is at `clipTimeAtEnd` then.
    void standUntil(int c, const RootXf& at, double until, double clipTimeAtEnd) {
        const double lastStart = until - clipTimeAtEnd;
        auto holdAt = [&](double start, double end, double offset) {
            append(c, hold, start, at * lib.rootAt(hold, 0).inverse(), offset, end);
        };
        double t = track(c).empty() ? 0.0 : freeAt(c);
        while (t < lastStart - 1e-6) {
            const double end = std::min(lastStart, t + act(hold).duration);
            holdAt(t, end, 0.0);
            t = end;
        }
        if (until > t + 1e-9) holdAt(t, until, std::max(0.0, clipTimeAtEnd - (until - t)));
    }

    // Share of the painted floor within ComposeStats::kCoverRadius of a spot.
    double coverage(const std::vector<glm::vec2>& fallers) const {
        constexpr float kStep = 0.25f;
        const glm::vec2 lo = spec.floor.extentMin(), hi = spec.floor.extentMax();
        long painted = 0, covered = 0;
        for (float z = lo.y + 0.5f * kStep; z < hi.y; z += kStep) {
            for (float x = lo.x + 0.5f * kStep; x < hi.x; x += kStep) {
                const glm::vec2 q(x, z);
                if (!spec.floor.paintedAt(q)) continue;
                ++painted;
                for (const glm::vec2& s : fallers) {
                    if (glm::length(s - q) <= ComposeStats::kCoverRadius) {
                        ++covered;
                        break;
                    }
                }
            }
        }
        return painted > 0 ? static_cast<double>(covered) / static_cast<double>(painted) : 0.0;
    }

    Status domino(const ProgressFn& progress) {
        if (spec.floor.empty()) return makeError("domino: no floor bitmap");
        if (spec.starts.empty()) return makeError("domino: no start (where the first person falls)");
        std::vector<std::size_t> chainPatches;
        std::vector<char> isChain(patches.patches.size(), 0);
        for (std::size_t i = 0; i < patches.patches.size(); ++i) {
            const auto& p = patches.patches[i];
            const auto& pattern = patches.patterns[static_cast<std::size_t>(p.pattern)];
            if (!allowed[i] || pattern.entries.empty() || !isReactiveAnnotation(pattern.entries[0].annotation) ||
                pattern.entries[0].character != 0)
                continue;
            const bool pushes = std::any_of(p.hits.begin(), p.hits.end(), [](const HitEvent& h) { return h.attacker == 0 && !h.blocked; });
            if (pushes) chainPatches.push_back(i), isChain[i] = 1;
        }
        if (chainPatches.empty()) return makeError("domino: the patch library has no patch where a falling body knocks someone over (generate the fall-fall pattern)");
        std::vector<Print> prints;     // per character: where it stands and falls
        std::vector<glm::vec2> spots;  // per character: where it stands
        std::vector<Faller> queue;
        auto byTime = [](const Faller& a, const Faller& b) { return a.clipStart > b.clipStart; };
        std::uniform_real_distribution<double> unit(0.0, 1.0);
        for (std::size_t k = 0; k < spec.starts.size(); ++k) {
            const auto& st = spec.starts[k];
            if (!spec.floor.paintedAt(st.pos)) {
                return makeError("domino: start " + std::to_string(k) + " at (" + std::to_string(st.pos.x) + ", " +
                                 std::to_string(st.pos.y) + ") is not on the painted area");
            }
            const Patch& p = patches.patches[chainPatches[static_cast<std::size_t>(rng() % chainPatches.size())]];
            const int action = p.tracks[0].front().action;
            RootXf at;
            at.pos = st.pos;
            at.heading = wrapAngle(unit(rng) * 2 * std::numbers::pi);
            const int c = addCharacter("person-" + std::to_string(scene.characters.size() + 1), 0);
            standUntil(c, at, st.time, 0.0);
            const RootXf root = at * lib.rootAt(action, 0).inverse();
            append(c, action, st.time, root);
            Print first = footprint(p, 0, root * p.tracks[0].front().root.inverse());
            first.add(standingBox(at.pos));
            prints.push_back(first);
            spots.push_back(at.pos);
            queue.push_back({c, st.time, action, root, 0.0, -1});
            std::push_heap(queue.begin(), queue.end(), byTime);
        }
        constexpr int kBranch = 3;
        while (!queue.empty() && static_cast<int>(scene.characters.size()) < spec.maxCharacters) {
            std::pop_heap(queue.begin(), queue.end(), byTime);
            const Faller f = queue.back();
            queue.pop_back();
            // What the faller can knock over next: where it fell in a patch,
            // the chain patches spatially connected to it through the faller
            // (SPEC 4.3: it plays the same fall on, and the new victim never
            // meets whoever pushed it); a start, any chain patch that begins
            // with its fall. With the patch time from which the fall is the faller's.
            std::vector<std::pair<std::size_t, double>> next;
            if (f.patch >= 0) {
                for (const auto& l : patches.spatial[static_cast<std::size_t>(f.patch)]) {
                    if (l.sharedA == 1 && l.sharedB == 0 && isChain[static_cast<std::size_t>(l.to)]) next.emplace_back(l.to, l.from);
                }
                std::sort(next.begin(), next.end());
            } else {
                for (std::size_t idx : chainPatches) {
                    if (patches.patches[idx].tracks[0].front().action == f.action) next.emplace_back(idx, f.offset);
                }
            }
            for (int child = 0; child < kBranch && static_cast<int>(scene.characters.size()) < spec.maxCharacters; ++child) {
                int best = -1;
                double bestS = -std::numeric_limits<double>::max();
                for (const auto& [idx, from] : next) {
                    const Patch& p = patches.patches[idx];
                    const HitEvent& hit = *std::find_if(p.hits.begin(), p.hits.end(), [](const HitEvent& h) { return h.attacker == 0; });
                    if (hit.time < from + 0.05) continue;  // the fall is already past that point
                    const RootXf xf = f.root * p.tracks[0].front().root.inverse();
                    const glm::vec2 q = (xf * p.tracks[1].front().placementAt(lib, 0)).pos;
                    if (!spec.floor.paintedAt(q)) continue;

                    Print print = footprint(p, 1, xf);
                    print.add(standingBox(q));
                    bool clear = true;
                    for (std::size_t o = 0; o < prints.size() && clear; ++o) {
                        // Boxes around bodies are generous: they must overlap by 0.15 m to count.
                        if (static_cast<int>(o) != f.c) clear = !prints[o].overlaps(print, -0.15f);
                    }
                    if (!clear) continue;
                    int near = 0;
                    for (const auto& sp : spots) near += glm::length(sp - q) < 1.5f ? 1 : 0;
                    const double sc = score(idx, near, 0);
                    if (sc > bestS) bestS = sc, best = static_cast<int>(idx);
                }
                if (best < 0) break;
                const Patch& p = patches.patches[static_cast<std::size_t>(best)];
                const HitEvent hit = *std::find_if(p.hits.begin(), p.hits.end(), [](const HitEvent& h) { return h.attacker == 0; });
                const RootXf xf = f.root * p.tracks[0].front().root.inverse();
                const RootXf standing = xf * p.tracks[1].front().placementAt(lib, 0);
                const double tHit = f.clipStart + hit.time;
                const int n = addCharacter("person-" + std::to_string(scene.characters.size() + 1), 0);
                // It stands in the guard, at the clip time the patch had when the body hit it.
                const double holdTime = hit.time - p.tracks[1].front().start;
                standUntil(n, standing, tHit, holdTime);
                const auto& reaction = *std::find_if(p.tracks[1].begin(), p.tracks[1].end(), [](const ActionInstance& i) { return i.forced; });
                ActionInstance fall = reaction;
                fall.start = tHit;
                fall.end = tHit + (reaction.end - reaction.start);
                fall.root = xf * reaction.root;
                track(n).push_back(fall);
                HitEvent h = hit;
                h.time = tHit, h.attacker = f.c, h.defender = n, h.attackAction = f.action;
                scene.hits.push_back(h);
                Print print = footprint(p, 1, xf);
                print.add(standingBox(standing.pos));
                prints.push_back(print);
                spots.push_back(standing.pos);
                used(static_cast<std::size_t>(best));
                ++stats.chainFalls;
                stats.spatialFalls += f.patch >= 0 ? 1 : 0;
                queue.push_back({n, tHit - reaction.offset, reaction.action, fall.root, reaction.offset, best});
                std::push_heap(queue.begin(), queue.end(), byTime);
            }
            if (!reportProgress(progress, std::min(1.0, static_cast<double>(scene.characters.size()) / spec.maxCharacters), "compose")) {
                return makeError("cancelled");
            }
        }
        stats.paintedCoverage = coverage(spots);
        scene.floor = spec.floor;  // the viewers draw the painted area
        // Bystanders outside the painted area, clear of every fall.
        const glm::vec2 lo = spec.floor.extentMin(), hi = spec.floor.extentMax();
        for (int b = 0, tries = 0; b < spec.background && tries < 200 * spec.background; ++tries) {
            const float ux = static_cast<float>(unit(rng)), uz = static_cast<float>(unit(rng));
            const glm::vec2 q(lo.x + ux * (hi.x - lo.x), lo.y + uz * (hi.y - lo.y));
            if (spec.floor.paintedAt(q)) continue;
            Print box;
            box.add(standingBox(q));
            bool clear = true;
            for (const auto& pr : prints) clear = clear && !pr.overlaps(box, 0.3f);
            if (!clear) continue;
            RootXf at;
            at.pos = q;
            at.heading = wrapAngle(unit(rng) * 2 * std::numbers::pi);
            const int c = addCharacter("bystander-" + std::to_string(b + 1), 1);
            append(c, hold, 0.0, at * lib.rootAt(hold, 0).inverse());
            prints.push_back(box);
            spots.push_back(q);
            ++b;
        }
        // Everyone still standing stays until the last one has fallen.
        double end = 0;
        for (int c = 0; c < static_cast<int>(scene.characters.size()); ++c) end = std::max(end, freeAt(c));
        for (int c = 0; c < static_cast<int>(scene.characters.size()); ++c) {
            if (!act(track(c).back().action).is(kReactive)) waitUntil(c, end);
        }
        return {};
    }

    // A porter who has handed the item on walks 2.5-4 m away, in the first
    // direction (away from the carrier first) whose walk touches nobody.
    bool stepAside(int c, int carrier) {
        const RootXf g = leaves(c);
        glm::vec2 away = g.pos - leaves(carrier).pos;
        if (glm::length(away) < 1e-3f) away = -headingVector(g.heading);
        away = glm::normalize(away);
        for (float dist : {2.5f, 4.0f}) {
            for (double turn : {0.0, 0.8, -0.8, 1.6, -1.6, 2.4, -2.4}) {
                const glm::vec2 dir = rotateFloor(away, turn);
                RootXf spot;
                spot.pos = g.pos + dir * dist;
                spot.heading = angleOf(-dir);
                std::vector<ActionInstance> walk;
                auto [end, when] = locomote(c, -1, g, freeAt(c), track(c).back().action, spot, 0.0, walk);
                if (walk.empty() || glm::length(end.pos - g.pos) < 1.0f || penetrates(walk, c)) continue;
                // Room to wait there: nobody within 1 m of the spot.
                bool room = true;
                for (int o = 0; o < static_cast<int>(scene.characters.size()) && room; ++o) {
                    if (o != c && !track(o).empty()) room = rectDistance(bodyBox(o, when), end.pos) >= 1.0f;
                }
                if (!room) continue;
                for (auto& w : walk) track(c).push_back(w);
                stats.locomotionSteps += static_cast<int>(walk.size());
                return true;
            }
        }
        return false;
    }

    // ---- luggage: an item passed along a chain of porters; whoever has handed
    // it on is recycled as a later receiver.
    Status luggage(const ProgressFn& progress) {
        std::vector<std::size_t> handoffs;  // patches where character 1 hands and character 2 receives
        for (std::size_t i = 0; i < patches.patches.size(); ++i) {
            if (!allowed[i]) continue;
            const auto& p = patches.patches[i];
            auto has = [&](int role, const char* annotation) {
                return std::any_of(p.tracks[static_cast<std::size_t>(role)].begin(), p.tracks[static_cast<std::size_t>(role)].end(),
                                   [&](const ActionInstance& inst) { return act(inst.action).has(annotation); });
            };
            if (has(0, "hand") && has(1, "receive") && act(p.tracks[0].front().action).has("carry")) handoffs.push_back(i);
        }
        if (handoffs.empty()) return makeError("luggage: the patch library has no patch where character 1 hands and character 2 receives");
        nearDistance = 0.25f;
        standWhenDone = true;
        if (spec.porters < 2) return makeError("luggage: needs at least 2 porters");
        std::vector<int> porters;
        for (int k = 0; k < spec.porters; ++k) porters.push_back(addCharacter("porter-" + std::to_string(k + 1), 0));
        // The first hand-over at the origin; the other porters wait in a row behind the receiver.
        int prev = -1, carrier = porters[0], aside = -1, retries = 0;
        std::vector<Pass> passes;
        std::vector<double> lastUsed(porters.size(), -1.0);  // per porter index
        auto porterIndex = [&](int c) { return static_cast<int>(std::find(porters.begin(), porters.end(), c) - porters.begin()); };
        for (int k = 0; k < spec.handoffs; ++k) {
            const double t0 = track(carrier).empty() ? 0.0 : freeAt(carrier);
            if (t0 >= spec.duration) break;
            const RootXf at = track(carrier).empty() ? RootXf{} : leaves(carrier);
            std::vector<std::size_t> cands;
            if (prev >= 0) {
                for (const auto& l : patches.temporal[static_cast<std::size_t>(prev)]) {
                    if (l.shared == 1 && l.roles == 1 && std::binary_search(handoffs.begin(), handoffs.end(), static_cast<std::size_t>(l.to))) {
                        cands.push_back(static_cast<std::size_t>(l.to));
                    }
                }
            }
            const bool linked = !cands.empty();
            if (!linked) cands = handoffs;
            // The receiver: the porter free for longest (never the carrier);
            // when that one has failed to reach the carrier twice, the next.
            std::vector<int> free;
            for (std::size_t j = 0; j < porters.size(); ++j) {
                if (porters[j] != carrier) free.push_back(static_cast<int>(j));
            }
            std::stable_sort(free.begin(), free.end(), [&](int x, int y) {
                return lastUsed[static_cast<std::size_t>(x)] < lastUsed[static_cast<std::size_t>(y)];
            });
            const int receiver = free[std::min(static_cast<std::size_t>(retries / 2), free.size() - 1)];
            const int rc = porters[static_cast<std::size_t>(receiver)];
            struct Option {
                double score;
                std::size_t patch;
            };
            std::vector<Option> options;
            for (std::size_t i : cands) {
                const Patch& p = patches.patches[i];
                options.push_back({score(i, 0, 0) + (track(carrier).empty() || lib.startNode[static_cast<std::size_t>(p.tracks[0].front().action)] ==
                                                                               lib.endNode[static_cast<std::size_t>(track(carrier).back().action)]
                                                          ? 1.0
                                                          : 0.0),
                                   i});
            }
            std::stable_sort(options.begin(), options.end(), [](const Option& x, const Option& y) { return x.score > y.score; });
            // The other porters, standing where they wait: the hand-over must not
            // touch them (the last giver steps aside once this one is placed).
            Print others;
            for (int c : porters) {
                if (c != carrier && c != rc && c != aside && !track(c).empty()) others.add(bodyBox(c, std::max(t0, freeAt(c))));
            }
            bool placed = false;
            for (std::size_t o = 0; o < options.size() && o < 60 && !placed; ++o) {
                const Patch& p = patches.patches[options[o].patch];
                const RootXf xf = at * p.tracks[0].front().root.inverse();
                Print print = footprint(p, 0, xf);
                for (const auto& b : footprint(p, 1, xf).parts) print.add(b);
                if (!others.parts.empty() && others.overlaps(print, 0.0f)) continue;
                const RootXf goal = xf * p.tracks[1].front().root;
                // To take this option back: the tracks' lengths before it.
                const std::size_t kept[] = {track(carrier).size(), track(rc).size(), aside >= 0 ? track(aside).size() : 0};
                const int keptSteps = stats.locomotionSteps;
                const double keptJunction = stats.maxJunctionError;
                // The receiver walks over from where it is (it starts next to the goal the first time).
                std::vector<ActionInstance> walk;
                double arrive = t0;
                if (!track(rc).empty()) {
                    // Planned backward from the hand-over: it sets off as late as
                    // it can (never before it is free) and arrives when the
                    // carrier is ready; re-planned until the timing settles.
                    // Straight there, or round the others by a point 2 m off
                    // to either side of the goal.
                    bool reached = false;
                    const RootXf from = leaves(rc);
                    const glm::vec2 back = glm::length(from.pos - goal.pos) > 1e-3f ? glm::normalize(from.pos - goal.pos) : glm::vec2(0, 1);
                    for (double turn : {0.0, 1.0, -1.0, 2.0, -2.0}) {
                        RootXf end;
                        double when = 0, shift = std::max(freeAt(rc), t0 - 3.0);
                        RootXf via;
                        via.pos = goal.pos + rotateFloor(back, turn) * 2.0f;
                        via.heading = angleOf(goal.pos - via.pos);
                        for (int pass = 0; pass < 4; ++pass) {
                            walk.clear();
                            RootXf mid = from;
                            double midTime = 0;
                            if (turn != 0.0) std::tie(mid, midTime) = locomote(rc, carrier, from, 0.0, track(rc).back().action, via, shift, walk);
                            std::tie(end, when) = locomote(rc, carrier, mid, midTime, walk.empty() ? track(rc).back().action : walk.back().action,
                                                           goal, shift, walk);
                            const double next = std::max(freeAt(rc), t0 - when);
                            if (std::fabs(next - shift) < 1e-9) break;
                            shift = next;
                        }
                        for (auto& w : walk) w.start += shift, w.end += shift;
                        if (glm::length(end.pos - goal.pos) > 0.3f || penetrates(walk, rc)) continue;
                        arrive = shift + when;
                        stats.maxJunctionError = std::max(stats.maxJunctionError, static_cast<double>(glm::length(end.pos - goal.pos)));
                        reached = true;
                        break;
                    }
                    if (!reached) continue;
                    if (!walk.empty()) waitUntil(rc, walk.front().start);
                }
                const double start = std::max(t0, arrive);
                if (!track(carrier).empty()) waitUntil(carrier, start);
                for (auto& w : walk) track(rc).push_back(w);
                if (!track(rc).empty()) waitUntil(rc, start);
                placeTrack(p, 0, carrier, start, xf);
                placeTrack(p, 1, rc, start, xf);
                // The previous giver steps out of the way now that this
                // hand-over is known (its walk is checked against it) and
                // waits there to be recycled. Where it cannot, or where the
                // hand-over would touch someone on the move (the footprint
                // test above sees where people stand, not where they walk):
                // the next option instead.
                const auto added = [&](int c, std::size_t from) {
                    return std::vector<ActionInstance>(track(c).begin() + static_cast<std::ptrdiff_t>(from), track(c).end());
                };
                const bool clear = (aside < 0 || aside == rc || stepAside(aside, carrier)) &&
                                   !penetrates(added(carrier, kept[0]), carrier) && !penetrates(added(rc, kept[1]), rc);
                if (!clear) {
                    track(carrier).resize(kept[0]);
                    track(rc).resize(kept[1]);
                    if (aside >= 0) track(aside).resize(kept[2]);
                    stats.locomotionSteps = keptSteps;
                    stats.maxJunctionError = keptJunction;
                    continue;
                }
                stats.locomotionSteps += static_cast<int>(walk.size());
                passes.push_back({carrier, rc, start, start + p.duration});
                used(options[o].patch);
                (linked ? stats.temporalLinks : stats.recycled) += 1;
                prev = static_cast<int>(options[o].patch);
                lastUsed[static_cast<std::size_t>(porterIndex(carrier))] = start;
                lastUsed[static_cast<std::size_t>(receiver)] = start;
                placed = true;
            }
            if (!placed) {
                // Nobody can reach the carrier where it stands: it carries on a
                // step (or turns) and the hand-over is tried again from there.
                auto when = [&] {
                    char buf[32];
                    std::snprintf(buf, sizeof buf, "%.2f s", t0);
                    return std::string(buf);
                };
                if (++retries > 6 || track(carrier).empty()) {
                    return makeError("luggage: no porter can reach porter " + std::to_string(porterIndex(carrier) + 1) + " to take the item at " +
                                     when() + " (it moved on and was tried again 6 times; try another seed or fewer porters)");
                }
                // A carrying walk or turn that continues its last action; where
                // none does (it has put the item down), any carrying action
                // that does (picking it up again).
                int step = -1;
                for (const bool moving : {true, false}) {
                    for (int i = 0; i < lib.size(); ++i) {
                        const auto& a = act(i);
                        if (!a.has("carry") || (moving && !(a.is(kWalk) || a.is(kTurn))) || a.has("hand") || a.has("receive")) continue;
                        if (lib.startNode[static_cast<std::size_t>(i)] != lib.endNode[static_cast<std::size_t>(track(carrier).back().action)]) continue;
                        if (step < 0 || (rng() & 1)) step = i;
                    }
                    if (step >= 0) break;
                }
                if (step < 0) {
                    return makeError("luggage: porter " + std::to_string(receiver + 1) + " cannot reach the hand-over at " + when() +
                                     ", and the carrier has no carrying step that continues its '" + act(track(carrier).back().action).name +
                                     "' (try another seed)");
                }
                // The last giver leaves first (it stands where the carrier
                // would go), and the others wait where they are (their idles
                // written now) while the carrier moves.
                if (aside >= 0 && aside != rc && stepAside(aside, carrier)) aside = -1;
                const ActionInstance move{step, t0, 0.0, t0 + act(step).duration, leaves(carrier), false, false};
                for (int c : porters) {
                    if (c != carrier && !track(c).empty()) waitUntil(c, move.end);
                }
                if (!penetrates({move}, carrier)) track(carrier).push_back(move);
                --k;
                continue;
            }
            retries = 0;
            aside = carrier;
            carrier = rc;
            if (k == 0) {
                // The waiting porters stand in a row beside the first receiver,
                // each where its body touches nobody for the first hand-over.
                const RootXf r = leaves(rc);
                int row = 1;
                for (int c : porters) {
                    if (!track(c).empty()) continue;
                    for (int tries = 0; tries < 40; ++tries, ++row) {
                        RootXf spot = r;
                        spot.pos = r.pos - headingVector(r.heading) * (1.2f * static_cast<float>(row)) +
                                   rotateFloor(glm::vec2(1.5f, 0.0f), r.heading);
                        const ActionInstance wait{hold, 0.0, 0.0, freeAt(rc), spot * lib.rootAt(hold, 0).inverse(), false, false};
                        if (penetrates({wait}, c)) continue;
                        track(c).push_back(wait);
                        ++row;
                        break;
                    }
                    if (track(c).empty()) return makeError("luggage: no room for porter " + std::to_string(c + 1) + " to wait");
                }
            }
            if (!reportProgress(progress, static_cast<double>(k + 1) / spec.handoffs, "compose")) return makeError("cancelled");
        }
        // The last giver steps aside too (it would stand in the last carrier's way).
        if (aside >= 0 && aside != carrier) stepAside(aside, carrier);
        double end = 0;
        for (int c : porters) end = std::max(end, freeAt(c));
        for (int c : porters) waitUntil(c, end);
        addBag(passes, porters[0], end);
        return {};
    }

    // A hand-over of the luggage: giver, receiver and the patch's time span.
    struct Pass {
        int giver = 0, receiver = 0;
        double start = 0, end = 0;
    };

    // The item itself, as a one-joint body ("bag") held between its holder's
    // hands, across the body: the first porter holds it from the start, and it
    // changes hands in each hand-over where the two porters' hands come
    // closest, passing from one pair of hands to the other over kPassTime
    // (hands that do not quite meet do not make it jump).
    void addBag(const std::vector<Pass>& passes, int first, double end) {
        const ScenePoser poser(scene, lib);
        std::vector<glm::vec3> world;
        auto hands = [&](int c, double t) {
            const auto& joints = lib.motions[static_cast<std::size_t>(act(track(c).front().action).motion)].joints;
            poser.worldPositions(c, t, world);
            if (!joints.hasHands()) return world[0];
            return 0.5f * (world[static_cast<std::size_t>(joints.leftHand)] + world[static_cast<std::size_t>(joints.rightHand)]);
        };
        std::vector<std::pair<double, int>> holders{{0.0, first}};  // from this time on, this porter
        for (const auto& p : passes) {
            double best = p.start, bestD = std::numeric_limits<double>::max();
            for (double t = p.start; t <= p.end + 1e-9; t += 1.0 / kSampleRate) {
                const double d = static_cast<double>(glm::length(hands(p.giver, t) - hands(p.receiver, t)));
                if (d < bestD) bestD = d, best = t;
            }
            holders.emplace_back(best, p.receiver);
        }
        SceneCharacter bag;
        bag.name = "bag";
        bag.body = "bag";
        bag.side = 1;
        bag.preset = "prop";
        constexpr double kKeyRate = 15;  // keys per second
        constexpr double kPassTime = 0.5;  // s
        auto across = [&](int c, double t) {  // the bag's axis along the holder's left-right
            const auto& inst = playingAt(c, t);
            return wrapAngle(inst.placementAt(lib, inst.clipTimeAt(t)).heading + std::numbers::pi / 2);
        };
        std::size_t h = 0;
        for (int k = 0; k <= static_cast<int>(std::ceil(end * kKeyRate)); ++k) {
            const double t = std::min(end, k / kKeyRate);
            while (h + 1 < holders.size() && holders[h + 1].first - 0.5 * kPassTime <= t) ++h;
            const int c = holders[h].second;
            glm::vec3 mid = hands(c, t);
            double heading = across(c, t);
            if (h > 0 && t < holders[h].first + 0.5 * kPassTime) {
                // Passing: from the giver's hands to the receiver's.
                const int giver = holders[h - 1].second;
                const double x = std::clamp((t - (holders[h].first - 0.5 * kPassTime)) / kPassTime, 0.0, 1.0);
                const float w = static_cast<float>(x * x * (3.0 - 2.0 * x));
                const glm::vec3 from = hands(giver, t);
                mid = from + w * (mid - from);
                heading = lerp(RootXf{{}, across(giver, t)}, RootXf{{}, heading}, static_cast<double>(w)).heading;
            }
            const glm::vec2 centre(mid.x, mid.z);
            bag.keys.push_back({t, {centre - headingVector(heading) * (0.5f * kBagLength), heading}, std::max(0.0f, mid.y)});
        }
        scene.characters.push_back(std::move(bag));
    }

    // The standard pose nearest to c among those some usable patch starts from.
    int nearestStartingPose(const PatchConfig& c) const {
        int best = -1;
        double bestD = std::numeric_limits<double>::max();
        for (std::size_t i = 0; i < patches.patches.size(); ++i) {
            if (!allowed[i]) continue;
            const int pose = patches.initialPose[i];
            const double d = configDistance(c, patches.standardPoses[static_cast<std::size_t>(pose)]);
            if (d < bestD) bestD = d, best = pose;
        }
        return best;
    }
    double freeAt0(int c) const { return track0(c).empty() ? 0.0 : freeAt(c); }
    const std::vector<ActionInstance>& track0(int c) const { return scene.characters[static_cast<std::size_t>(c)].track; }
};

}  // namespace


namespace {

// Optional members of the compose spec: absent leaves `out` as it is; present
// must be a number (an integer for the int form) within [lo, hi].
Status optionalInt(const prep::JsonReader& rd, const json& obj, const char* key, int lo, int hi, int& out) {
    const std::string path = std::string("/") + key;
    auto f = rd.field(obj, "", key, false);
    if (!f) return f.error();
    if (!*f) return {};
    auto n = rd.integer(**f, path);
    if (!n) return n.error();
    if (*n < lo || *n > hi) return rd.error(path, "must be between " + std::to_string(lo) + " and " + std::to_string(hi));
    out = *n;
    return {};
}

// An optional number field of obj (at JSON path `parent`) within (lo, hi],
// or [lo, hi] when lowIncluded.
Status optionalNumberIn(const prep::JsonReader& rd, const json& obj, const std::string& parent, const char* key, double lo,
                        double hi, const char* unit, double& out, bool lowIncluded) {
    const std::string path = parent + "/" + key;
    auto f = rd.field(obj, parent, key, false);
    if (!f) return f.error();
    if (!*f) return {};
    auto x = rd.number(**f, path);
    if (!x) return x.error();
    if (!(lowIncluded ? *x >= lo : *x > lo) || *x > hi) {
        char range[64];
        std::snprintf(range, sizeof range, "must be in %c%g, %g] %s", lowIncluded ? '[' : '(', lo, hi, unit);
        return rd.error(path, range);
    }
    out = *x;
    return {};
}

Status optionalNumber(const prep::JsonReader& rd, const json& obj, const char* key, double lo, double hi, const char* unit,
                      double& out) {
    return optionalNumberIn(rd, obj, "", key, lo, hi, unit, out, false);
}

}  // namespace

const char* sceneKindName(SceneKind kind) {
    switch (kind) {
        case SceneKind::OneVsMany: return "one-vs-many";
        case SceneKind::OneVsOne: return "one-vs-one";
        case SceneKind::Domino: return "domino";
        case SceneKind::Luggage: return "luggage";
        case SceneKind::Football: return "football";
        case SceneKind::Rat: return "rat";
    }
    return "?";
}

Result<ComposeSpec> parseComposeSpec(std::string_view text, std::string_view fileName, const PatchLibrary& patches) {
    const prep::JsonReader rd(fileName);
    const json j = json::parse(text, nullptr, false);
    if (j.is_discarded()) return rd.error("", "not valid JSON");
    if (!j.is_object()) return rd.error("", "must be an object");
    ComposeSpec s;
    s.text = std::string(text);
    static const char* const known[] = {"version", "kind",  "duration", "seed",       "enemies",       "entry_radius",
                                        "patterns", "commands", "floor", "starts", "background", "max_characters",
                                        "porters", "handoffs", "tacklers", "goal", "directions", "doubles",
                                        "rat", "crowd", "band", "spacing", "reach", "bumps"};
    for (auto it = j.begin(); it != j.end(); ++it) {
        if (std::find_if(std::begin(known), std::end(known), [&](const char* k) { return it.key() == k; }) == std::end(known)) {
            return rd.error("/" + it.key(), "unknown field");
        }
    }
    FRAY_TRY(kind, rd.stringAt(j, "", "kind"));
    if (kind == "one-vs-many") s.kind = SceneKind::OneVsMany;
    else if (kind == "one-vs-one") s.kind = SceneKind::OneVsOne;
    else if (kind == "domino") s.kind = SceneKind::Domino;
    else if (kind == "luggage") s.kind = SceneKind::Luggage;
    else if (kind == "football") s.kind = SceneKind::Football;
    else if (kind == "rat") s.kind = SceneKind::Rat;
    else return rd.error("/kind", "unknown scene kind '" + kind + "' (this build composes one-vs-many, one-vs-one, domino, luggage, football and rat)");
    if (auto st = optionalNumber(rd, j, "duration", 0, 3600, "seconds", s.duration); !st) return st.error();
    if (auto f = rd.field(j, "", "seed", false); !f) return f.error();
    else if (*f) {
        FRAY_TRY(d, rd.integer(**f, "/seed"));
        if (d < 0) return rd.error("/seed", "must not be negative");
        s.seed = static_cast<std::uint64_t>(d);
    }
    if (auto st = optionalInt(rd, j, "enemies", 1, 1000, s.enemies); !st) return st.error();
    if (auto st = optionalNumber(rd, j, "entry_radius", 0, 1000, "m", s.entryRadius); !st) return st.error();
    if (auto f = rd.field(j, "", "patterns", false); !f) return f.error();
    else if (*f) {
        FRAY_TRY(names, rd.strings(**f, "/patterns"));
        for (std::size_t i = 0; i < names.size(); ++i) {
            const bool found = std::any_of(patches.patterns.begin(), patches.patterns.end(),
                                           [&](const PatternList& p) { return p.name == names[i]; });
            if (!found) return rd.error("/patterns/" + std::to_string(i), "no pattern '" + names[i] + "' in the patch library");
        }
        s.patterns = names;
    }
    if (auto f = rd.field(j, "", "commands", false); !f) return f.error();
    else if (*f) {
        if (!(*f)->is_array()) return rd.error("/commands", "must be an array of {time, action}");
        for (std::size_t i = 0; i < (*f)->size(); ++i) {
            const std::string p = "/commands/" + std::to_string(i);
            const json& c = (**f)[i];
            if (!c.is_object()) return rd.error(p, "must be an object {time, action}");
            FRAY_TRY(t, rd.numberAt(c, p, "time"));
            FRAY_TRY(a, rd.stringAt(c, p, "action"));
            static const char* const verbs[] = {"punch", "kick", "avoid", "attack", "defence", "block"};
            if (std::find_if(std::begin(verbs), std::end(verbs), [&](const char* v) { return a == v; }) == std::end(verbs)) {
                return rd.error(p + "/action", "unknown command '" + a + "' (punch, kick, avoid, attack, defence, block)");
            }
            if (t < 0) return rd.error(p + "/time", "must not be negative");
            if (!s.commands.empty() && t < s.commands.back().time) return rd.error(p + "/time", "commands must be in time order");
            s.commands.push_back({t, a});
        }
    }
    if (auto f = rd.field(j, "", "floor", false); !f) return f.error();
    else if (*f) {
        const json& fl = **f;
        if (!fl.is_object()) return rd.error("/floor", "must be an object {bitmap, metres_per_pixel, origin}");
        FRAY_TRY(file, rd.stringAt(fl, "/floor", "bitmap"));
        if (file.empty()) return rd.error("/floor/bitmap", "must name a PNG file");
        s.floorFile = file;
        if (auto m = rd.field(fl, "/floor", "metres_per_pixel", false); !m) return m.error();
        else if (*m) {
            FRAY_TRY(x, rd.number(**m, "/floor/metres_per_pixel"));
            if (!(x > 0.001) || x > 10) return rd.error("/floor/metres_per_pixel", "must be in (0.001, 10]");
            s.metresPerPixel = x;
        }
        if (auto o = rd.field(fl, "/floor", "origin", false); !o) return o.error();
        else if (*o) {
            if (!(*o)->is_array() || (*o)->size() != 2) return rd.error("/floor/origin", "must be [x, z]");
            FRAY_TRY(x, rd.number((**o)[0], "/floor/origin/0"));
            FRAY_TRY(z, rd.number((**o)[1], "/floor/origin/1"));
            if (std::fabs(x) > 1e4 || std::fabs(z) > 1e4) return rd.error("/floor/origin", "is too far out");
            s.floorOrigin = glm::vec2(static_cast<float>(x), static_cast<float>(z));
        }
    }
    if (auto f = rd.field(j, "", "starts", false); !f) return f.error();
    else if (*f) {
        if (!(*f)->is_array()) return rd.error("/starts", "must be an array of {time, x, z}");
        for (std::size_t i = 0; i < (*f)->size(); ++i) {
            const std::string p = "/starts/" + std::to_string(i);
            const json& st = (**f)[i];
            if (!st.is_object()) return rd.error(p, "must be an object {time, x, z}");
            FRAY_TRY(t, rd.numberAt(st, p, "time"));
            FRAY_TRY(x, rd.numberAt(st, p, "x"));
            FRAY_TRY(z, rd.numberAt(st, p, "z"));
            if (t < 0 || t > 3600) return rd.error(p + "/time", "must be in [0, 3600] seconds");
            if (std::fabs(x) > 1e4 || std::fabs(z) > 1e4) return rd.error(p, "is too far out");
            s.starts.push_back({t, glm::vec2(static_cast<float>(x), static_cast<float>(z))});
        }
    }
    if (auto st = optionalInt(rd, j, "background", 0, 10000, s.background); !st) return st.error();
    if (auto st = optionalInt(rd, j, "max_characters", 1, 100000, s.maxCharacters); !st) return st.error();
    if (auto st = optionalInt(rd, j, "porters", 2, 100, s.porters); !st) return st.error();
    if (auto st = optionalInt(rd, j, "handoffs", 1, 10000, s.handoffs); !st) return st.error();
    if (auto st = optionalInt(rd, j, "tacklers", 1, 1000, s.tacklers); !st) return st.error();
    if (auto st = optionalNumber(rd, j, "goal", 0, 1000, "m", s.goal); !st) return st.error();
    if (auto f = rd.field(j, "", "doubles", false); !f) return f.error();
    else if (*f) {
        if (!(*f)->is_boolean()) return rd.error("/doubles", "must be true or false");
        s.doubles = (*f)->get<bool>();
    }
    if (auto f = rd.field(j, "", "directions", false); !f) return f.error();
    else if (*f) {
        if (!(*f)->is_array()) return rd.error("/directions", "must be an array of {time, heading_deg}");
        for (std::size_t i = 0; i < (*f)->size(); ++i) {
            const std::string p = "/directions/" + std::to_string(i);
            const json& d = (**f)[i];
            if (!d.is_object()) return rd.error(p, "must be an object {time, heading_deg}");
            for (auto it = d.begin(); it != d.end(); ++it) {
                if (it.key() != "time" && it.key() != "heading_deg") return rd.error(p + "/" + it.key(), "unknown field");
            }
            FRAY_TRY(t, rd.numberAt(d, p, "time"));
            FRAY_TRY(h, rd.numberAt(d, p, "heading_deg"));
            if (t < 0 || t > 3600) return rd.error(p + "/time", "must be in [0, 3600] seconds");
            if (!(std::fabs(h) < 80)) {
                return rd.error(p + "/heading_deg", "must be within 80 degrees of the goal direction (0 = straight at the goal line, +Z)");
            }
            if (!s.directions.empty() && t < s.directions.back().time) return rd.error(p + "/time", "directions must be in time order");
            s.directions.push_back({t, h * std::numbers::pi / 180});
        }
    }
    if (auto f = rd.field(j, "", "rat", false); !f) return f.error();
    else if (*f) {
        const json& r = **f;
        if (!r.is_object()) return rd.error("/rat", "must be an object {path, speed, start}");
        for (auto it = r.begin(); it != r.end(); ++it) {
            if (it.key() != "path" && it.key() != "speed" && it.key() != "start") return rd.error("/rat/" + it.key(), "unknown field");
        }
        FRAY_TRY(pf, rd.field(r, "/rat", "path"));
        if (!pf->is_array()) return rd.error("/rat/path", "must be an array of [x, z] points (the rat's trajectory)");
        if (pf->size() > 10000) return rd.error("/rat/path", "has more than 10000 points");
        double length = 0;
        for (std::size_t i = 0; i < pf->size(); ++i) {
            const std::string p = "/rat/path/" + std::to_string(i);
            const json& q = (*pf)[i];
            if (!q.is_array() || q.size() != 2) return rd.error(p, "must be [x, z]");
            FRAY_TRY(x, rd.number(q[0], p + "/0"));
            FRAY_TRY(z, rd.number(q[1], p + "/1"));
            if (!(std::fabs(x) <= 1e4) || !(std::fabs(z) <= 1e4)) return rd.error(p, "is too far out");
            const glm::vec2 v(static_cast<float>(x), static_cast<float>(z));
            if (!s.ratPath.empty()) length += static_cast<double>(glm::length(v - s.ratPath.back()));
            s.ratPath.push_back(v);
        }
        if (s.ratPath.size() < 2 || length < 0.5) {
            return rd.error("/rat/path", "the rat's trajectory is empty: draw at least two points, 0.5 m apart or more");
        }
        if (auto st = optionalNumberIn(rd, r, "/rat", "speed", 0.3, 10, "m/s", s.ratSpeed, true); !st) return st.error();
        if (auto st = optionalNumberIn(rd, r, "/rat", "start", 0, 600, "s", s.ratStart, true); !st) return st.error();
    }
    if (auto st = optionalInt(rd, j, "crowd", 1, 2000, s.crowd); !st) return st.error();
    if (auto st = optionalNumber(rd, j, "band", 0, 100, "m", s.band); !st) return st.error();
    if (auto st = optionalNumber(rd, j, "spacing", 0.5, 20, "m", s.spacing); !st) return st.error();
    if (auto st = optionalNumber(rd, j, "reach", 0, 10, "m", s.reach); !st) return st.error();
    if (auto f = rd.field(j, "", "bumps", false); !f) return f.error();
    else if (*f) {
        FRAY_TRY(x, rd.number(**f, "/bumps"));
        if (!(x >= 0 && x <= 1)) return rd.error("/bumps", "must be in [0, 1] (0: people avoid bumping into each other, 1: they seek it)");
        s.bumps = x;
    }
    if (s.kind == SceneKind::Rat && s.ratPath.empty()) {
        return rd.error("/rat", "a rat scene needs the rat's trajectory: \"rat\": {\"path\": [[x, z], ...]}");
    }
    if (s.kind == SceneKind::Domino) {
        if (s.floorFile.empty()) return rd.error("/floor", "a domino scene needs a floor bitmap (the painted area where people fall)");
        if (s.starts.empty()) return rd.error("/starts", "a domino scene needs at least one start (where the first person falls)");
    }
    return s;
}

bool composeNeedsPatches(std::string_view specText) {
    const json j = json::parse(specText, nullptr, false);
    if (!j.is_object()) return true;
    const auto k = j.find("kind");
    return k == j.end() || !k->is_string() || *k != "rat";
}

Result<Scene> compose(const ActionLibrary& lib, const PatchLibrary& patches, const ComposeSpec& spec, ComposeStats* stats,
                      const ProgressFn& progress) {
    if (spec.kind != SceneKind::Rat) {
        if (patches.patches.empty()) return makeError("the patch library is empty (run patches generate first)");
        if (patches.temporal.size() != patches.patches.size()) return makeError("the patch library has no connection tables");
    }
    const auto wallStart = std::chrono::steady_clock::now();
    ComposeStats local;
    ComposeStats& st = stats ? *stats : local;
    st = {};
    Composer c(lib, patches, spec, st);
    if (c.hold < 0) return makeError("the project has no idle action (characters need one to wait)");
    if (c.locomotion.empty()) return makeError("the project has no walk, step or turn action (characters need them to move)");
    const Status done = spec.kind == SceneKind::OneVsMany  ? c.oneVsMany(progress)
                        : spec.kind == SceneKind::OneVsOne ? c.oneVsOne(progress)
                        : spec.kind == SceneKind::Domino   ? c.domino(progress)
                        : spec.kind == SceneKind::Football ? c.football(progress)
                        : spec.kind == SceneKind::Rat      ? c.rat(progress)
                                                           : c.luggage(progress);
    if (!done) return done.error();
    Scene scene = std::move(c.scene);
    scene.seed = spec.seed;
    scene.spec = spec.text;
    double end = 0;
    for (const auto& ch : scene.characters) {
        end = std::max(end, ch.track.empty() ? 0.0 : ch.track.back().end);
        if (!ch.keys.empty()) end = std::max(end, ch.keys.back().time);
    }
    scene.duration = end;
    std::sort(scene.hits.begin(), scene.hits.end(), [](const HitEvent& a, const HitEvent& b) {
        return a.time != b.time ? a.time < b.time : a.attacker < b.attacker;
    });
    scene.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count();
    st.seconds = scene.stats.seconds;
    reportProgress(progress, 1.0, "compose");
    return scene;
}

Result<std::vector<RatAvoidPatch>> ratAvoidPatches(const ActionLibrary& lib, const ComposeSpec& spec) {
    const PatchLibrary none;
    ComposeStats st;
    Composer c(lib, none, spec, st);
    if (c.hold < 0) return makeError("the project has no idle action (characters need one to wait)");
    if (!c.findWays()) return makeError(Composer::kNoWays);
    c.makeRatPatches();
    std::vector<RatAvoidPatch> out;
    for (int l = -c.ratLaterals; l <= c.ratLaterals; ++l) {
        for (int f = 0; f < Composer::kRatFacings; ++f) {
            for (const auto& p : c.ratTable[c.ratCell(l, f)]) {
                out.push_back({l * Composer::kRatLateralStep, Composer::ratFacingAt(f), c.ways[static_cast<std::size_t>(p.way)], p.lead, p.clearance});
            }
        }
    }
    return out;
}

}  // namespace fray::sim
