#include "fray/sim/metrics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "fray/sim/segment_boxes.h"
#include "interaction.h"

namespace fray::sim {

namespace {

using json = nlohmann::ordered_json;

struct Placed {
    int action = -1;
    double tau = 0;
    RootXf root;
    RootXf pelvis;
};

Placed placedAt(const Scene& scene, const ActionLibrary& lib, int c, double t) {
    Placed p;
    const int i = scene.instanceAt(c, t);
    if (i < 0) return p;
    const auto& inst = scene.characters[static_cast<std::size_t>(c)].track[static_cast<std::size_t>(i)];
    const double tau = inst.offset + (t - inst.repeatStart(inst.repeatAt(t)));  // a looped idle: the repetition under way
    p.action = inst.action;
    p.tau = tau;
    p.root = inst.root;
    p.pelvis = inst.placementAt(lib, tau);
    return p;
}

bool penetrate(const ActionLibrary& lib, const Placed& a, const Placed& b) {
    if (a.action < 0 || b.action < 0) return false;
    return detail::coreBodiesOverlap(lib, {a.action, a.tau, a.root}, {b.action, b.tau, b.root}, 0.8f);
}

double distanceToPath(glm::vec2 p, const std::vector<Checkpoint>& path, bool loop) {
    if (path.size() == 1) return glm::length(p - path[0].pos);
    double best = 1e30;
    for (std::size_t i = 0; i + 1 < path.size(); ++i) best = std::min(best, distanceToSegment(p, path[i].pos, path[i + 1].pos));
    if (loop) best = std::min(best, distanceToSegment(p, path.back().pos, path.front().pos));
    return best;
}

}  // namespace

SceneMetrics computeMetrics(const Scene& scene, const ActionLibrary& lib, const MetricsOptions& options) {
    SceneMetrics m;
    m.duration = scene.duration;
    m.sampleRate = options.sampleRate;
    const int n = static_cast<int>(scene.characters.size());
    m.characters.resize(static_cast<std::size_t>(n));
    for (int c = 0; c < n; ++c) {
        const auto& sc = scene.characters[static_cast<std::size_t>(c)];
        auto& cm = m.characters[static_cast<std::size_t>(c)];
        cm.name = sc.name;
        cm.actions = 0;
        cm.fallbacks = sc.fallbacks;
        for (const auto& inst : sc.track) {
            cm.actions += inst.repeats();  // each time round a looped idle counts, as when it was one instance a time
            if (inst.forced) ++cm.forcedReactions;
            if (!inst.forced && lib.actions()[static_cast<std::size_t>(inst.action)].is(kAttack)) ++m.attacks;
        }
    }
    for (const auto& h : scene.hits) {
        auto& a = m.characters[static_cast<std::size_t>(h.attacker)];
        auto& d = m.characters[static_cast<std::size_t>(h.defender)];
        if (h.blocked) {
            ++a.blockedGiven, ++d.blockedReceived, ++m.blocked;
        } else {
            ++a.hitsGiven, ++d.hitsReceived, ++m.hits;
            a.damageGiven += h.speed, d.damageReceived += h.speed;
        }
    }
    m.hitRate = m.attacks > 0 ? static_cast<double>(m.hits) / m.attacks : 0.0;
    for (const auto& c : scene.catches) {
        for (int who : {c.chaser, c.runaway}) {
            auto& cm = m.characters[static_cast<std::size_t>(who)];
            if (!cm.timeToCatch) cm.timeToCatch = c.time;
        }
    }

    // Bodies, distances and paths at sampleRate.
    const int samples = static_cast<int>(std::floor(scene.duration * options.sampleRate)) + 1;
    std::vector<double> distSum(static_cast<std::size_t>(n), 0.0), pathSum(static_cast<std::size_t>(n), 0.0);
    std::vector<int> distCount(static_cast<std::size_t>(n), 0);
    std::vector<Placed> placed(static_cast<std::size_t>(n));
    // Timed checkpoints per character (index into its path), reached in order.
    std::vector<std::vector<std::size_t>> timed(static_cast<std::size_t>(n));
    std::vector<std::size_t> nextTimed(static_cast<std::size_t>(n), 0);
    for (int c = 0; c < n; ++c) {
        const auto& path = scene.characters[static_cast<std::size_t>(c)].path;
        for (std::size_t k = 0; k < path.size(); ++k) {
            if (path[k].time) timed[static_cast<std::size_t>(c)].push_back(k);
        }
        m.characters[static_cast<std::size_t>(c)].checkpointsReached.assign(timed[static_cast<std::size_t>(c)].size(), -1.0);
    }
    for (int s = 0; s < samples; ++s) {
        const double t = s / options.sampleRate;
        for (int c = 0; c < n; ++c) placed[static_cast<std::size_t>(c)] = placedAt(scene, lib, c, t);
        std::vector<std::uint8_t> penetrating(static_cast<std::size_t>(n), 0);
        bool any = false;
        for (int a = 0; a < n; ++a) {
            const auto& ca = scene.characters[static_cast<std::size_t>(a)];
            if (!scene.present(a, t)) continue;
            // Opponent distance: explicit opponent, else the nearest enemy in its group.
            double best = -1;
            for (int b = 0; b < n; ++b) {
                const auto& cb = scene.characters[static_cast<std::size_t>(b)];
                if (b == a || cb.group != ca.group || cb.side == ca.side || !scene.present(b, t)) continue;
                if (ca.opponent >= 0 && b != ca.opponent) continue;
                const double d = glm::length(placed[static_cast<std::size_t>(a)].pelvis.pos - placed[static_cast<std::size_t>(b)].pelvis.pos);
                if (best < 0 || d < best) best = d;
            }
            if (best >= 0) distSum[static_cast<std::size_t>(a)] += best, ++distCount[static_cast<std::size_t>(a)];
            if (!ca.path.empty()) {
                const double e = distanceToPath(placed[static_cast<std::size_t>(a)].pelvis.pos, ca.path, ca.loopPath);
                pathSum[static_cast<std::size_t>(a)] += e;
                auto& cm = m.characters[static_cast<std::size_t>(a)];
                cm.pathErrorMax = std::max(cm.pathErrorMax.value_or(0.0), e);
                const auto& ts = timed[static_cast<std::size_t>(a)];
                auto& next = nextTimed[static_cast<std::size_t>(a)];
                if (next < ts.size()) {
                    const auto& cp = ca.path[ts[next]];
                    if (t >= *cp.time - 1e-9 &&
                        static_cast<double>(glm::length(placed[static_cast<std::size_t>(a)].pelvis.pos - cp.pos)) <= CharacterMetrics::kCheckpointReach) {
                        cm.checkpointsReached[next++] = t;
                    }
                }
            }
            for (int b = a + 1; b < n; ++b) {
                if (!scene.present(b, t)) continue;
                if (!penetrate(lib, placed[static_cast<std::size_t>(a)], placed[static_cast<std::size_t>(b)])) continue;
                const bool intended = std::any_of(scene.hits.begin(), scene.hits.end(), [&](const HitEvent& h) {
                    const bool pair = (h.attacker == a && h.defender == b) || (h.attacker == b && h.defender == a);
                    return pair && std::fabs(h.time - t) <= options.hitWindow;
                });
                if (intended) continue;
                penetrating[static_cast<std::size_t>(a)] = penetrating[static_cast<std::size_t>(b)] = 1;
                any = true;
                if (m.penetrations.size() < SceneMetrics::kMaxListed) m.penetrations.push_back({t, a, b});
                if (scene.characters[static_cast<std::size_t>(b)].group != ca.group) ++m.crossGroupPenetrations;
            }
        }
        for (int c = 0; c < n; ++c) m.characters[static_cast<std::size_t>(c)].penetrationFrames += penetrating[static_cast<std::size_t>(c)];
        if (any) ++m.penetrationFrames;
    }
    for (int c = 0; c < n; ++c) {
        auto& cm = m.characters[static_cast<std::size_t>(c)];
        if (distCount[static_cast<std::size_t>(c)] > 0) cm.meanOpponentDistance = distSum[static_cast<std::size_t>(c)] / distCount[static_cast<std::size_t>(c)];
        if (!scene.characters[static_cast<std::size_t>(c)].path.empty()) cm.pathErrorMean = pathSum[static_cast<std::size_t>(c)] / samples;
    }

    // Foot skate on the played-back poses (transitions included).
    const ScenePoser poser(scene, lib);
    const int skateSamples = static_cast<int>(std::floor(scene.duration * options.skateRate)) + 1;
    std::vector<glm::vec3> world, prevWorld;
    for (int c = 0; c < n; ++c) {
        auto& cm = m.characters[static_cast<std::size_t>(c)];
        const auto& track = scene.characters[static_cast<std::size_t>(c)].track;
        if (track.empty()) continue;
        const auto& joints = lib.motion(lib.actions()[static_cast<std::size_t>(track.front().action)].motion).joints;
        const int feet[2] = {joints.leftFoot, joints.rightFoot};
        double sum = 0;
        int count = 0;
        std::array<bool, 2> prevContact{false, false};
        for (int s = 0; s < skateSamples; ++s) {
            const double t = s / options.skateRate;
            poser.worldPositions(c, t, world);
            const auto contact = poser.contacts(c, t);
            if (s > 0) {
                for (int f = 0; f < 2; ++f) {
                    if (!contact[static_cast<std::size_t>(f)] || !prevContact[static_cast<std::size_t>(f)] || feet[f] < 0) continue;
                    const glm::vec3 d = world[static_cast<std::size_t>(feet[f])] - prevWorld[static_cast<std::size_t>(feet[f])];
                    const double cm100 = 100.0 * static_cast<double>(std::sqrt(d.x * d.x + d.z * d.z));
                    sum += cm100;
                    ++count;
                    cm.footSkateMax = std::max(cm.footSkateMax, cm100);
                }
            }
            prevContact = contact;
            std::swap(world, prevWorld);
        }
        cm.footSkateMean = count > 0 ? sum / count : 0.0;
    }
    return m;
}

std::string metricsToJson(const SceneMetrics& m) {
    json j;
    j["duration"] = m.duration;
    j["hits"] = m.hits;
    j["blocked"] = m.blocked;
    j["attacks"] = m.attacks;
    j["hit_rate"] = m.hitRate;
    j["penetration_frames"] = m.penetrationFrames;
    j["cross_group_penetrations"] = m.crossGroupPenetrations;
    json list = json::array();
    for (const auto& p : m.penetrations) {
        list.push_back(json{{"time", p.time}, {"a", m.characters[static_cast<std::size_t>(p.a)].name},
                            {"b", m.characters[static_cast<std::size_t>(p.b)].name}});
    }
    j["penetrations"] = list;
    j["sample_rate"] = m.sampleRate;
    json chars = json::array();
    auto opt = [](const std::optional<double>& v) { return v ? json(*v) : json(nullptr); };
    for (const auto& c : m.characters) {
        chars.push_back(json{{"name", c.name},
                             {"actions", c.actions},
                             {"hits_given", c.hitsGiven},
                             {"hits_received", c.hitsReceived},
                             {"blocked_given", c.blockedGiven},
                             {"blocked_received", c.blockedReceived},
                             {"damage_given", c.damageGiven},
                             {"damage_received", c.damageReceived},
                             {"time_to_catch", opt(c.timeToCatch)},
                             {"mean_opponent_distance", opt(c.meanOpponentDistance)},
                             {"path_error_mean", opt(c.pathErrorMean)},
                             {"path_error_max", opt(c.pathErrorMax)},
                             {"penetration_frames", c.penetrationFrames},
                             {"foot_skate_mean_cm", c.footSkateMean},
                             {"foot_skate_max_cm", c.footSkateMax},
                             {"forced_reactions", c.forcedReactions},
                             {"fallbacks", c.fallbacks}});
        if (!c.checkpointsReached.empty()) {
            json reached = json::array();
            for (double t : c.checkpointsReached) reached.push_back(t >= 0 ? json(t) : json(nullptr));
            chars.back()["checkpoints_reached"] = std::move(reached);
        }
    }
    j["characters"] = std::move(chars);
    return j.dump(2) + "\n";
}

std::string metricsToText(const SceneMetrics& m) {
    std::string out;
    char line[512];
    std::snprintf(line, sizeof line, "scene: %.1f s, %d attacks, %d hits (%.0f %%), %d blocked, %d penetration samples (%d between groups)\n",
                  m.duration, m.attacks, m.hits, 100.0 * m.hitRate, m.blocked, m.penetrationFrames, m.crossGroupPenetrations);
    out += line;
    std::snprintf(line, sizeof line, "%-12s %7s %5s %5s %5s %8s %8s %8s %6s %8s %8s %6s\n", "character", "actions", "hits",
                  "recv", "block", "catch_s", "dist_m", "path_m", "pen", "skate_cm", "skatemax", "fallbk");
    out += line;
    auto f = [](const std::optional<double>& v, char* buf, std::size_t n) {
        if (v) std::snprintf(buf, n, "%.2f", *v);
        else std::snprintf(buf, n, "-");
        return buf;
    };
    for (const auto& c : m.characters) {
        char a[32], b[32], d[32];
        std::snprintf(line, sizeof line, "%-12s %7d %5d %5d %5d %8s %8s %8s %6d %8.3f %8.2f %6lld\n", c.name.c_str(), c.actions,
                      c.hitsGiven, c.hitsReceived, c.blockedReceived, f(c.timeToCatch, a, sizeof a),
                      f(c.meanOpponentDistance, b, sizeof b), f(c.pathErrorMean, d, sizeof d), c.penetrationFrames,
                      c.footSkateMean, c.footSkateMax, static_cast<long long>(c.fallbacks));
        out += line;
    }
    return out;
}

// ---- Posture metrics ---------------------------------------------------------

JointTracks kinematicTracks(const Scene& scene, const ActionLibrary& lib, double fps) {
    JointTracks tracks;
    tracks.fps = fps;
    tracks.frames = static_cast<int>(std::floor(scene.duration * fps)) + 1;
    const auto n = scene.characters.size();
    tracks.joints.resize(n);
    tracks.jointCount.assign(n, 0);
    const ScenePoser poser(scene, lib);
    std::vector<glm::vec3> world;
    for (std::size_t c = 0; c < n; ++c) {
        if (scene.isCreature(static_cast<int>(c)) || scene.characters[c].track.empty()) continue;
        const int jc = poser.skeleton(static_cast<int>(c)).jointCount();
        tracks.jointCount[c] = jc;
        auto& out = tracks.joints[c];
        out.reserve(static_cast<std::size_t>(tracks.frames) * static_cast<std::size_t>(jc));
        for (int f = 0; f < tracks.frames; ++f) {
            poser.worldPositions(static_cast<int>(c), f / fps, world);
            out.insert(out.end(), world.begin(), world.end());
        }
    }
    return tracks;
}

namespace {

// Projections of a box on a unit axis: its half length there.
float projectedRadius(const Obb& b, const glm::vec3& axis) {
    return std::fabs(glm::dot(axis, b.axes[0])) * b.half.x + std::fabs(glm::dot(axis, b.axes[1])) * b.half.y +
           std::fabs(glm::dot(axis, b.axes[2])) * b.half.z;
}

glm::vec3 closestPointInBox(const Obb& b, const glm::vec3& p) {
    const glm::vec3 d = p - b.centre;
    glm::vec3 q = b.centre;
    for (int k = 0; k < 3; ++k) q += b.axes[k] * std::clamp(glm::dot(d, b.axes[k]), -b.half[k], b.half[k]);
    return q;
}

}  // namespace

namespace {

// Depth along the axis of least overlap, and that axis pointing from a to b.
double leastOverlap(const Obb& a, const Obb& b, glm::vec3* leastAxis) {
    const glm::vec3 d = b.centre - a.centre;
    double least = 1e30;
    auto test = [&](glm::vec3 axis) {
        const float len = glm::length(axis);
        if (!(len > 1e-5f)) return true;  // parallel edges: no new axis
        axis /= len;
        const float along = glm::dot(d, axis);
        const double overlap = projectedRadius(a, axis) + projectedRadius(b, axis) - std::fabs(along);
        if (overlap <= 0) return false;
        if (overlap < least) {
            least = overlap;
            if (leastAxis) *leastAxis = along < 0 ? -axis : axis;
        }
        return true;
    };
    for (int i = 0; i < 3; ++i) {
        if (!test(a.axes[i]) || !test(b.axes[i])) return 0.0;
    }
    for (int i = 0; i < 3; ++i) {
        for (int k = 0; k < 3; ++k) {
            if (!test(glm::cross(a.axes[i], b.axes[k]))) return 0.0;
        }
    }
    return least < 1e29 ? least : 0.0;
}

}  // namespace

double boxPenetration(const Obb& a, const Obb& b) { return leastOverlap(a, b, nullptr); }

double boxSignedDistance(const Obb& a, const Obb& b, glm::vec3* normal) {
    glm::vec3 axis(0.0f, 1.0f, 0.0f);
    const double depth = leastOverlap(a, b, &axis);
    if (depth > 0) {
        if (normal) *normal = axis;
        return -depth;
    }
    // Apart: alternate projections between the two convex boxes converge to
    // a closest pair.
    glm::vec3 p = closestPointInBox(a, b.centre), q = closestPointInBox(b, p);
    for (int i = 0; i < 64; ++i) {
        const glm::vec3 p2 = closestPointInBox(a, q);
        const glm::vec3 q2 = closestPointInBox(b, p2);
        const bool settled = glm::length(p2 - p) < 1e-6f && glm::length(q2 - q) < 1e-6f;
        p = p2, q = q2;
        if (settled) break;
    }
    const float gap = glm::length(q - p);
    if (normal) *normal = gap > 1e-7f ? (q - p) / gap : glm::vec3(0.0f, 1.0f, 0.0f);
    return gap;
}

namespace {

// A blow with the body (a push, a bump, a fall onto someone): the pelvis,
// torso or head is the hit's effector.
bool bodyBlow(int effector) { return effector == kPelvis || effector == kTorso || effector == kHead; }

// The segments of the limb that strikes with `effector` (itself included).
// A body blow strikes with the whole body: whichever segment meets the
// victim first (a pushing forearm, a falling body's head or arm).
std::vector<int> strikingLimb(int effector) {
    if (bodyBlow(effector)) {
        std::vector<int> all(kSegmentCount);
        for (int s = 0; s < kSegmentCount; ++s) all[static_cast<std::size_t>(s)] = s;
        return all;
    }
    switch (effector) {
        case kLeftForearm: return {kLeftUpperArm, kLeftForearm};
        case kRightForearm: return {kRightUpperArm, kRightForearm};
        case kLeftShin: case kLeftThigh: case kLeftFoot: return {kLeftThigh, kLeftShin, kLeftFoot};
        case kRightShin: case kRightThigh: case kRightFoot: return {kRightThigh, kRightShin, kRightFoot};
        default: return {effector};
    }
}

bool handOver(const ActionLibrary& lib, const Scene& scene, int c, double t) {
    const int i = scene.instanceAt(c, t);
    if (i < 0) return false;
    const auto& a = lib.actions()[static_cast<std::size_t>(scene.characters[static_cast<std::size_t>(c)].track[static_cast<std::size_t>(i)].action)];
    return a.has("hand") || a.has("receive");
}

// Is character c in a hit, a catch or a reaction at time t (its pose may leave the capture)?
bool reacting(const Scene& scene, const ActionLibrary& lib, int c, double t, double window) {
    for (const auto& h : scene.hits) {
        if ((h.attacker == c || h.defender == c) && std::fabs(h.time - t) <= window) return true;
    }
    for (const auto& k : scene.catches) {
        if ((k.chaser == c || k.runaway == c) && t >= k.time - window) return true;
    }
    constexpr double kSettle = 0.5;  // s after a reaction ends
    for (const auto& inst : scene.characters[static_cast<std::size_t>(c)].track) {
        const bool reactive = inst.forced || lib.actions()[static_cast<std::size_t>(inst.action)].is(kReactive);
        if (reactive && t >= inst.start - 1e-9 && t <= inst.end + kSettle) return true;
    }
    return false;
}

}  // namespace

namespace {

// The balls held in the scene against their holders' hands in `shown`: the
// hand to the ball as keyed (ballGripAt). The ball shown is not measured: in
// physics it is drawn on the hand that holds it (posture's heldBalls), so it
// would be 0 by construction, and in the kinematic posture it is the ball
// as keyed.
std::vector<BallHold> ballHolds(const Scene& scene, const ActionLibrary& lib, const JointTracks& shown) {
    std::vector<BallHold> out;
    const int n = static_cast<int>(scene.characters.size());
    for (int b = 0; b < n; ++b) {
        const auto& ball = scene.characters[static_cast<std::size_t>(b)];
        const int h = ball.holder;
        if (ball.body != "ball" || ball.keys.empty() || h < 0 || h >= n || !shown.has(h) ||
            scene.characters[static_cast<std::size_t>(h)].track.empty()) {
            continue;
        }
        const auto& joints = lib.motion(lib.actions()[static_cast<std::size_t>(scene.characters[static_cast<std::size_t>(h)].track.front().action)].motion).joints;
        const int hand = ball.hand == 0 ? joints.leftHand : joints.rightHand;
        if (hand < 0) continue;
        BallHold bh;
        bh.ball = ball.name;
        bh.holder = scene.characters[static_cast<std::size_t>(h)].name;
        double sum = 0;
        for (int f = 0; f < shown.frames; ++f) {
            const double t = f / shown.fps;
            if (!scene.present(h, t)) continue;
            const glm::vec3 at = shown.at(h, f)[static_cast<std::size_t>(hand)];
            const double k = 100.0 * static_cast<double>(glm::length(at - ballGripAt(ball, t)));
            sum += k, bh.keyedMaxCm = std::max(bh.keyedMaxCm, k);
            ++bh.frames;
        }
        if (bh.frames > 0) bh.keyedMeanCm = sum / bh.frames;
        out.push_back(std::move(bh));
    }
    return out;
}

}  // namespace

PostureMetrics computePostureMetrics(const Scene& scene, const ActionLibrary& lib, const JointTracks& shown,
                                     const JointTracks& captured, const MetricsOptions& options) {
    PostureMetrics m;
    m.fps = shown.fps;
    const int n = static_cast<int>(scene.characters.size());
    m.characters.resize(static_cast<std::size_t>(n));
    const ScenePoser poser(scene, lib);
    const double fps = shown.fps;
    auto jointsOf = [&](int c) -> const StandardJoints& {
        const auto& track = scene.characters[static_cast<std::size_t>(c)].track;
        return lib.motion(lib.actions()[static_cast<std::size_t>(track.front().action)].motion).joints;
    };
    long contactSum = 0;
    double skateSum = 0, devSum = 0;
    long devCount = 0;
    for (int c = 0; c < n; ++c) {
        auto& cm = m.characters[static_cast<std::size_t>(c)];
        cm.name = scene.characters[static_cast<std::size_t>(c)].name;
        if (!shown.has(c)) continue;
        const auto& j = jointsOf(c);
        const int feet[2] = {j.leftFoot, j.rightFoot};
        // Foot skate: horizontal travel of a foot supported at both ends of a frame.
        std::array<bool, 2> prev{false, false};
        double sum = 0;
        for (int f = 0; f < shown.frames; ++f) {
            const double t = f / fps;
            const auto contact = poser.contacts(c, t);
            if (f > 0 && scene.present(c, (f - 1) / fps)) {
                for (int k = 0; k < 2; ++k) {
                    if (!contact[static_cast<std::size_t>(k)] || !prev[static_cast<std::size_t>(k)] || feet[k] < 0) continue;
                    const glm::vec3 d = shown.at(c, f)[static_cast<std::size_t>(feet[k])] - shown.at(c, f - 1)[static_cast<std::size_t>(feet[k])];
                    const double cm100 = 100.0 * std::sqrt(static_cast<double>(d.x * d.x + d.z * d.z));
                    sum += cm100;
                    ++cm.contactFrames;
                    cm.footSkateMaxCm = std::max(cm.footSkateMaxCm, cm100);
                }
            }
            prev = contact;
        }
        cm.footSkateMeanCm = cm.contactFrames > 0 ? sum / cm.contactFrames : 0.0;
        contactSum += cm.contactFrames;
        skateSum += sum;
        m.footSkateMaxCm = std::max(m.footSkateMaxCm, cm.footSkateMaxCm);

        // Joint-velocity jumps at action boundaries.
        const auto& track = scene.characters[static_cast<std::size_t>(c)].track;
        double jumpSum = 0;
        // Every seam: between instances and between a looped idle's repetitions.
        std::vector<double> seams;
        for (std::size_t i = 0; i < track.size(); ++i) {
            for (int k = i == 0 ? 1 : 0; k < track[i].repeats(); ++k) seams.push_back(track[i].repeatStart(k));
        }
        for (const double seam : seams) {
            const int f = static_cast<int>(std::lround(seam * fps));
            if (f < 1 || f + 1 >= shown.frames) continue;
            const auto a = shown.at(c, f - 1), b = shown.at(c, f), e = shown.at(c, f + 1);
            double worst = 0;
            for (std::size_t k = 0; k < b.size(); ++k) {
                const glm::vec3 dv = (e[k] - b[k]) - (b[k] - a[k]);
                worst = std::max(worst, static_cast<double>(glm::length(dv)) * fps);
            }
            jumpSum += worst;
            ++cm.boundaries;
            cm.boundaryJumpMax = std::max(cm.boundaryJumpMax, worst);
        }
        cm.boundaryJumpMean = cm.boundaries > 0 ? jumpSum / cm.boundaries : 0.0;
        m.boundaryJumpMax = std::max(m.boundaryJumpMax, cm.boundaryJumpMax);

        // Deviation from the captured pose.
        double all = 0, outside = 0;
        int allFrames = 0;
        for (int f = 0; f < shown.frames && f < captured.frames; ++f) {
            const double t = f / fps;
            if (!scene.present(c, t)) continue;
            const auto s = shown.at(c, f), r = captured.at(c, f);
            double e = 0;
            for (std::size_t k = 0; k < s.size(); ++k) e += static_cast<double>(glm::length(s[k] - r[k]));
            e = 100.0 * e / static_cast<double>(s.size());
            all += e;
            ++allFrames;
            if (reacting(scene, lib, c, t, options.hitWindow)) continue;
            outside += e;
            ++cm.deviationFrames;
        }
        cm.deviationAllMeanCm = allFrames > 0 ? all / allFrames : 0.0;
        cm.deviationMeanCm = cm.deviationFrames > 0 ? outside / cm.deviationFrames : 0.0;
        devSum += outside;
        devCount += cm.deviationFrames;
    }
    m.footSkateMeanCm = contactSum > 0 ? skateSum / static_cast<double>(contactSum) : 0.0;
    m.deviationMeanCm = devCount > 0 ? devSum / static_cast<double>(devCount) : 0.0;

    // Penetration between bodies outside intended contacts, at sampleRate.
    // A body blow's two bodies lean on each other after it, until the end of
    // the attacker's action at the blow (a faller lying on the next domino, a
    // pushed neighbour): intended until then, plus the hit window.
    std::vector<double> leanUntil(scene.hits.size(), -1.0);
    for (std::size_t i = 0; i < scene.hits.size(); ++i) {
        const auto& h = scene.hits[i];
        if (!bodyBlow(h.effector) || h.attacker < 0 || h.attacker >= n) continue;
        const int inst = scene.instanceAt(h.attacker, h.time);
        const auto& track = scene.characters[static_cast<std::size_t>(h.attacker)].track;
        if (inst >= 0 && static_cast<std::size_t>(inst) < track.size()) leanUntil[i] = track[static_cast<std::size_t>(inst)].end + options.hitWindow;
    }
    const int step = std::max(1, static_cast<int>(std::lround(fps / options.sampleRate)));
    std::vector<std::array<Obb, kSegmentCount>> boxes(static_cast<std::size_t>(n));
    std::vector<std::uint8_t> live(static_cast<std::size_t>(n));
    for (int f = 0; f < shown.frames; f += step) {
        const double t = f / fps;
        for (int c = 0; c < n; ++c) {
            live[static_cast<std::size_t>(c)] = shown.has(c) && scene.present(c, t);
            if (live[static_cast<std::size_t>(c)]) boxes[static_cast<std::size_t>(c)] = segmentBoxes(shown.at(c, f), jointsOf(c));
        }
        for (int a = 0; a < n; ++a) {
            if (!live[static_cast<std::size_t>(a)]) continue;
            for (int b = a + 1; b < n; ++b) {
                if (!live[static_cast<std::size_t>(b)]) continue;
                const auto& A = boxes[static_cast<std::size_t>(a)];
                const auto& B = boxes[static_cast<std::size_t>(b)];
                if (glm::length(A[kPelvis].centre - B[kPelvis].centre) > 2.5f) continue;
                const bool intended =
                    std::any_of(scene.hits.begin(), scene.hits.end(), [&](const HitEvent& h) {
                        const bool pair = (h.attacker == a && h.defender == b) || (h.attacker == b && h.defender == a);
                        const double until = leanUntil[static_cast<std::size_t>(&h - scene.hits.data())];
                        return pair && (std::fabs(h.time - t) <= options.hitWindow || (t >= h.time && t <= until));
                    }) ||
                    std::any_of(scene.catches.begin(), scene.catches.end(), [&](const CatchEvent& k) {
                        const bool pair = (k.chaser == a && k.runaway == b) || (k.chaser == b && k.runaway == a);
                        return pair && t >= k.time - options.hitWindow;
                    }) ||
                    (handOver(lib, scene, a, t) && handOver(lib, scene, b, t));
                if (intended) continue;
                double depth = 0;
                int segA = 0, segB = 0;
                for (int x = 0; x < kSegmentCount; ++x) {
                    for (int y = 0; y < kSegmentCount; ++y) {
                        const auto& bx = A[static_cast<std::size_t>(x)];
                        const auto& by = B[static_cast<std::size_t>(y)];
                        if (glm::length(bx.centre - by.centre) > bx.radius() + by.radius()) continue;
                        const double d = boxPenetration(bx, by);
                        if (d > depth) depth = d, segA = x, segB = y;
                    }
                }
                if (100.0 * depth > m.penetrationMaxCm) m.worstPenetration = {t, a, b, segA, segB};
                auto& ca = m.characters[static_cast<std::size_t>(a)];
                auto& cb = m.characters[static_cast<std::size_t>(b)];
                ca.penetrationMaxCm = std::max(ca.penetrationMaxCm, 100.0 * depth);
                cb.penetrationMaxCm = std::max(cb.penetrationMaxCm, 100.0 * depth);
                m.penetrationMaxCm = std::max(m.penetrationMaxCm, 100.0 * depth);
            }
        }
    }

    // The striking segment against the target at each hit.
    for (const auto& h : scene.hits) {
        const int f = std::clamp(static_cast<int>(std::lround(h.time * fps)), 0, shown.frames - 1);
        if (!shown.has(h.attacker) || !shown.has(h.defender)) continue;
        const auto A = segmentBoxes(shown.at(h.attacker, f), jointsOf(h.attacker));
        const auto B = segmentBoxes(shown.at(h.defender, f), jointsOf(h.defender));
        HitContact hc{h.time, h.attacker, h.defender, h.effector, h.target, h.blocked, 0.0, 0.0, h.target};
        // The victim's surface: the nearest of its segments (a blow may meet
        // an arm or a thigh on its way to the target); the deepest when inside.
        auto nearest = [&](int striker, int* met) {
            double best = 1e30;
            for (int s = 0; s < kSegmentCount; ++s) {
                const double d = boxSignedDistance(A[static_cast<std::size_t>(striker)], B[static_cast<std::size_t>(s)]);
                if (d < best) {
                    best = d;
                    if (met) *met = s;
                }
            }
            return best;
        };
        hc.effectorDistanceCm = 100.0 * nearest(h.effector, &hc.met);
        // The striking limb: a kick whose thigh meets the victim first lands there.
        hc.distanceCm = hc.effectorDistanceCm;
        for (int s : strikingLimb(h.effector)) {
            if (s == h.effector) continue;
            const double d = 100.0 * nearest(s, nullptr);
            // The nearest of the limb when apart; the deepest when inside.
            if (hc.distanceCm > 0 ? d < hc.distanceCm : (d < 0 && d < hc.distanceCm)) hc.distanceCm = d;
        }
        if (!h.blocked) {
            ++m.landed;
            if (hc.distanceCm <= 2.0 && hc.distanceCm >= -3.0) ++m.hitsOnSurface;
        }
        m.hits.push_back(hc);
    }
    m.balls = ballHolds(scene, lib, shown);
    return m;
}

std::string postureMetricsToJson(const PostureMetrics& m) {
    json j;
    j["fps"] = m.fps;
    j["foot_skate_max_cm"] = m.footSkateMaxCm;
    j["foot_skate_mean_cm"] = m.footSkateMeanCm;
    j["penetration_max_cm"] = m.penetrationMaxCm;
    if (m.worstPenetration.a >= 0) {
        j["worst_penetration"] = json{{"time", m.worstPenetration.time},
                                      {"a", m.characters[static_cast<std::size_t>(m.worstPenetration.a)].name},
                                      {"b", m.characters[static_cast<std::size_t>(m.worstPenetration.b)].name},
                                      {"segment_a", segmentName(m.worstPenetration.segmentA)},
                                      {"segment_b", segmentName(m.worstPenetration.segmentB)}};
    }
    j["deviation_mean_cm"] = m.deviationMeanCm;
    j["boundary_jump_max"] = m.boundaryJumpMax;
    j["hits_landed"] = m.landed;
    j["hits_on_surface"] = m.hitsOnSurface;
    json hits = json::array();
    for (const auto& h : m.hits) {
        hits.push_back(json{{"time", h.time},
                            {"attacker", m.characters[static_cast<std::size_t>(h.attacker)].name},
                            {"defender", m.characters[static_cast<std::size_t>(h.defender)].name},
                            {"effector", segmentName(h.effector)},
                            {"target", segmentName(h.target)},
                            {"met", segmentName(h.met)},
                            {"blocked", h.blocked},
                            {"distance_cm", h.distanceCm},
                            {"effector_distance_cm", h.effectorDistanceCm}});
    }
    j["hit_contacts"] = std::move(hits);
    if (!m.balls.empty()) {
        json balls = json::array();
        for (const auto& b : m.balls) {
            balls.push_back(json{{"ball", b.ball},
                                 {"holder", b.holder},
                                 {"frames", b.frames},
                                 {"hand_to_keyed_ball_mean_cm", b.keyedMeanCm},
                                 {"hand_to_keyed_ball_max_cm", b.keyedMaxCm}});
        }
        j["balls"] = std::move(balls);
    }
    json chars = json::array();
    for (const auto& c : m.characters) {
        chars.push_back(json{{"name", c.name},
                             {"contact_frames", c.contactFrames},
                             {"foot_skate_mean_cm", c.footSkateMeanCm},
                             {"foot_skate_max_cm", c.footSkateMaxCm},
                             {"penetration_max_cm", c.penetrationMaxCm},
                             {"boundaries", c.boundaries},
                             {"boundary_jump_mean", c.boundaryJumpMean},
                             {"boundary_jump_max", c.boundaryJumpMax},
                             {"deviation_frames", c.deviationFrames},
                             {"deviation_mean_cm", c.deviationMeanCm},
                             {"deviation_all_mean_cm", c.deviationAllMeanCm}});
    }
    j["characters"] = std::move(chars);
    return j.dump(2) + "\n";
}

std::string postureMetricsToText(const PostureMetrics& m) {
    std::string out;
    char line[512];
    std::snprintf(line, sizeof line,
                  "posture: skate max %.2f cm, mean %.3f cm; penetration max %.2f cm; deviation mean %.2f cm; "
                  "landed hits on the surface %d/%d; boundary jump max %.2f m/s\n",
                  m.footSkateMaxCm, m.footSkateMeanCm, m.penetrationMaxCm, m.deviationMeanCm, m.hitsOnSurface, m.landed,
                  m.boundaryJumpMax);
    out += line;
    for (const auto& b : m.balls) {
        std::snprintf(line, sizeof line,
                      "ball: %s in %s's hand: hand to the ball as keyed mean %.2f cm, max %.2f cm\n", b.ball.c_str(), b.holder.c_str(),
                      b.keyedMeanCm, b.keyedMaxCm);
        out += line;
    }
    std::snprintf(line, sizeof line, "%-12s %8s %8s %8s %8s %8s\n", "character", "skate_cm", "skatemax", "pen_cm", "dev_cm",
                  "jump_max");
    out += line;
    for (const auto& c : m.characters) {
        std::snprintf(line, sizeof line, "%-12s %8.3f %8.2f %8.2f %8.2f %8.2f\n", c.name.c_str(), c.footSkateMeanCm,
                      c.footSkateMaxCm, c.penetrationMaxCm, c.deviationMeanCm, c.boundaryJumpMax);
        out += line;
    }
    return out;
}

}  // namespace fray::sim
