#include "fray/sim/spec.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>

#include <nlohmann/json.hpp>

#include "fray/prep/json_reader.h"

namespace fray::sim {

// Defined in scene.cpp.
Result<std::vector<Checkpoint>> parseCheckpoints(const prep::JsonReader& rd, const nlohmann::ordered_json& v,
                                                 const std::string& path);
Result<Arena> parseArena(const prep::JsonReader& rd, const nlohmann::ordered_json& v, const std::string& path);

namespace {

using json = nlohmann::ordered_json;
using prep::JsonReader;

constexpr const char* kPresetSection = "planner_presets";

struct WeightField {
    const char* key;
    double StyleWeights::*number;
    bool StyleWeights::*flag;
};

const WeightField kWeightFields[] = {
    {"w_theta", &StyleWeights::wTheta, nullptr},
    {"w_r", &StyleWeights::wR, nullptr},
    {"r_d", &StyleWeights::rD, nullptr},
    {"w_hit_short", &StyleWeights::wHitShort, nullptr},
    {"w_hit_long", &StyleWeights::wHitLong, nullptr},
    {"w_damage", &StyleWeights::wDamage, nullptr},
    {"w_combo", &StyleWeights::wCombo, nullptr},
    {"catches", nullptr, &StyleWeights::catches},
    {"w_psi", &StyleWeights::wPsi, nullptr},
    {"w_path", &StyleWeights::wPath, nullptr},
    {"w_req", &StyleWeights::wReq, nullptr},
    {"w_recency", &StyleWeights::wRecency, nullptr},
    {"attack_range", &StyleWeights::attackRange, nullptr},
    {"defence_range", &StyleWeights::defenceRange, nullptr},
    {"face_opponent", nullptr, &StyleWeights::faceOpponent},
    {"per_second", nullptr, &StyleWeights::perSecond},
};

const WeightField* findField(std::string_view key) {
    for (const auto& f : kWeightFields) {
        if (key == f.key) return &f;
    }
    return nullptr;
}

std::string keyList() {
    std::string s;
    for (const auto& f : kWeightFields) s += (s.empty() ? "" : ", ") + std::string(f.key);
    return s;
}

// Every numeric weight is finite and at least 0 (the costs add weighted
// terms; a negative weight would reward what the term penalises). Distances
// (r_d, attack_range, defence_range) are at most 100 m, the rest at most 1e6.
std::string weightProblem(std::string_view key, double x) {
    if (!std::isfinite(x)) return "must be a finite number";
    const bool distance = key == "r_d" || key == "attack_range" || key == "defence_range";
    const double hi = distance ? 100.0 : 1e6;
    if (x < 0 || x > hi) return distance ? "must be between 0 and 100 (metres)" : "must be between 0 and 1e6";
    return "";
}

json weightsJson(const StyleWeights& w) {
    json j;
    for (const auto& f : kWeightFields) {
        if (f.number) j[f.key] = w.*(f.number);
        else j[f.key] = w.*(f.flag);
    }
    return j;
}

Result<StyleWeights> weightsFrom(StyleWeights w, const JsonReader& rd, const json& v, const std::string& path) {
    if (!v.is_object()) return rd.error(path, "must be an object of weights");
    for (auto it = v.begin(); it != v.end(); ++it) {
        const std::string p = path + "/" + it.key();
        const auto* f = findField(it.key());
        if (!f) return rd.error(p, "unknown weight (expected one of " + keyList() + ")");
        if (f->number) {
            FRAY_TRY(x, rd.number(it.value(), p));
            if (const auto why = weightProblem(it.key(), x); !why.empty()) return rd.error(p, why);
            w.*(f->number) = x;
        } else {
            FRAY_TRY(b, rd.boolean(it.value(), p));
            w.*(f->flag) = b;
        }
    }
    return w;
}

Preset make(std::string name, std::string description, StyleWeights w) {
    return {std::move(name), std::move(description), w};
}

}  // namespace

const std::vector<std::string>& weightKeys() {
    static const std::vector<std::string> keys = [] {
        std::vector<std::string> k;
        for (const auto& f : kWeightFields) k.emplace_back(f.key);
        return k;
    }();
    return keys;
}

const std::vector<Preset>& builtinPresets() {
    static const std::vector<Preset> presets = [] {
        std::vector<Preset> out;
        StyleWeights boxer;  // general boxer: the defaults
        out.push_back(make("general-boxer", "fights at mid range with every attack", boxer));
        StyleWeights in = boxer;
        in.rD = 0.5, in.wHitShort = 1000, in.wHitLong = 10;
        out.push_back(make("infighter", "stays close and punches", in));
        StyleWeights outb = boxer;
        outb.rD = 2.0, outb.wHitShort = 10, outb.wHitLong = 1000, outb.attackRange = 1.6;
        out.push_back(make("outboxer", "keeps away and kicks", outb));
        StyleWeights chaser;
        chaser.rD = 0.1, chaser.wHitShort = 1000, chaser.wHitLong = 0, chaser.wDamage = 0, chaser.wCombo = 0;
        chaser.catches = true, chaser.perSecond = true;
        out.push_back(make("chaser", "runs the opponent down", chaser));
        StyleWeights runaway;
        runaway.rD = 3.0, runaway.wHitShort = 0, runaway.wHitLong = 0, runaway.wDamage = 1000, runaway.wCombo = 0;
        runaway.catches = true, runaway.faceOpponent = false, runaway.wTheta = 0, runaway.perSecond = true;
        out.push_back(make("runaway", "keeps its distance from the chaser", runaway));
        const std::size_t n = out.size();
        for (std::size_t i = 0; i < n; ++i) {
            Preset p = out[i];
            p.name += "-path";
            p.description += ", following its path";
            p.weights.wPath = 10;
            p.weights.wReq = 1;
            out.push_back(p);
        }
        return out;
    }();
    return presets;
}

Result<std::vector<Preset>> projectPresets(const prep::Project& project, std::string_view fileName) {
    std::vector<Preset> out = builtinPresets();
    const auto it = project.laterSections.find(kPresetSection);
    if (it == project.laterSections.end()) return out;
    const JsonReader rd(fileName);
    const json j = json::parse(it->second, nullptr, false);  // a section of a parsed (size- and depth-checked) project
    const std::string base = std::string("/") + kPresetSection;
    if (j.is_discarded() || !j.is_object()) return rd.error(base, "must be an object of presets");
    std::vector<Preset> extra;
    for (auto p = j.begin(); p != j.end(); ++p) {
        const std::string path = base + "/" + p.key();
        if (!p.value().is_object()) return rd.error(path, "must be an object");
        // Fields a stored preset lacks (written by an older Fray) keep the
        // built-in preset's value, else the defaults.
        auto found = std::find_if(out.begin(), out.end(), [&](const Preset& x) { return x.name == p.key(); });
        StyleWeights w = found != out.end() ? found->weights : StyleWeights{};
        std::string description;
        json weights = json::object();
        for (auto f = p.value().begin(); f != p.value().end(); ++f) {
            if (f.key() == "description") {
                FRAY_TRY(d, rd.string(f.value(), path + "/description"));
                description = d;
            } else {
                weights[f.key()] = f.value();
            }
        }
        FRAY_TRY(parsed, weightsFrom(w, rd, weights, path));
        if (found != out.end()) {
            found->weights = parsed;
            if (!description.empty()) found->description = description;
        } else {
            extra.push_back({p.key(), description, parsed});
        }
    }
    std::sort(extra.begin(), extra.end(), [](const Preset& a, const Preset& b) { return a.name < b.name; });
    out.insert(out.end(), extra.begin(), extra.end());
    return out;
}

std::optional<Preset> setProjectPreset(prep::Project& project, const Preset& preset) {
    json section = json::object();
    if (auto it = project.laterSections.find(kPresetSection); it != project.laterSections.end()) {
        section = json::parse(it->second, nullptr, false);
        if (section.is_discarded() || !section.is_object()) section = json::object();
    }
    std::optional<Preset> previous;
    if (auto old = projectPresets(project, "project"); old) {
        for (const auto& p : *old) {
            if (p.name == preset.name) previous = p;
        }
    }
    json entry = weightsJson(preset.weights);
    if (!preset.description.empty()) entry["description"] = preset.description;
    section[preset.name] = entry;
    project.laterSections[kPresetSection] = prep::dumpJson(section);
    return previous;
}

std::optional<Preset> removeProjectPreset(prep::Project& project, std::string_view name) {
    auto it = project.laterSections.find(kPresetSection);
    if (it == project.laterSections.end()) return std::nullopt;
    json section = json::parse(it->second, nullptr, false);
    if (section.is_discarded() || !section.is_object() || !section.contains(std::string(name))) return std::nullopt;
    std::optional<Preset> removed;
    if (auto all = projectPresets(project, "project"); all) {
        for (const auto& p : *all) {
            if (p.name == name) removed = p;
        }
    }
    section.erase(std::string(name));
    if (section.empty()) project.laterSections.erase(it);
    else it->second = prep::dumpJson(section);
    return removed;
}

std::string weightsToJson(const StyleWeights& w) { return weightsJson(w).dump(); }

Result<StyleWeights> applyWeightsJson(StyleWeights base, std::string_view text, std::string_view what) {
    const JsonReader rd(what);
    FRAY_TRY(j, prep::parseJson(text, what));
    return weightsFrom(base, rd, j, "");
}

Status applyWeightEdit(StyleWeights& w, std::string_view edit) {
    const auto eq = edit.find('=');
    if (eq == std::string_view::npos) return makeError("'" + std::string(edit) + "': expected key=value");
    const std::string key(edit.substr(0, eq));
    const std::string value(edit.substr(eq + 1));
    const auto* f = findField(key);
    if (!f) return makeError("'" + key + "': unknown weight (expected one of " + keyList() + ")");
    if (f->flag) {
        if (value != "true" && value != "false") return makeError(key + ": expected true or false, got '" + value + "'");
        w.*(f->flag) = value == "true";
        return {};
    }
    double x = 0;
    const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), x);
    if (ec != std::errc() || end != value.data() + value.size() || !std::isfinite(x)) {
        return makeError(key + ": expected a number, got '" + value + "'");
    }
    if (const auto why = weightProblem(key, x); !why.empty()) return makeError(key + ": " + why + ", got '" + value + "'");
    w.*(f->number) = x;
    return {};
}

namespace {

// The top-level fields of a simulate spec other than the characters.
Status parseSimOptions(const JsonReader& rd, const json& j, SimOptions& o) {
    if (auto v = j.find("version"); v != j.end()) {
        FRAY_TRY(version, rd.integer(*v, "/version"));
        if (version != 1) return rd.error("/version", "version " + std::to_string(version) + " is not supported (expected 1)");
    }
    FRAY_TRY(duration, rd.numberAt(j, "", "duration"));
    if (!(duration > 0) || !std::isfinite(duration)) return rd.error("/duration", "must be a positive number of seconds");
    if (duration > kMaxSceneSeconds) return rd.error("/duration", "must be at most 3600 s");
    o.duration = duration;
    if (auto v = j.find("seed"); v != j.end()) {
        if (!v->is_number_unsigned()) return rd.error("/seed", "must be a non-negative integer");
        o.seed = v->get<std::uint64_t>();
    }
    auto flag = [&](const char* key, bool& out) -> Status {
        if (auto v = j.find(key); v != j.end()) {
            auto b = rd.boolean(*v, std::string("/") + key);
            if (!b) return b.error();
            out = *b;
        }
        return {};
    };
    auto positive = [&](const char* key, double& out) -> Status {
        if (auto v = j.find(key); v != j.end()) {
            auto x = rd.number(*v, std::string("/") + key);
            if (!x) return x.error();
            if (!(*x > 0) || *x > 1e4) return rd.error(std::string("/") + key, "must be positive and at most 1e4");
            out = *x;
        }
        return {};
    };
    for (auto s : {flag("pruning", o.pruning), flag("alpha_beta", o.alphaBeta), flag("parallel", o.parallel),
                   flag("stop_on_catch", o.stopOnCatch), flag("pins_in_tree", o.pinsInTree), positive("catch_radius", o.catchRadius),
                   positive("fall_impulse", o.fallImpulse), positive("checkpoint_radius", o.checkpointRadius)}) {
        if (!s) return s.error();
    }
    if (auto v = j.find("leaf_budget"); v != j.end()) {
        // Leaves one decision may visit before it settles for a shallower depth.
        if (!v->is_number_unsigned() || v->get<std::uint64_t>() < 1000 || v->get<std::uint64_t>() > 1'000'000'000) {
            return rd.error("/leaf_budget", "must be an integer from 1000 to 1000000000 (leaves one decision may visit)");
        }
        o.leafBudget = static_cast<std::int64_t>(v->get<std::uint64_t>());
    }
    if (auto v = j.find("root_beam"); v != j.end()) {
        // Root children the last search pass keeps (0: all, the exact search).
        if (!v->is_number_unsigned() || v->get<std::uint64_t>() > 100000) {
            return rd.error("/root_beam", "must be an integer from 0 to 100000 (root children the deepest search pass keeps; 0: all)");
        }
        o.rootBeam = static_cast<int>(v->get<std::uint64_t>());
    }
    if (auto v = j.find("start_jitter"); v != j.end()) {
        if (!v->is_object()) return rd.error("/start_jitter", "must be {distance, angle_deg}");
        if (auto d = v->find("distance"); d != v->end()) {
            FRAY_TRY(x, rd.number(*d, "/start_jitter/distance"));
            if (x < 0 || x > 1e4) return rd.error("/start_jitter/distance", "must be between 0 and 1e4 (metres)");
            o.startJitter = x;
        }
        if (auto d = v->find("angle_deg"); d != v->end()) {
            FRAY_TRY(x, rd.number(*d, "/start_jitter/angle_deg"));
            if (x < 0 || x > 360) return rd.error("/start_jitter/angle_deg", "must be between 0 and 360");
            o.startJitterDegrees = x;
        }
    }
    if (auto v = j.find("arena"); v != j.end()) {
        FRAY_TRY(arena, parseArena(rd, *v, "/arena"));
        o.arena = arena;
    }
    return {};
}

// "@annotation" or an action name -> library actions (optionally within motions).
struct ActionSelector {
    const JsonReader& rd;
    const ActionLibrary& lib;

    Result<std::vector<int>> key(const std::string& key, const std::vector<std::string>& motions, const std::string& path) const {
        if (key.empty()) return rd.error(path, "must not be empty");
        if (key[0] == '@') {
            const std::string word = key.substr(1);
            if (std::find(lib.vocabulary().begin(), lib.vocabulary().end(), word) == lib.vocabulary().end()) {
                return rd.error(path, "unknown annotation '" + word + "' (not in the project's vocabulary)");
            }
        }
        std::vector<int> out;
        for (int a : lib.select(key)) {
            const auto& x = lib.actions()[static_cast<std::size_t>(a)];
            if (motions.empty() || std::find(motions.begin(), motions.end(), x.motionId) != motions.end()) out.push_back(a);
        }
        if (out.empty()) {
            return rd.error(path, key[0] == '@' ? "no action has annotation '" + key.substr(1) + "'" +
                                                      (motions.empty() ? "" : " in the selected motions")
                                                : "no action is named '" + key + "'" +
                                                      (motions.empty() ? "" : " in the selected motions"));
        }
        return out;
    }
    Result<std::vector<int>> list(const json& v, const std::vector<std::string>& motions, const std::string& path) const {
        if (!v.is_array()) return rd.error(path, "must be an array of \"@annotation\" or action names");
        std::vector<int> out;
        for (std::size_t i = 0; i < v.size(); ++i) {
            FRAY_TRY(k, rd.string(v[i], path + "/" + std::to_string(i)));
            FRAY_TRY(sel, key(k, motions, path + "/" + std::to_string(i)));
            out.insert(out.end(), sel.begin(), sel.end());
        }
        std::sort(out.begin(), out.end());
        out.erase(std::unique(out.begin(), out.end()), out.end());
        return out;
    }
};

// The actions a character may choose and the reactions hits may force on it.
Status parseCharacterActions(const ActionSelector& select, const json& c, const std::string& p,
                             const std::vector<std::string>& motions, CharacterSpec& cs) {
    const JsonReader& rd = select.rd;
    const ActionLibrary& lib = select.lib;
    auto inMotions = [&](int a) {
        return motions.empty() || std::find(motions.begin(), motions.end(),
                                            lib.actions()[static_cast<std::size_t>(a)].motionId) != motions.end();
    };
    if (auto v = c.find("actions"); v != c.end()) {
        FRAY_TRY(sel, select.list(*v, motions, p + "/actions"));
        cs.allowed = sel;
    } else {
        for (int a = 0; a < lib.size(); ++a) {
            if (inMotions(a) && !lib.actions()[static_cast<std::size_t>(a)].is(kReactive)) cs.allowed.push_back(a);
        }
    }
    std::erase_if(cs.allowed, [&](int a) { return lib.actions()[static_cast<std::size_t>(a)].is(kReactive); });
    if (cs.allowed.empty()) {
        return rd.error(p + "/actions", "character '" + cs.name + "' has no usable action (reactions like pushed/falling are "
                                        "only forced by hits)");
    }
    if (auto v = c.find("reactions"); v != c.end()) {
        FRAY_TRY(sel, select.list(*v, motions, p + "/reactions"));
        std::erase_if(sel, [&](int a) { return !lib.actions()[static_cast<std::size_t>(a)].is(kReactive); });
        cs.reactions = sel;
    } else {
        for (int a = 0; a < lib.size(); ++a) {
            if (lib.actions()[static_cast<std::size_t>(a)].is(kReactive) && inMotions(a)) cs.reactions.push_back(a);
        }
        if (cs.reactions.empty()) {
            for (int a = 0; a < lib.size(); ++a) {
                if (lib.actions()[static_cast<std::size_t>(a)].is(kReactive)) cs.reactions.push_back(a);
            }
        }
    }
    return {};
}

// Where a character starts, the path it follows and what it must or must not do.
Status parseCharacterPlacementAndPath(const ActionSelector& select, const json& c, const std::string& p,
                                      const std::vector<std::string>& motions, CharacterSpec& cs) {
    const JsonReader& rd = select.rd;
    if (auto v = c.find("start"); v != c.end()) {
        if (!v->is_object()) return rd.error(p + "/start", "must be {x, z, heading_deg}");
        double x = 0, z = 0, h = 0;
        for (auto [key, out] : {std::pair<const char*, double*>{"x", &x}, {"z", &z}, {"heading_deg", &h}}) {
            if (auto f = v->find(key); f != v->end()) {
                const double bound = std::string_view(key) == "heading_deg" ? 1e6 : kMaxCoordinate;
                FRAY_TRY(num, rd.numberIn(*f, p + "/start/" + key, -bound, bound));
                *out = num;
            }
        }
        cs.start = {{static_cast<float>(x), static_cast<float>(z)}, wrapAngle(h * std::numbers::pi / 180.0)};
    }
    if (auto v = c.find("start_action"); v != c.end()) {
        FRAY_TRY(key, rd.string(*v, p + "/start_action"));
        FRAY_TRY(sel, select.key(key, motions, p + "/start_action"));
        cs.startAction = sel.front();
    }
    if (auto v = c.find("path"); v != c.end()) {
        FRAY_TRY(path, parseCheckpoints(rd, *v, p + "/path"));
        if (path.empty()) return rd.error(p + "/path", "is empty: give at least one checkpoint {x, z}, or leave the path out");
        for (std::size_t k = 0; k < path.size(); ++k) {
            if (!path[k].action.empty()) {
                FRAY_TRY(sel, select.key(path[k].action, motions, p + "/path/" + std::to_string(k) + "/action"));
                (void)sel;
            }
        }
        cs.path = std::move(path);
    }
    if (auto v = c.find("loop_path"); v != c.end()) {
        FRAY_TRY(b, rd.boolean(*v, p + "/loop_path"));
        cs.loopPath = b;
    }
    if (auto v = c.find("require"); v != c.end()) {
        FRAY_TRY(sel, select.list(*v, {}, p + "/require"));
        cs.required = sel;
    }
    if (auto v = c.find("forbid"); v != c.end()) {
        FRAY_TRY(sel, select.list(*v, {}, p + "/forbid"));
        cs.forbidden = sel;
    }
    return {};
}

// One entry of "characters"; `opponent` gets the name of the opponent it names ("" for none).
Result<CharacterSpec> parseCharacter(const ActionSelector& select, const std::vector<Preset>& presets, const json& c,
                                     std::size_t i, const std::vector<CharacterSpec>& before, std::string& opponent) {
    const JsonReader& rd = select.rd;
    const ActionLibrary& lib = select.lib;
    static const char* const kCharKeys[] = {"name",    "side",    "group",   "preset",       "depth",
                                            "actions", "motions", "reactions", "start",      "start_action",
                                            "weights", "path",    "loop_path", "require",    "forbid",
                                            "opponent"};
    const std::string p = "/characters/" + std::to_string(i);
    if (!c.is_object()) return rd.error(p, "must be an object");
    for (auto it = c.begin(); it != c.end(); ++it) {
        if (std::find_if(std::begin(kCharKeys), std::end(kCharKeys), [&](const char* k) { return it.key() == k; }) ==
            std::end(kCharKeys)) {
            return rd.error(p + "/" + it.key(), "unknown field");
        }
    }
    CharacterSpec cs;
    FRAY_TRY(name, rd.stringAt(c, p, "name"));
    if (name.empty()) return rd.error(p + "/name", "must not be empty");
    for (const auto& other : before) {
        if (other.name == name) return rd.error(p + "/name", "'" + name + "' is used twice");
    }
    cs.name = name;
    if (auto v = c.find("side"); v != c.end()) {
        FRAY_TRY(side, rd.integer(*v, p + "/side"));
        cs.side = side;
    } else {
        cs.side = static_cast<int>(i);
    }
    if (auto v = c.find("group"); v != c.end()) {
        FRAY_TRY(group, rd.integer(*v, p + "/group"));
        cs.group = group;
    }
    std::string presetName = "general-boxer";
    if (auto v = c.find("preset"); v != c.end()) {
        FRAY_TRY(pn, rd.string(*v, p + "/preset"));
        presetName = pn;
    }
    const auto pit = std::find_if(presets.begin(), presets.end(), [&](const Preset& x) { return x.name == presetName; });
    if (pit == presets.end()) {
        std::string names;
        for (const auto& x : presets) names += (names.empty() ? "" : ", ") + x.name;
        return rd.error(p + "/preset", "unknown preset '" + presetName + "' (available: " + names + ")");
    }
    cs.preset = presetName;
    cs.weights = pit->weights;
    if (auto v = c.find("weights"); v != c.end()) {
        FRAY_TRY(w, weightsFrom(cs.weights, rd, *v, p + "/weights"));
        cs.weights = w;
    }
    if (auto v = c.find("depth"); v != c.end()) {
        FRAY_TRY(depth, rd.integer(*v, p + "/depth"));
        if (depth < 1 || depth > 8) return rd.error(p + "/depth", "must be between 1 and 8");
        cs.depth = depth;
    }
    std::vector<std::string> motions;
    if (auto v = c.find("motions"); v != c.end()) {
        FRAY_TRY(ms, rd.strings(*v, p + "/motions"));
        for (std::size_t k = 0; k < ms.size(); ++k) {
            const bool known = std::any_of(lib.actions().begin(), lib.actions().end(),
                                           [&](const LibraryAction& a) { return a.motionId == ms[k]; });
            if (!known) return rd.error(p + "/motions/" + std::to_string(k), "no motion '" + ms[k] + "' in the project");
        }
        motions = ms;
    }
    if (auto st = parseCharacterActions(select, c, p, motions, cs); !st) return st.error();
    if (auto st = parseCharacterPlacementAndPath(select, c, p, motions, cs); !st) return st.error();
    opponent.clear();
    if (auto v = c.find("opponent"); v != c.end()) {
        FRAY_TRY(name2, rd.string(*v, p + "/opponent"));
        opponent = name2;
    }
    return cs;
}

// What holds between characters: named opponents, starts inside the arena, group sizes.
Status checkCharacters(const JsonReader& rd, SceneSpec& spec, const std::vector<std::string>& opponentNames) {
    const auto& o = spec.options;
    for (std::size_t i = 0; i < spec.characters.size(); ++i) {
        if (opponentNames[i].empty()) continue;
        const std::string p = "/characters/" + std::to_string(i) + "/opponent";
        auto& cs = spec.characters[i];
        int found = -1;
        for (std::size_t k = 0; k < spec.characters.size(); ++k) {
            if (spec.characters[k].name == opponentNames[i]) found = static_cast<int>(k);
        }
        if (found < 0) return rd.error(p, "no character is named '" + opponentNames[i] + "'");
        const auto& other = spec.characters[static_cast<std::size_t>(found)];
        if (other.group != cs.group) {
            return rd.error(p, "'" + other.name + "' is in another group (characters interact within a group)");
        }
        if (other.side == cs.side) return rd.error(p, "'" + other.name + "' is on the same side");
        cs.opponent = found;
    }
    if (o.arena.bounded()) {
        for (std::size_t i = 0; i < spec.characters.size(); ++i) {
            const auto& c = spec.characters[i];
            const double d = o.arena.distanceFrom(c.start.pos);
            if (d > o.arena.radius) {
                char buf[96];
                std::snprintf(buf, sizeof buf, "starts %.2f m from the arena's centre, outside its radius of %.2f m", d,
                              o.arena.radius);
                return rd.error("/characters/" + std::to_string(i) + "/start", "'" + c.name + "' " + buf);
            }
        }
    }
    std::map<int, int> groupSizes;
    for (const auto& c : spec.characters) {
        if (++groupSizes[c.group] > kMaxGroupSize) {
            return rd.error("/characters", "group " + std::to_string(c.group) + " has more than " +
                                               std::to_string(kMaxGroupSize) + " characters");
        }
    }
    return {};
}

// "pins": [{character, time, action}] (docs/TREE_EXPANSION.md "Pins"): pinned choices
// of edited generated interactions, sorted by character, then time.
Status parsePins(const ActionSelector& select, const json& j, SceneSpec& spec) {
    const JsonReader& rd = select.rd;
    auto pf = j.find("pins");
    if (pf == j.end()) return {};
    if (!pf->is_array()) return rd.error("/pins", "must be an array of {character, time, action}");
    for (std::size_t i = 0; i < pf->size(); ++i) {
        const std::string p = "/pins/" + std::to_string(i);
        const json& jp = (*pf)[i];
        if (!jp.is_object()) return rd.error(p, "must be an object {character, time, action}");
        for (auto it = jp.begin(); it != jp.end(); ++it) {
            if (it.key() != "character" && it.key() != "time" && it.key() != "action") return rd.error(p + "/" + it.key(), "unknown field");
        }
        ActionPin pin;
        FRAY_TRY(name, rd.stringAt(jp, p, "character"));
        pin.character = -1;
        std::string names;
        for (std::size_t k = 0; k < spec.characters.size(); ++k) {
            if (spec.characters[k].name == name) pin.character = static_cast<int>(k);
            names += (k ? ", " : "") + spec.characters[k].name;
        }
        if (pin.character < 0) return rd.error(p + "/character", "no character is named '" + name + "' (the characters: " + names + ")");
        FRAY_TRY(tf, rd.field(jp, p, "time"));
        FRAY_TRY(time, rd.numberIn(*tf, p + "/time", 0, 3600));
        if (time >= spec.options.duration) {
            char buf[128];
            std::snprintf(buf, sizeof buf, "%g s is beyond the scene, which lasts %g s", time, spec.options.duration);
            return rd.error(p + "/time", buf);
        }
        pin.time = time;
        FRAY_TRY(key, rd.stringAt(jp, p, "action"));
        FRAY_TRY(selected, select.key(key, {}, p + "/action"));
        std::vector<int> named = selected;
        std::sort(named.begin(), named.end());
        const auto& allowed = spec.characters[static_cast<std::size_t>(pin.character)].allowed;
        std::set_intersection(named.begin(), named.end(), allowed.begin(), allowed.end(), std::back_inserter(pin.actions));
        if (pin.actions.empty()) {
            return rd.error(p + "/action", "'" + key + "' is not among the actions '" + name +
                                               "' may choose (its \"actions\" and \"motions\"; reactions are only forced by hits)");
        }
        pin.key = key;
        spec.pins.push_back(std::move(pin));
    }
    std::stable_sort(spec.pins.begin(), spec.pins.end(), [](const ActionPin& a, const ActionPin& b) {
        return a.character != b.character ? a.character < b.character : a.time < b.time;
    });
    return {};
}

}  // namespace

Result<SceneSpec> parseSceneSpec(std::string_view text, std::string_view fileName, const ActionLibrary& lib,
                                 const std::vector<Preset>& presets) {
    const JsonReader rd(fileName);
    FRAY_TRY(j, prep::parseJson(text, fileName));
    if (!j.is_object()) return rd.error("", "must be a JSON object");
    static const char* const kTopKeys[] = {"version",   "duration",     "seed",         "pruning",      "alpha_beta",
                                           "parallel",  "catch_radius", "stop_on_catch", "fall_impulse", "start_jitter",
                                           "checkpoint_radius", "arena", "characters", "description", "leaf_budget", "pins",
                                           "pins_in_tree", "root_beam"};
    for (auto it = j.begin(); it != j.end(); ++it) {
        if (std::find_if(std::begin(kTopKeys), std::end(kTopKeys), [&](const char* k) { return it.key() == k; }) ==
            std::end(kTopKeys)) {
            return rd.error("/" + it.key(), "unknown field");
        }
    }
    SceneSpec spec;
    spec.text = std::string(text);
    if (auto st = parseSimOptions(rd, j, spec.options); !st) return st.error();

    FRAY_TRY(cf, rd.field(j, "", "characters"));
    if (!cf->is_array() || cf->empty()) return rd.error("/characters", "must be a non-empty array");
    const ActionSelector select{rd, lib};
    std::vector<std::string> opponentNames;
    for (std::size_t i = 0; i < cf->size(); ++i) {
        std::string opponent;
        FRAY_TRY(cs, parseCharacter(select, presets, (*cf)[i], i, spec.characters, opponent));
        opponentNames.push_back(opponent);
        spec.characters.push_back(std::move(cs));
    }
    if (auto st = checkCharacters(rd, spec, opponentNames); !st) return st.error();
    if (auto st = parsePins(select, j, spec); !st) return st.error();
    return spec;
}

}  // namespace fray::sim
