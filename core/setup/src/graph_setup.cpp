#include "fray/setup/graph_setup.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <set>

#include <nlohmann/json.hpp>

#include "fray/prep/json_reader.h"

namespace fray::setup {
namespace {

using json = nlohmann::ordered_json;

struct Reader {
    const SceneSetup& s;
    const json& j;
    Error error(const std::string& key, const std::string& problem) const {
        return makeError("setup '" + s.name + "': /" + key + ": " + problem);
    }
    const json* find(const char* key) const {
        const auto it = j.find(key);
        return it == j.end() || it->is_null() ? nullptr : &*it;
    }
    Status number(const char* key, double lo, double hi, double& out, bool openLow = false) const {
        const json* v = find(key);
        if (!v) return {};
        if (!v->is_number() || !std::isfinite(v->get<double>())) return error(key, "must be a number");
        const double x = v->get<double>();
        if (x > hi || (openLow ? !(x > lo) : x < lo)) {
            char buf[96];
            std::snprintf(buf, sizeof buf, "must be in %s%g, %g]", openLow ? "(" : "[", lo, hi);
            return error(key, buf);
        }
        out = x;
        return {};
    }
    template <class Int>
    Status integer(const char* key, std::int64_t lo, std::int64_t hi, Int& out) const {
        const json* v = find(key);
        if (!v) return {};
        if (!v->is_number_integer()) return error(key, "must be an integer from " + std::to_string(lo) + " to " + std::to_string(hi));
        const std::int64_t x = v->is_number_unsigned() && v->get<std::uint64_t>() > static_cast<std::uint64_t>(INT64_MAX)
                                   ? INT64_MAX
                                   : v->get<std::int64_t>();
        if (x < lo || x > hi) return error(key, "must be an integer from " + std::to_string(lo) + " to " + std::to_string(hi));
        out = static_cast<Int>(x);
        return {};
    }
    Status choice(const char* key, std::initializer_list<const char*> names, std::string& out) const {
        const json* v = find(key);
        if (!v) return {};
        std::string list;
        for (const char* n : names) list += std::string(list.empty() ? "" : ", ") + n;
        if (!v->is_string()) return error(key, "must be one of " + list);
        const std::string x = v->get<std::string>();
        if (std::none_of(names.begin(), names.end(), [&](const char* n) { return x == n; })) {
            return error(key, "'" + x + "' is not one of " + list);
        }
        out = x;
        return {};
    }
    Status boolean(const char* key, bool& out) const {
        const json* v = find(key);
        if (!v) return {};
        if (!v->is_boolean()) return error(key, "must be true or false");
        out = v->get<bool>();
        return {};
    }
};

}  // namespace

const Trajectory* carryTrajectory(const SceneSetup& setup) {
    for (const auto& t : setup.trajectories) {
        if (t.character == kCarryPathCharacter) return &t;
    }
    return nullptr;
}

Result<GraphSetupParams> graphParams(const SceneSetup& s, bool checkPath) {
    if (!isGraphKind(s.kind)) return makeError("setup '" + s.name + "' is a " + setupKindName(s.kind) + " setup, not an Interaction Graph one");
    const json j = json::parse(s.spec, nullptr, false);
    if (!j.is_object()) return makeError("setup '" + s.name + "': the parameters are not a JSON object");
    const Reader rd{s, j};
    GraphSetupParams p;
    p.kind = s.kind;
    // Which fields each kind reads; any other is refused by name (a typo would otherwise be ignored).
    std::set<std::string> known = {"version", "duration", "seed"};
    switch (s.kind) {
    case SetupKind::GraphDuel:
        known.insert({"style", "depth", "opponent_style", "opponent_depth", "you", "opponent", "distance", "jitter", "refine", "graph_states"});
        break;
    case SetupKind::GraphTeams:
        known.insert({"style", "depth", "opponent_style", "opponent_depth", "red", "blue", "jitter", "refine", "graph_states"});
        p.jitter = 0.2;
        p.red = 10, p.blue = 10;
        break;
    default:
        known.insert({"depth", "carry_states", "weights"});
        p.duration = 60;
        break;
    }
    for (auto it = j.begin(); it != j.end(); ++it) {
        if (!known.count(it.key())) {
            std::string list;
            for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
            return rd.error(it.key(), std::string("unknown parameter of a ") + setupKindName(s.kind) + " setup (" + list + ")");
        }
    }
    if (const json* v = rd.find("version"); v && !(v->is_number_integer() && v->get<std::int64_t>() == 1)) {
        return rd.error("version", "must be 1");
    }
    if (auto st = rd.number("duration", 0, 3600, p.duration, true); !st) return st.error();
    if (auto st = rd.integer("seed", 0, INT64_MAX, p.seed); !st) return st.error();
    if (auto st = rd.integer("depth", 1, 64, p.depth); !st) return st.error();
    if (s.kind != SetupKind::GraphCarry) {
        static const std::initializer_list<const char*> styles = {"general", "infighter", "outboxer"};
        if (auto st = rd.choice("style", styles, p.style); !st) return st.error();
        if (auto st = rd.choice("opponent_style", styles, p.opponentStyle); !st) return st.error();
        if (auto st = rd.integer("opponent_depth", 1, 64, p.opponentDepth); !st) return st.error();
        if (auto st = rd.number("jitter", 0, 2, p.jitter); !st) return st.error();
        if (auto st = rd.boolean("refine", p.refine); !st) return st.error();
        if (auto st = rd.integer("graph_states", 16, 10000000, p.graphStates); !st) return st.error();
    }
    if (s.kind == SetupKind::GraphDuel) {
        if (auto st = rd.choice("you", {"graph", "static"}, p.you); !st) return st.error();
        if (auto st = rd.choice("opponent", {"graph", "static"}, p.opponent); !st) return st.error();
        if (auto st = rd.number("distance", 0.5, 10, p.distance); !st) return st.error();
        if (!s.trajectories.empty()) return rd.error("", "a graph duel has no trajectories (its boxers fight where they start)");
    } else if (s.kind == SetupKind::GraphTeams) {
        if (auto st = rd.integer("red", 1, 5000, p.red); !st) return st.error();
        if (auto st = rd.integer("blue", 1, 5000, p.blue); !st) return st.error();
        if (!s.trajectories.empty()) return rd.error("", "a graph team fight has no trajectories");
    } else {
        if (auto st = rd.integer("carry_states", 16, 1000000, p.carryStates); !st) return st.error();
        if (const json* w = rd.find("weights")) {
            if (!w->is_object()) return rd.error("weights", "must be an object {name: value} (w_theta, w_d, w_v, speed, gamma)");
            for (auto it = w->begin(); it != w->end(); ++it) {
                const std::string key = "weights/" + it.key();
                static const char* const names[] = {"w_theta", "w_d", "w_v", "speed", "gamma"};
                if (std::none_of(std::begin(names), std::end(names), [&](const char* n) { return it.key() == n; })) {
                    return rd.error(key, "unknown reward weight (w_theta, w_d, w_v, speed, gamma)");
                }
                if (!it->is_number() || !std::isfinite(it->get<double>()) || it->get<double>() < 0) {
                    return rd.error(key, "must be a finite number >= 0");
                }
                if (it.key() == "gamma" && it->get<double>() > 1) return rd.error(key, "must be in [0, 1]");
                p.carryWeights.emplace_back(it.key(), it->get<double>());
            }
        }
        for (const auto& t : s.trajectories) {
            if (t.character != kCarryPathCharacter) {
                return makeError("setup '" + s.name + "': a carry setup's trajectory belongs to '" + kCarryPathCharacter + "' (the box), not '" +
                                 t.character + "'");
            }
        }
        const Trajectory* t = carryTrajectory(s);
        if (!t && !checkPath) return p;
        if (!t) {
            return makeError("setup '" + s.name + "': the box has no path: draw a trajectory for '" + kCarryPathCharacter +
                             "' (Polyline, Arc or Circle tool; fray-cli setup import)");
        }
        if (t->shape == TrajectoryShape::Polyline && t->points.size() < 2) {
            return makeError("setup '" + s.name + "': the box's path needs at least 2 points");
        }
        if (auto line = sampleTrajectory(*t); !line) return makeError("setup '" + s.name + "': " + line.error().message);
    }
    return p;
}

}  // namespace fray::setup
