// Scene composition: the registry of scene kinds, the compose spec's common
// part, and what every composed scene gets (compose.h). The kinds themselves
// are in compose_<kind>.cpp, on the shared context of compose_context.h.
#include "fray/sim/compose.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <string>

#include "compose_kinds.h"

namespace fray::sim {

namespace detail {

// The registry: every scene kind, in the order their spec fields are read.
std::span<const SceneKindModule* const> sceneKinds() {
    static const std::array<const SceneKindModule*, 6> kinds = {&oneVsManyKind(), &oneVsOneKind(), &dominoKind(),
                                                                &luggageKind(),   &footballKind(),  &ratKind()};
    return kinds;
}

Status optionalInt(const prep::JsonReader& rd, const Json& obj, const char* key, int lo, int hi, int& out) {
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

Status optionalNumberIn(const prep::JsonReader& rd, const Json& obj, const std::string& parent, const char* key, double lo,
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

Status optionalNumber(const prep::JsonReader& rd, const Json& obj, const char* key, double lo, double hi, const char* unit,
                      double& out) {
    return optionalNumberIn(rd, obj, "", key, lo, hi, unit, out, false);
}

const SceneKindModule* kindNamed(std::string_view name) {
    for (const SceneKindModule* k : sceneKinds()) {
        if (name == k->name) return k;
    }
    return nullptr;
}

}  // namespace detail

namespace {

using detail::Json;
using detail::SceneKindModule;
using detail::kindNamed;

// "a, b and c": the kinds this build composes.
std::string kindList() {
    const auto kinds = detail::sceneKinds();
    std::string out;
    for (std::size_t i = 0; i < kinds.size(); ++i) {
        if (i > 0) out += i + 1 == kinds.size() ? " and " : ", ";
        out += kinds[i]->name;
    }
    return out;
}

// The fields every kind reads: the scene, the patches it may use and the user's commands.
Status parseCommon(const prep::JsonReader& rd, const Json& j, const std::vector<PatternList>& patterns, ComposeCommonSpec& s) {
    if (auto st = detail::optionalNumber(rd, j, "duration", 0, 3600, "seconds", s.duration); !st) return st.error();
    s.durationGiven = j.contains("duration");
    if (auto f = rd.field(j, "", "seed", false); !f) return f.error();
    else if (*f) {
        FRAY_TRY(d, rd.integer(**f, "/seed"));
        if (d < 0) return rd.error("/seed", "must not be negative");
        s.seed = static_cast<std::uint64_t>(d);
    }
    if (auto st = detail::optionalNumber(rd, j, "entry_radius", 0, 1000, "m", s.entryRadius); !st) return st.error();
    if (auto f = rd.field(j, "", "patterns", false); !f) return f.error();
    else if (*f) {
        FRAY_TRY(names, rd.strings(**f, "/patterns"));
        for (std::size_t i = 0; i < names.size(); ++i) {
            const bool found = std::any_of(patterns.begin(), patterns.end(),
                                           [&](const PatternList& p) { return p.name == names[i]; });
            if (!found) return rd.error("/patterns/" + std::to_string(i), "no pattern '" + names[i] + "' in the patch library");
        }
        s.patterns = names;
    }
    if (auto f = rd.field(j, "", "commands", false); !f) return f.error();
    else if (*f) {
        if (!(*f)->is_array()) return rd.error("/commands", "must be an array of {time, action, at}");
        for (std::size_t i = 0; i < (*f)->size(); ++i) {
            const std::string p = "/commands/" + std::to_string(i);
            const Json& c = (**f)[i];
            if (!c.is_object()) return rd.error(p, "must be an object {time, action, at}");
            for (auto it = c.begin(); it != c.end(); ++it) {
                if (it.key() != "time" && it.key() != "action" && it.key() != "at") return rd.error(p + "/" + it.key(), "unknown field");
            }
            FRAY_TRY(t, rd.numberAt(c, p, "time"));
            FRAY_TRY(a, rd.stringAt(c, p, "action"));
            static const char* const verbs[] = {"move", "punch", "kick", "avoid", "attack", "defence", "block"};
            if (std::find_if(std::begin(verbs), std::end(verbs), [&](const char* v) { return a == v; }) == std::end(verbs)) {
                return rd.error(p + "/action", "unknown command '" + a + "' (move, punch, kick, avoid, attack, defence, block)");
            }
            if (t < 0) return rd.error(p + "/time", "must not be negative");
            if (!s.commands.empty() && t < s.commands.back().time) return rd.error(p + "/time", "commands must be in time order");
            std::optional<glm::vec2> at;
            if (auto v = c.find("at"); v != c.end()) {
                if (!v->is_array() || v->size() != 2) return rd.error(p + "/at", "must be [x, z] (m)");
                FRAY_TRY(x, rd.numberIn((*v)[0], p + "/at/0", -1e5, 1e5));
                FRAY_TRY(z, rd.numberIn((*v)[1], p + "/at/1", -1e5, 1e5));
                at = glm::vec2(static_cast<float>(x), static_cast<float>(z));
            } else if (a == "move") {
                return rd.error(p + "/at", "a move command needs the place to move to, [x, z] (m)");
            }
            s.commands.push_back({t, a, at});
        }
    }
    return {};
}

}  // namespace

std::vector<std::string> sceneKindNames() {
    std::vector<std::string> out;
    for (const SceneKindModule* k : detail::sceneKinds()) out.emplace_back(k->name);
    return out;
}

Result<ComposeSpec> parseComposeSpec(std::string_view text, std::string_view fileName, const PatchLibrary& patches) {
    return parseComposeSpec(text, fileName, patches.patterns());
}

Result<ComposeSpec> parseComposeSpec(std::string_view text, std::string_view fileName, const std::vector<PatternList>& patterns) {
    const prep::JsonReader rd(fileName);
    const Json j = Json::parse(text, nullptr, false);
    if (j.is_discarded()) return rd.error("", "not valid JSON");
    if (!j.is_object()) return rd.error("", "must be an object");
    ComposeSpec s;
    s.text = std::string(text);
    static const char* const common[] = {"version", "kind", "duration", "seed", "entry_radius", "patterns", "commands"};
    for (auto it = j.begin(); it != j.end(); ++it) {
        const auto named = [&](const char* k) { return it.key() == k; };
        bool known = std::any_of(std::begin(common), std::end(common), named);
        for (const SceneKindModule* k : detail::sceneKinds()) known = known || std::any_of(k->fields.begin(), k->fields.end(), named);
        if (!known) return rd.error("/" + it.key(), "unknown field");
    }
    FRAY_TRY(kindName, rd.stringAt(j, "", "kind"));
    const SceneKindModule* kind = kindNamed(kindName);
    if (!kind) return rd.error("/kind", "unknown scene kind '" + kindName + "' (this build composes " + kindList() + ")");
    s.kind = kind->name;
    if (auto st = parseCommon(rd, j, patterns, s); !st) return st.error();
    for (std::size_t i = 0; i < s.commands.size(); ++i) {
        if (s.commands[i].annotation == "move" && s.kind != "one-vs-many") {
            return rd.error("/commands/" + std::to_string(i) + "/action", "move commands belong to one-vs-many scenes");
        }
    }
    for (const SceneKindModule* k : detail::sceneKinds()) {
        std::any part = k->defaults();
        if (auto st = k->parse(rd, j, part); !st) return st.error();
        if (k == kind) s.own = std::move(part);
    }
    if (auto st = kind->check(rd, s.own); !st) return st.error();
    return s;
}

bool composeNeedsPatches(std::string_view specText) {
    const Json j = Json::parse(specText, nullptr, false);
    if (!j.is_object()) return true;
    const auto k = j.find("kind");
    if (k == j.end() || !k->is_string()) return true;
    const SceneKindModule* kind = kindNamed(k->get<std::string>());
    return !kind || kind->needsPatches;
}

Result<Scene> compose(const ActionLibrary& lib, const PatchLibrary& patches, const ComposeSpec& spec, ComposeStats* stats,
                      const ProgressFn& progress) {
    const SceneKindModule* found = kindNamed(spec.kind);
    if (!found) {
        return makeError(ErrorKind::InvalidInput, spec.kind.empty() ? "the compose spec names no scene kind (this build composes " + kindList() + ")"
                                                                    : "unknown scene kind '" + spec.kind + "' (this build composes " + kindList() + ")");
    }
    const SceneKindModule& kind = *found;
    if (spec.own.has_value() && !kind.holds(spec.own)) {
        return makeError(ErrorKind::InvalidInput, "the compose spec's own part is not a " + spec.kind + " spec");
    }
    if (!spec.own.has_value()) {
        // No own part: the kind's defaults.
        ComposeSpec withDefaults = spec;
        withDefaults.own = kind.defaults();
        return compose(lib, patches, withDefaults, stats, progress);
    }
    if (kind.needsPatches) {
        if (patches.empty()) return makeError("the patch library is empty (run patches generate first)");
        if (!patches.complete()) return makeError("the patch library has no connection tables");
    }
    const auto wallStart = std::chrono::steady_clock::now();
    ComposeStats local;
    ComposeStats& st = stats ? *stats : local;
    st = {};
    auto composed = kind.compose(lib, patches, spec, st, progress);
    if (!composed) return composed.error();
    Scene scene = std::move(*composed);
    scene.seed = spec.seed;
    scene.spec = spec.text;
    double end = 0;
    for (const auto& ch : scene.characters) {
        end = std::max(end, ch.track.empty() ? 0.0 : ch.track.back().end);
        if (!ch.keys.empty()) end = std::max(end, ch.keys.back().time);
    }
    scene.duration = end;
    detail::sortHits(scene.hits);
    scene.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count();
    st.seconds = scene.stats.seconds;
    reportProgress(progress, 1.0, "compose");
    return scene;
}

}  // namespace fray::sim
