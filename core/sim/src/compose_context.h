#pragma once
// The composition context every scene kind builds on (SPEC 4.4): the scene
// being built, standard actions (idle, locomotion), placing patches and their
// hits, scoring them (density, usage, user commands), recycling through
// standard poses, greedy collision-free locomotion and the body tests.
// A scene kind derives from KindComposer (its own spec part `own` and
// stats `ownStats`) and provides run(). Internal to fray_sim.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <random>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

#include "fray/sim/compose.h"
#include "interaction.h"

namespace fray::sim::detail {

inline constexpr double kArriveDistance = 0.25;          // m: locomotion is done this close to its target
inline constexpr double kArriveHeading = 25 * std::numbers::pi / 180;
inline constexpr int kMaxLocomotionSteps = 60;
inline constexpr float kClearance = 0.2f;               // m between a new patch's newcomer and anyone present
inline constexpr double kSeamBlend = 0.15;              // s: ScenePoser's default blend at a seam between two actions (scene.h)

struct Composer {
    const ActionLibrary& lib;
    const PatchLibrary& patches;
    const ComposeCommonSpec& spec;  // each kind keeps its own part beside it (own)
    ComposeCommonStats& stats;
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
            const auto& a = lib.actions()[static_cast<std::size_t>(i)];
            if (a.is(kIdle) && a.duration > best) best = a.duration, hold = i;
            if (!a.is(kWalk | kStep | kTurn | kRun) || a.has("carry") || a.is(kReactive) || a.is(kAttack)) continue;
            reps.emplace(std::make_pair(lib.variantClass()[static_cast<std::size_t>(i)], lib.startNode()[static_cast<std::size_t>(i)]), i);
        }
        for (const auto& [key, i] : reps) locomotion.push_back(i);
        for (int i = 0; i < lib.size(); ++i) {
            if (!lib.actions()[static_cast<std::size_t>(i)].is(kIdle)) continue;
            const int node = lib.startNode()[static_cast<std::size_t>(i)];
            if (node < 0) continue;
            if (static_cast<std::size_t>(node) >= idleFrom.size()) idleFrom.resize(static_cast<std::size_t>(node) + 1, -1);
            int& longest = idleFrom[static_cast<std::size_t>(node)];
            if (longest < 0 || lib.actions()[static_cast<std::size_t>(i)].duration > lib.actions()[static_cast<std::size_t>(longest)].duration) longest = i;
        }
        usage.assign(patches.patches().size(), 0.0);
        allowed.assign(patches.patches().size(), 1);
        if (!spec.patterns.empty()) {
            for (std::size_t i = 0; i < patches.patches().size(); ++i) {
                const auto& name = patches.patterns()[static_cast<std::size_t>(patches.patches()[i].pattern)].name;
                allowed[i] = std::find(spec.patterns.begin(), spec.patterns.end(), name) != spec.patterns.end();
            }
        }
    }

    // Every kind needs an idle action and locomotion.
    Status ready() const {
        if (hold < 0) return makeError("the project has no idle action (characters need one to wait)");
        if (locomotion.empty()) return makeError("the project has no walk, step or turn action (characters need them to move)");
        return {};
    }

    const LibraryAction& act(int a) const { return lib.actions()[static_cast<std::size_t>(a)]; }

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
        if (i.looped()) return i.placementAt(lib, i.clipTimeAt(i.end));  // a looped idle: where its last time round leaves off
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
    // (The longest idle starting at each node, worked out once: idleFrom.)
    int idleAfter(int action) const {
        const int end = lib.endNode()[static_cast<std::size_t>(action)];
        if (end < 0) {  // not a node of the graph: compared as the others are
            int best = -1;
            for (int i = 0; i < lib.size(); ++i) {
                if (!act(i).is(kIdle) || lib.startNode()[static_cast<std::size_t>(i)] != end) continue;
                if (best < 0 || act(i).duration > act(best).duration) best = i;
            }
            return best >= 0 ? best : hold;
        }
        const auto node = static_cast<std::size_t>(end);
        const int best = node < idleFrom.size() ? idleFrom[node] : -1;
        return best >= 0 ? best : hold;
    }
    std::vector<int> idleFrom;  // per motion-graph node: the longest idle starting there (the first of equals), else -1

    // The instance character c plays at time t (its track must not be empty).
    const ActionInstance& playingAt(int c, double t) const {
        return scene.characters[static_cast<std::size_t>(c)].track[static_cast<std::size_t>(scene.instanceAt(c, t))];
    }

    // Floor rectangle around character c's whole body at time t.
    SweptBox bodyBox(int c, double t) const {
        const int index = scene.instanceAt(c, t);
        const auto& inst = scene.characters[static_cast<std::size_t>(c)].track[static_cast<std::size_t>(index)];
        const int sample = lib.sampleAt(inst.action, inst.clipTimeAt(t));
        InstanceBoxes* memo = nullptr;
        if (memoBodyBoxes) {
            // Per character and instance, per sample; the instance's action and
            // placement are checked (a character may be removed and another
            // take its index).
            if (static_cast<std::size_t>(c) >= bodyBoxMemo.size()) bodyBoxMemo.resize(static_cast<std::size_t>(c) + 1);
            auto& perInstance = bodyBoxMemo[static_cast<std::size_t>(c)];
            if (static_cast<std::size_t>(index) >= perInstance.size()) perInstance.resize(static_cast<std::size_t>(index) + 1);
            memo = &perInstance[static_cast<std::size_t>(index)];
            if (memo->action != inst.action || memo->root.pos != inst.root.pos || memo->root.heading != inst.root.heading) {
                memo->action = inst.action, memo->root = inst.root;
                memo->box.assign(static_cast<std::size_t>(act(inst.action).sampleCount), SweptBox{});
                memo->have.assign(static_cast<std::size_t>(act(inst.action).sampleCount), 0);
            }
            if (memo->have[static_cast<std::size_t>(sample)]) return memo->box[static_cast<std::size_t>(sample)];
        }
        const Obb* boxes = lib.boxesAt(inst.action, sample);
        SweptBox out = SweptBox::empty();
        for (int seg = 0; seg < kSegmentCount; ++seg) out.add(floorBox(boxes[seg].placed(inst.root)));
        if (memo) memo->box[static_cast<std::size_t>(sample)] = out, memo->have[static_cast<std::size_t>(sample)] = 1;
        return out;
    }
    // bodyBox remembers what it placed (a composer used by one thread at a
    // time: the memo is not locked).
    bool memoBodyBoxes = false;
    struct InstanceBoxes {
        int action = -1;
        RootXf root;
        std::vector<SweptBox> box;  // per sample of the action
        std::vector<char> have;
    };
    mutable std::vector<std::vector<InstanceBoxes>> bodyBoxMemo;  // per character, per instance
    static float rectDistance(const SweptBox& r, const glm::vec2& p) {
        const glm::vec2 d = glm::max(glm::max(r.lo - p, p - r.hi), glm::vec2(0.0f));
        return glm::length(d);
    }
    // No floor box of any body reaches farther than this from its root (m);
    // < 0: not measured, nobody is skipped (measureBodyReach sets it).
    float bodyReach = -1;
    // Bounds bodyReach over every sample of every action of the library: the
    // box's centre from the root at that sample and the next (the root at any
    // clip time between lies on the segment between them), plus 1.5 times the
    // sum of its half extents (its floor box's corner is nearer than that).
    static float measureBodyReach(const ActionLibrary& lib) {
        const std::vector<float> each = measureActionReach(lib);
        float reach = 0;
        for (float r : each) reach = std::max(reach, r);
        return reach;
    }
    // The same bound per action (bodyReach is their largest).
    static std::vector<float> measureActionReach(const ActionLibrary& lib) {
        std::vector<float> out(static_cast<std::size_t>(lib.size()), 0.0f);
        for (int a = 0; a < lib.size(); ++a) {
            float& reach = out[static_cast<std::size_t>(a)];
            const int n = lib.actions()[static_cast<std::size_t>(a)].sampleCount;
            for (int s = 0; s < n; ++s) {
                const glm::vec2 r0 = lib.rootAt(a, s / kSampleRate).pos, r1 = lib.rootAt(a, std::min(s + 1, n - 1) / kSampleRate).pos;
                const Obb* boxes = lib.boxesAt(a, s);
                for (int seg = 0; seg < kSegmentCount; ++seg) {
                    const glm::vec2 c(boxes[seg].centre.x, boxes[seg].centre.z);
                    const float h = 1.5f * (boxes[seg].half[0] + boxes[seg].half[1] + boxes[seg].half[2]);
                    reach = std::max(reach, std::max(glm::length(c - r0), glm::length(c - r1)) + h);
                }
            }
        }
        return out;
    }
    // Per action, when the caller measured them (measureActionReach): the
    // bodyReach of that action alone, so that the test below skips more.
    const std::vector<float>* actionReach = nullptr;
    // Character c's body at time t is certainly farther than `dist` from p
    // (its root beyond the reach of what it plays + dist, with a margin): its
    // boxes need not be placed.
    bool surelyFarther(int c, const glm::vec2& p, double t, float dist) const {
        if (bodyReach < 0 && !actionReach) return false;
        const auto& inst = playingAt(c, t);
        const float reach = actionReach ? (*actionReach)[static_cast<std::size_t>(inst.action)] : bodyReach;
        const glm::vec2 r = inst.placementAt(lib, inst.clipTimeAt(t)).pos;
        return glm::length(r - p) > reach + dist + 0.05f;
    }

    // Someone (other than self and partner) is closer than nearDistance to p at time t.
    bool occupied(int self, int partner, const glm::vec2& p, double t) const {
        for (int c = 0; c < static_cast<int>(scene.characters.size()); ++c) {
            if (c == self || c == partner || scene.characters[static_cast<std::size_t>(c)].track.empty()) continue;
            if (surelyFarther(c, p, t, nearDistance)) continue;
            if (rectDistance(bodyBox(c, t), p) < nearDistance) return true;
        }
        return false;
    }

    // Stepping from `from` to p at time t would come too close to someone
    // (walking away from someone already close is allowed).
    bool blocked(int self, int partner, const glm::vec2& from, const glm::vec2& p, double t) const {
        for (int c = 0; c < static_cast<int>(scene.characters.size()); ++c) {
            if (c == self || c == partner || scene.characters[static_cast<std::size_t>(c)].track.empty()) continue;
            if (surelyFarther(c, p, t, nearDistance)) continue;  // dn >= nearDistance: not blocked by c
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

    // Discs round the core boxes (shrunk by penetrates' 0.82), when the caller
    // made them for the library (CoreDiscs): penetrates' first test.
    const detail::CoreDiscs* coreDiscs = nullptr;
    static constexpr float kPenetrationShrink = 0.82f;

    // Per action: a disc round its pelvis path in the clip's frame (rootAt
    // interpolates between samples and clamps to the clip: the samples bound
    // it; a millimetre more covers the rounding).
    static std::vector<detail::CoreDiscs::Disc> pelvisPathDiscs(const ActionLibrary& lib) {
        std::vector<detail::CoreDiscs::Disc> out(static_cast<std::size_t>(lib.size()));
        for (int a = 0; a < lib.size(); ++a) {
            const int n = lib.actions()[static_cast<std::size_t>(a)].sampleCount;
            glm::vec2 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
            for (int k = 0; k < n; ++k) {
                const glm::vec2 p = lib.rootAt(a, k / kSampleRate).pos;
                lo = glm::min(lo, p), hi = glm::max(hi, p);
            }
            auto& d = out[static_cast<std::size_t>(a)];
            d.centre = n > 0 ? 0.5f * (lo + hi) : glm::vec2(0.0f);
            for (int k = 0; k < n; ++k) d.radius = std::max(d.radius, glm::length(lib.rootAt(a, k / kSampleRate).pos - d.centre));
            d.radius += 1e-3f;
        }
        return out;
    }
    // The discs above, when the caller made them for the library:
    // penetrates passes over everyone whose pelvis path stays beyond the pelvis
    // reach of the walker's for a whole action (no sample of theirs would pass
    // the pelvis test).
    const std::vector<detail::CoreDiscs::Disc>* pathDiscs = nullptr;
    detail::CoreDiscs::Disc placedPath(const ActionInstance& inst) const {
        const auto& d = (*pathDiscs)[static_cast<std::size_t>(inst.action)];
        return {inst.root.pos + FloorRotation(inst.root.heading)(d.centre), d.radius};
    }

    // Would a planned list of actions for character `self` put its body inside
    // anyone else's (the metrics' test, at every 30 Hz sample of each action
    // from its start; with sceneGrid, at the scene's 30 Hz samples within it,
    // s / 30 s, the times the metrics look at)?
    bool penetrates(const std::vector<ActionInstance>& walk, int self, bool sceneGrid = false) const {
        constexpr float kShrink = kPenetrationShrink;
        constexpr float kPelvisReach = 1.2f;  // coreBodiesOverlap's default
        std::vector<char> far;  // per character: apart from the walker for all of w (pathDiscs)
        for (const auto& w : walk) {
            if (pathDiscs && !standWhenDone) {
                const detail::CoreDiscs::Disc me = placedPath(w);
                far.assign(scene.characters.size(), 0);
                for (std::size_t c = 0; c < scene.characters.size(); ++c) {
                    const auto& tr = scene.characters[c].track;
                    if (tr.empty()) continue;
                    // The instances played at the samples of w (instanceIndexAt is monotone in t).
                    const int i0 = instanceIndexAt(tr, w.start), i1 = instanceIndexAt(tr, w.end + 1e-6);
                    bool apart = true;
                    for (int i = i0; i <= i1 && apart; ++i) {
                        const detail::CoreDiscs::Disc d = placedPath(tr[static_cast<std::size_t>(i)]);
                        const float scale = std::fabs(me.centre.x) + std::fabs(me.centre.y) + std::fabs(d.centre.x) + std::fabs(d.centre.y);
                        apart = glm::length(me.centre - d.centre) > kPelvisReach + me.radius + d.radius + 0.02f + 1e-5f * scale;
                    }
                    far[c] = apart ? 1 : 0;
                }
            }
            const FloorRotation meRotation(w.root.heading);
            auto touches = [&](double t) {
                // The walker's body placed once per sample (its boxes only if someone is near).
                const detail::CoreBody me(lib, detail::BodyPose{w.action, w.offset + (t - w.start), w.root}, meRotation, kShrink);
                const detail::CoreDiscs::Disc meDisc = coreDiscs ? coreDiscs->placed(me) : detail::CoreDiscs::Disc{};
                for (int c = 0; c < static_cast<int>(scene.characters.size()); ++c) {
                    if (c == self || (!far.empty() && far[static_cast<std::size_t>(c)])) continue;
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
                    const detail::CoreBody them(lib, other, kShrink);
                    if (coreDiscs) {
                        // The pelvis test, then the discs round the core boxes: the same answer, fewer boxes placed.
                        const glm::vec2 d = me.pelvis() - them.pelvis();
                        if (glm::dot(d, d) > kPelvisReach * kPelvisReach) continue;
                        if (detail::CoreDiscs::apart(meDisc, coreDiscs->placed(them))) continue;
                    }
                    if (detail::coreBodiesOverlap(me, them, kPelvisReach)) return true;
                }
                return false;
            };
            if (sceneGrid) {
                for (auto k = static_cast<long long>(std::ceil(w.start * kSampleRate - 1e-9)); k / kSampleRate <= w.end + 1e-9; ++k) {
                    if (touches(static_cast<double>(k) / kSampleRate)) return true;
                }
                continue;
            }
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
                const bool offGraph = last >= 0 && lib.startNode()[static_cast<std::size_t>(a)] != lib.endNode()[static_cast<std::size_t>(last)];
                // The cost is at least the distance (the facing term is never
                // negative, and adding to it rounds no lower): a step whose
                // distance alone loses is passed over without its angle.
                {
                    double floorCost = static_cast<double>(glm::length(target.pos - end.pos));
                    if (offGraph) floorCost += 0.05;
                    if (floorCost >= bestCost) continue;
                }
                double c = cost(end);
                if (offGraph) c += 0.05;
                if (c >= bestCost) continue;
                const RootXf mid = at * lib.rootAt(a, 0.5 * A.duration);
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
            if (c.time <= t && c.annotation != "move") cmd = &c;
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
        // The walk's last step blends into the patch's first action over
        // kSeamBlend; an action shorter than that is gone before the blend is
        // done, and the next one starts from its raw pose (ScenePoser), the
        // walk's pose and up to kMaxJunction of root error dropped in one
        // frame: such a patch is no place to walk into.
        if (first.end - first.start < kSeamBlend) return std::nullopt;
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
            // At the scene's samples (the times the metrics look at): the
            // walk is shifted to end on time, so its own samples fall between
            // them, and at a seam of someone else's (the main character's step
            // into its patch) the two can see different actions.
            if (penetrates(out, c, true)) continue;
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

    // The standard pose nearest to c among those some usable patch starts from.
    int nearestStartingPose(const PatchConfig& c) const {
        int best = -1;
        double bestD = std::numeric_limits<double>::max();
        for (std::size_t i = 0; i < patches.patches().size(); ++i) {
            if (!allowed[i]) continue;
            const int pose = patches.initialPose()[i];
            const double d = configDistance(c, patches.standardPoses()[static_cast<std::size_t>(pose)]);
            if (d < bestD) bestD = d, best = pose;
        }
        return best;
    }
    double freeAt0(int c) const { return track0(c).empty() ? 0.0 : freeAt(c); }
    const std::vector<ActionInstance>& track0(int c) const { return scene.characters[static_cast<std::size_t>(c)].track; }
};

// The floor rectangle a scene's characters and marks cover (their roots
// every 0.25 s of each clip, 1.5 m round them for bodies and falls).
inline SweptBox sceneExtent(const ActionLibrary& lib, const Scene& s) {
    SweptBox box = SweptBox::empty();
    for (const auto& ch : s.characters) {
        for (const auto& inst : ch.track) {
            const double last = inst.looped() ? inst.offset + inst.loop : inst.clipTimeAt(inst.end);
            for (double tau = inst.offset; tau <= last + 1e-9; tau += 0.25) {
                const glm::vec2 p = inst.placementAt(lib, tau).pos;
                box.add({p, p});
            }
            const glm::vec2 e = inst.placementAt(lib, last).pos;
            box.add({e, e});
        }
        for (const auto& k : ch.keys) box.add({k.at.pos, k.at.pos});
    }
    for (const auto& m : s.marks) {
        for (const auto& p : m.points) box.add({p, p});
    }
    box.lo -= glm::vec2(1.5f), box.hi += glm::vec2(1.5f);
    return box;
}

// Appends `part`'s characters (their names prefixed), hits and marks to
// `into`, moved by `shift`.
inline void mergeScene(Scene& into, Scene&& part, const std::string& prefix, const glm::vec2& shift) {
    const int base = static_cast<int>(into.characters.size());
    const RootXf offset{shift, 0.0};
    for (SceneCharacter& ch : part.characters) {
        ch.name = prefix + ch.name;
        for (auto& inst : ch.track) inst.root = offset * inst.root;
        for (auto& k : ch.keys) k.at = offset * k.at;
        if (ch.holder >= 0) ch.holder += base;
        into.characters.push_back(std::move(ch));
    }
    for (HitEvent h : part.hits) {
        h.attacker += base, h.defender += base;
        into.hits.push_back(h);
    }
    for (FloorMark& m : part.marks) {
        for (auto& p : m.points) p += shift;
        into.marks.push_back(std::move(m));
    }
}

// The base of a scene kind's composer: the shared context, the kind's own
// part of the spec (`own`, held in spec.own) and of the stats (`ownStats`,
// put in stats.own; the common ones for kinds with none of their own).
template <class Spec>
const Spec& ownPart(const ComposeSpec& s) {
    return std::any_cast<const Spec&>(s.own);  // compose() checked its type
}
template <class Stats>
Stats& ownStatsPart(ComposeStats& st) {
    if constexpr (std::is_same_v<Stats, ComposeCommonStats>) {
        return st;
    } else {
        return st.own.emplace<Stats>();
    }
}

template <class Spec, class Stats = ComposeCommonStats>
struct KindComposer : Composer {
    const Spec& own;
    Stats& ownStats;
    KindComposer(const ActionLibrary& l, const PatchLibrary& p, const ComposeSpec& s, ComposeStats& st)
        : Composer(l, p, s, st), own(ownPart<Spec>(s)), ownStats(ownStatsPart<Stats>(st)) {}
};

}  // namespace fray::sim::detail
