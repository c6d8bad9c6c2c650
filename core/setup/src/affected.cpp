#include "fray/setup/affected.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <nlohmann/json.hpp>

namespace fray::setup {
namespace {

double boxDistance(glm::vec2 p, const Point& lo, const Point& hi) {
    const double px = static_cast<double>(p.x), pz = static_cast<double>(p.y);
    const double dx = std::max({lo.x - px, 0.0, px - hi.x});
    const double dz = std::max({lo.z - pz, 0.0, pz - hi.z});
    return std::hypot(dx, dz);
}

glm::vec2 positionAt(const sim::Scene& scene, const sim::ActionLibrary& lib, int c, double t) {
    const auto& ch = scene.characters[static_cast<std::size_t>(c)];
    if (scene.isCreature(c)) return sim::creatureAt(ch, t).pos;
    const int i = scene.instanceAt(c, t);
    if (i < 0) return glm::vec2(0.0f);
    const auto& inst = ch.track[static_cast<std::size_t>(i)];
    return inst.placementAt(lib, inst.clipTimeAt(t)).pos;
}

// Planned scenes (tree expansion) have spec "characters"; composed ones a "kind".
bool planned(const sim::Scene& scene) {
    const auto j = nlohmann::ordered_json::parse(scene.spec, nullptr, false);
    return j.is_object() && j.contains("characters") && !j.contains("kind");
}


}  // namespace

std::vector<int> affectedCharacters(const sim::Scene& previous, const sim::ActionLibrary& lib, const SetupEdit& edit) {
    const int n = static_cast<int>(previous.characters.size());
    std::vector<char> hit(static_cast<std::size_t>(n), 0);
    double from = edit.time;
    auto byName = [&](const std::string& name) {
        for (int c = 0; c < n; ++c) {
            if (previous.characters[static_cast<std::size_t>(c)].name == name) return c;
        }
        return -1;
    };
    switch (edit.kind) {
    case SetupEdit::Kind::Other: std::fill(hit.begin(), hit.end(), 1); break;
    case SetupEdit::Kind::Start:
        from = 0;
        if (edit.side >= 0) {
            bool any = false;
            for (int c = 0; c < n; ++c) {
                if (previous.characters[static_cast<std::size_t>(c)].side == edit.side) hit[static_cast<std::size_t>(c)] = 1, any = true;
            }
            if (!any) std::fill(hit.begin(), hit.end(), 1);
        } else if (const int c = byName(edit.character); c >= 0) {
            hit[static_cast<std::size_t>(c)] = 1;
        } else {
            std::fill(hit.begin(), hit.end(), 1);  // a newcomer, or a name the scene lacks: plan everyone
        }
        break;
    case SetupEdit::Kind::Checkpoint:
        if (const int c = byName(edit.character); c >= 0) hit[static_cast<std::size_t>(c)] = 1;
        else std::fill(hit.begin(), hit.end(), 1);
        break;
    case SetupEdit::Kind::Stroke: {
        const Point lo{std::min(edit.lo.x, edit.hi.x), std::min(edit.lo.z, edit.hi.z)};
        const Point hi{std::max(edit.lo.x, edit.hi.x), std::max(edit.lo.z, edit.hi.z)};
        // A domino bystander stands at least as far from the painted area as
        // a fall reaches, and its spot depends on the painting that near only
        // (compose_domino.cpp). That distance is at most the nearest
        // bystander's distance to the painted area: a stroke within it of a
        // bystander may take its spot (or its cell's), one further away cannot.
        const bool domino = !previous.floor.empty();  // only a domino scene keeps its painted floor
        std::vector<char> inHit(static_cast<std::size_t>(n), 0);  // hits or is hit: not a bystander
        for (const auto& h : previous.hits) {
            if (h.attacker >= 0 && h.attacker < n) inHit[static_cast<std::size_t>(h.attacker)] = 1;
            if (h.defender >= 0 && h.defender < n) inHit[static_cast<std::size_t>(h.defender)] = 1;
        }
        auto stands = [&](int c) { return !inHit[static_cast<std::size_t>(c)]; };
        auto toPainted = [&](glm::vec2 p) {  // to 1 cm, up to 100 m
            double a = 0, b = 100;
            if (!previous.floor.paintedWithin(p, b)) return b;
            while (b - a > 0.01) {
                const double m = 0.5 * (a + b);
                (previous.floor.paintedWithin(p, m) ? b : a) = m;
            }
            return a;
        };
        double clearance = std::numeric_limits<double>::max();
        if (domino) {
            for (int c = 0; c < n; ++c) {
                if (!previous.characters[static_cast<std::size_t>(c)].track.empty() && stands(c))
                    clearance = std::min(clearance, toPainted(positionAt(previous, lib, c, previous.characters[static_cast<std::size_t>(c)].track.front().start)));
            }
        }
        for (int c = 0; c < n; ++c) {
            const auto& ch = previous.characters[static_cast<std::size_t>(c)];
            if (ch.track.empty() && !previous.isCreature(c)) continue;
            if (domino && !ch.track.empty() && stands(c)) {
                const double toStroke = boxDistance(positionAt(previous, lib, c, ch.track.front().start), lo, hi);
                if (toStroke <= std::max(kAffectReach, clearance)) hit[static_cast<std::size_t>(c)] = 1;
                continue;
            }
            // Sampled every 0.25 s from the stroke's start time (or the character's entry) on.
            const double t0 = std::max(from, ch.track.empty() ? 0.0 : ch.track.front().start);
            for (double t = t0; t <= previous.duration + 1e-9; t += 0.25) {
                if (boxDistance(positionAt(previous, lib, c, t), lo, hi) <= kAffectReach) {
                    hit[static_cast<std::size_t>(c)] = 1;
                    break;
                }
            }
        }
        break;
    }
    }
    // Close over interactions after the edit's time, and over planning groups.
    const bool groups = planned(previous);
    for (bool grew = true; grew;) {
        grew = false;
        auto join = [&](int a, int b) {
            if (a < 0 || b < 0 || a >= n || b >= n) return;
            auto& x = hit[static_cast<std::size_t>(a)];
            auto& y = hit[static_cast<std::size_t>(b)];
            if (x != y) x = y = 1, grew = true;
        };
        for (const auto& h : previous.hits) {
            if (h.time >= from - 1e-9) join(h.attacker, h.defender);
        }
        for (const auto& c : previous.catches) {
            if (c.time >= from - 1e-9) join(c.chaser, c.runaway);
        }
        if (groups) {
            for (int a = 0; a < n; ++a) {
                for (int b = a + 1; b < n; ++b) {
                    if (previous.characters[static_cast<std::size_t>(a)].group == previous.characters[static_cast<std::size_t>(b)].group) join(a, b);
                }
            }
        }
    }
    std::vector<int> out;
    for (int c = 0; c < n; ++c) {
        if (hit[static_cast<std::size_t>(c)]) out.push_back(c);
    }
    return out;
}

}  // namespace fray::setup
