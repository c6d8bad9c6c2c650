#include "fray/sim/metrics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

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
    const double tau = inst.offset + (t - inst.start);
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
        cm.actions = static_cast<int>(sc.track.size());
        cm.fallbacks = sc.fallbacks;
        for (const auto& inst : sc.track) {
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

}  // namespace fray::sim
